"""The paper's figures as PNG files: what ``axisflow figures`` and the demo write.

=============  ==================================================================================
file           figure
=============  ==================================================================================
fig2.png       Fig. 2, identification: measured against model motor torque over an excitation
               log, with the residual (refit by :func:`axisflow.identification.refit.identify`;
               only when an excitation log is given)
fig4a.png      Fig. 4a, energy of a poly5 move over distance and execution time, with the
               minimum-time limit and the time-energy optimum (:mod:`.energy_map_figure`)
fig4b.png      Fig. 4b, IPOPT's optimal time and solve time against its iteration cap, with the
               exact optimum (:mod:`.iteration_cap_figure`)
fig5a.png      Fig. 5a / 5b, position, velocity and motor torque through the way points per law,
fig5b.png      minimum time / minimum time-energy (:mod:`.trajectory_figure`; planned and sampled
               with the model, or measured from a recording of the planner's runs)
=============  ==================================================================================

Everything is drawn first and written after, all files together and atomically
(:func:`~axisflow.model.files.write_atomic_files`): a failure or a signal writes none of them.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from ..identification.refit import IdentifySettings, identify
from ..identification.signals import recorded_drive
from ..model import AxisParams
from ..model.files import check_output_dir, ensure_dir, write_atomic_files
from ..planner import Case
from .energy_map_figure import energy_map, energy_map_png
from .identification_figure import identification_png
from .iteration_cap_figure import cap_study, iteration_cap_png
from .trajectory_figure import CASE_TITLES, planned_traces, recorded_traces, trajectory_png

FIGURE_FILES = ("fig2.png", "fig4a.png", "fig4b.png", "fig5a.png", "fig5b.png")


@dataclass
class Figures:
    """Rendered figures: PNG bytes by file name, the reason for each figure left out, and the time
    each took [s]."""

    pngs: dict[str, bytes] = field(default_factory=dict)
    skipped: dict[str, str] = field(default_factory=dict)
    seconds: dict[str, float] = field(default_factory=dict)


def render_figures(
    params: AxisParams,
    waypoints: Sequence[float],
    excitation: str | Path | None = None,
    recording: str | Path | None = None,
    progress: Callable[[str], None] | None = None,
) -> Figures:
    """Draw every figure (see the module docstring). ``waypoints`` [m] are Fig. 5's (the paper: 25
    random ones; ``axisflow figures`` draws them with seed 0); ``recording`` makes Fig. 5 show the
    measured samples of a recording of the planner's runs instead of the plans."""
    say = progress or (lambda _text: None)
    figures = Figures()

    def timed(name: str, draw: Callable[[], bytes]) -> None:
        t0 = time.perf_counter()
        figures.pngs[name] = draw()
        figures.seconds[name] = time.perf_counter() - t0
        say(f"{name}: {figures.seconds[name]:.1f} s")

    if excitation is None:
        figures.skipped["fig2.png"] = "Fig. 2 needs an excitation log (--excitation LOG.mcap)"
        say("fig2.png: skipped, no excitation log")
    else:
        timed("fig2.png", lambda: _fig2(excitation, params))
    timed("fig4a.png", lambda: energy_map_png(energy_map(params), params))
    timed("fig4b.png", lambda: iteration_cap_png([cap_study(params, case) for case in Case]))
    for name, case in (("fig5a.png", Case.MIN_TIME), ("fig5b.png", Case.MIN_TIME_ENERGY)):
        timed(name, lambda case=case: _fig5(params, waypoints, case, recording))
    return figures


def _fig2(excitation: str | Path, params: AxisParams) -> bytes:
    settings = IdentifySettings()
    ident = identify([excitation], params, settings)
    drive = recorded_drive(excitation, settings.topic)
    return identification_png(
        ident.traces(),
        f"Fig. 2 — identification on {Path(excitation).name}"
        + (f" ({drive})" if drive else "")
        + ": measured motor torque against eq. (1), refit and nominal parameters",
    )


def _fig5(params: AxisParams, waypoints: Sequence[float], case: Case, recording: str | Path | None) -> bytes:
    if recording is None:
        traces = planned_traces(params, waypoints, case)
        caption = (
            f"The exact planner's moves through {len(waypoints)} way points, sampled at the drive's 1 kHz "
            "ticks with the model: torque by eq. (1), the parameters given (not measured)."
        )
    else:
        traces = recorded_traces(recording, case)
        drive = recorded_drive(recording, IdentifySettings().topic)
        caption = (
            f"Measured on the axis (state samples, 1 kHz): recording {Path(recording).name}"
            + (f", {drive}" if drive else "")
            + "."
        )
    return trajectory_png(traces, params, CASE_TITLES[case], caption)


def save_figures(figures: Figures, out_dir: str | Path) -> list[Path]:
    """Write the rendered PNGs into ``out_dir`` (created if missing), together and atomically."""
    return write_atomic_files(ensure_dir(check_output_dir(out_dir)), figures.pngs)


def write_figures(
    out_dir: str | Path,
    params: AxisParams,
    waypoints: Sequence[float],
    excitation: str | Path | None = None,
    recording: str | Path | None = None,
) -> list[Path]:
    """Draw the figures and write them into ``out_dir`` (what the demo calls); returns the files
    written (Fig. 2 only with ``excitation``)."""
    check_output_dir(out_dir)
    return save_figures(render_figures(params, waypoints, excitation, recording), out_dir)
