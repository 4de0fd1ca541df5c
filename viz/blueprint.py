"""The layout of the view, declared once: one column per axis, the plots of the paper's Fig. 5 and
more, stacked and sharing one time axis.

Per axis, top to bottom: position with the stroke and the way points; velocity with ±v_max; motor
torque, measured against the feed-forward, with ±tau_max; tracking error; mechanical power; energy per
move (measured and planned); the bridge's move statuses. Several axes stand side by side.
"""

from __future__ import annotations

from collections.abc import Sequence

import rerun.blueprint as rrb

from .entities import TIMELINE, AxisEntities

PLOTS: tuple[tuple[str, str], ...] = (
    ("position", "position [m]"),
    ("velocity", "velocity [m/s]"),
    ("torque", "motor torque [N·m]"),
    ("tracking_error", "tracking error, setpoint − measured [m]"),
    ("power", "mechanical power τ_m·ω_m [W]"),
    ("energy", "energy per move [J]"),
)
"""(plot subtree, title with unit) of each time-series view, top to bottom"""
_ROW_SHARES = (3, 2, 2, 1.5, 1.5, 1.5, 1.5)


def axis_column(label: str) -> rrb.Vertical:
    """The views of one axis, stacked."""
    entities = AxisEntities(label)
    shared_time = rrb.TimeAxis(link=rrb.components.LinkAxis.LinkToGlobal)
    views: list[rrb.View] = [
        rrb.TimeSeriesView(
            origin=entities.plot(plot),
            name=f"{label}: {title}",
            axis_x=shared_time,
            plot_legend=rrb.PlotLegend(rrb.components.Corner2D.RightTop),
        )
        for plot, title in PLOTS
    ]
    views.append(rrb.TextLogView(origin=entities.events, name=f"{label}: move status"))
    return rrb.Vertical(*views, row_shares=list(_ROW_SHARES), name=label)


def view_blueprint(labels: Sequence[str]) -> rrb.Blueprint:
    """The whole layout for the axes ``labels`` (in this order, left to right)."""
    columns = [axis_column(label) for label in labels]
    body = rrb.Horizontal(*columns) if len(columns) != 1 else columns[0]
    return rrb.Blueprint(
        body,
        rrb.TimePanel(timeline=TIMELINE, expanded=True),
        collapse_panels=False,
    )
