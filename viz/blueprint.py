"""The layout of the view, declared once: one column per axis, the plots of the paper's Fig. 5 and
more, stacked and sharing one time axis.

Per axis, top to bottom: position with the stroke and the way points; velocity with ±v_max; motor
torque, measured against the feed-forward, with ±tau_max; tracking error; mechanical power; energy per
move (measured and planned) and each move's E%; for an axis with an adaptive node, its parameters over
time (σ band) and the friction curve now against version 0; the bridge's move statuses. Several axes
stand side by side.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence

import rerun.blueprint as rrb

from .entities import TIMELINE, AxisEntities

PLOTS: tuple[tuple[str, str], ...] = (
    ("position", "position [m]"),
    ("velocity", "velocity [m/s]"),
    ("torque", "motor torque [N·m]"),
    ("tracking_error", "tracking error, setpoint − measured [m]"),
    ("power", "mechanical power τ_m·ω_m [W]"),
    ("energy", "energy per move [J]"),
    ("energy_error", "E% per move, (E_th − E_exp)/E_th [%]"),
)
"""(plot subtree, title with unit) of each time-series view, top to bottom"""
_ROW_SHARES = (3, 2, 2, 1.5, 1.5, 1.5, 1.5, 1.5)
_ADAPTED_SHARES = (2, 2)
"""the adapted parameters' plot and the friction curve, before the statuses"""


def axis_column(label: str, adapted: bool = False) -> rrb.Vertical:
    """The views of one axis, stacked (``adapted``: with the views of its adaptive node)."""
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
    shares = list(_ROW_SHARES)
    if adapted:
        views.append(
            rrb.TimeSeriesView(
                origin=f"{entities.root}/params",
                name=f"{label}: adapted parameters [% of version 0], ±σ",
                axis_x=shared_time,
                plot_legend=rrb.PlotLegend(rrb.components.Corner2D.RightTop),
            )
        )
        views.append(
            rrb.Spatial2DView(origin=entities.friction, name=f"{label}: friction F_c [N] over ẋ [m/s]")
        )
        shares[-1:-1] = _ADAPTED_SHARES
    views.append(rrb.TextLogView(origin=entities.events, name=f"{label}: move status"))
    return rrb.Vertical(*views, row_shares=shares, name=label)


def view_blueprint(labels: Sequence[str], adapted: Collection[str] = ()) -> rrb.Blueprint:
    """The whole layout for the axes ``labels`` (in this order, left to right); those in ``adapted``
    with the views of their adaptive node."""
    columns = [axis_column(label, label in adapted) for label in labels]
    body = rrb.Horizontal(*columns) if len(columns) != 1 else columns[0]
    return rrb.Blueprint(
        body,
        rrb.TimePanel(timeline=TIMELINE, expanded=True),
        collapse_panels=False,
    )
