"""``axisflow demo --axes N``: the demo on a cell of N axes (:mod:`axisflow.deploy.cell`).

:func:`run_cell_demo` starts N bridges, one recorder, a planner per axis; axis ``aK`` runs the paper's
experiment (both cases, all three laws, the nominal parameters) over its own random way points — seed
+ K, so that the axes move differently, as a cell's axes do — then Table 2 of each axis is measured from
the one recording.
"""

from __future__ import annotations

import json
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from ..acquisition.wire.keys import AxisKeys, topic_for_key
from ..deploy.cell import Cell, CellError, CellLayout
from ..deploy.processes import last_line
from ..experiment.table2 import table_from_recording
from ..experiment.table2_markdown import write_table2
from ..experiment.table2_record import Table2
from ..model import load_params
from ..model.files import write_atomic
from .settings import DemoSettings

PROGRESS_PERIOD_S = 10.0
"""how often the demo says where each axis's planner is [s]"""
RECORDING = "cell.mcap"
"""the demo's one recording, in its session folder"""
LABEL = "nominal"
"""the plan label of the demo's runs (the nominal parameters)"""


@dataclass(frozen=True)
class AxisRecording:
    """How completely the recording holds one axis's samples."""

    ticks: int
    """samples the bridge published (its ticks, less the ticks its drive measured nothing)"""
    recorded: int
    missed: int
    """gaps in the sequence numbers, as the recorder counted them"""


@dataclass
class CellDemoReport:
    out: Path
    axes: tuple[str, ...]
    tables: dict[str, Table2] = field(default_factory=dict)
    recording: dict[str, AxisRecording] = field(default_factory=dict)
    wall_time_s: float = 0.0
    phases_s: dict[str, float] = field(default_factory=dict)


def run_cell_demo(
    settings: DemoSettings, axes: int, progress: Callable[[str], None], stop: threading.Event | None = None
) -> CellDemoReport:
    """``axisflow demo --axes N`` (see the module docstring) into ``settings.out``."""
    stop = stop or threading.Event()
    layout = CellLayout.on_loopback(axes, settings.speed, _bridge_options(settings))  # checked first
    out = settings.out
    out.mkdir(parents=True, exist_ok=True)
    report = CellDemoReport(out, layout.axes)
    t_start = time.monotonic()
    progress(
        f"session folder {out}; a cell of {axes} axes ({', '.join(layout.axes)}), each bridge a client of "
        f"the router on {layout.endpoint}, bridges at --speed {settings.speed:g}"
    )
    with Cell(layout, out / "logs") as cell:
        t0 = time.monotonic()
        cell.start_router()
        cell.start_recorder(out / RECORDING)
        cell.start_bridges()
        report.phases_s["start"] = time.monotonic() - t0
        t0 = time.monotonic()
        _run_planners(cell, settings, progress, stop)
        report.phases_s["experiment"] = time.monotonic() - t0
        bridges = cell.stop_bridges()
        recorded = cell.stop_recorder()
        cell.stop_router()
    report.recording = _recording_counts(layout, bridges, recorded)
    t0 = time.monotonic()
    for axis in layout.axes:
        report.tables[axis] = _table(out, layout, axis)
    report.phases_s["tables"] = time.monotonic() - t0
    _pictures(out, settings, report, progress)
    report.wall_time_s = time.monotonic() - t_start
    write_atomic(out / "demo.json", json.dumps(_summary_json(report, settings), indent=1) + "\n")
    return report


def _bridge_options(settings: DemoSettings) -> tuple[str, ...]:
    params = ("--params", settings.params_path) if settings.params_path else ()
    return ("--drive", settings.drive, "--plant-profile", settings.plant_profile, *params)


def _planner_options(settings: DemoSettings, seed: int) -> tuple[str, ...]:
    params = ("--params", settings.params_path) if settings.params_path else ()
    return (
        "--random", str(settings.waypoints), "--seed", str(seed), "--case", "all", "--law", "all",
        "--lookahead", str(settings.lookahead), "--lookahead-s", f"{settings.lookahead_s:g}",
        "--label", LABEL, "--solver", settings.solver, *params,
    )  # fmt: skip


def _run_planners(
    cell: Cell, settings: DemoSettings, progress: Callable[[str], None], stop: threading.Event
) -> None:
    """One planner per axis, axis ``aK`` with seed + K, all at once; returns when all have ended well
    (a :class:`CellError` naming the first that failed; ``stop``: KeyboardInterrupt). Every
    :data:`PROGRESS_PERIOD_S` it passes on each planner's latest progress line, and at the end each
    one's summary of its runs."""
    layout = cell.layout
    planners = {}
    for k, axis in enumerate(layout.axes):
        options = _planner_options(settings, settings.seed + k)
        planners[axis] = cell.launcher.start(f"planner-{axis}", *layout.planner(axis, options))
    progress(
        f"experiment: {len(planners)} planners, {settings.waypoints} way points each (axis aK: seed "
        f"{settings.seed} + K), 2 cases × 3 laws, solver {settings.solver}, {settings.lookahead_s:g} s "
        "of drive time queued"
    )
    next_word = time.monotonic() + PROGRESS_PERIOD_S
    while any(p.poll() is None for p in planners.values()):
        if stop.wait(0.2):
            raise KeyboardInterrupt
        for axis, p in planners.items():
            if p.poll() not in (None, 0):
                raise CellError(f"the planner of axis {axis} failed: {last_line(p.stderr_text())}")
        cell.check_alive()
        if time.monotonic() >= next_word:
            next_word += PROGRESS_PERIOD_S
            for axis, p in planners.items():
                said = "done" if p.poll() == 0 else last_line(p.stderr_text()).strip()
                progress(f"  {axis}: {said}")
    for axis, p in planners.items():
        end = cell.launcher.wait(p)
        if end.returncode != 0:
            raise CellError(f"the planner of axis {axis} failed: {last_line(end.stderr)}")
        for line in end.stdout.splitlines():
            progress(f"  {axis}: {line.strip()}")


def _recording_counts(
    layout: CellLayout, bridges: dict[str, dict], recorded: dict
) -> dict[str, AxisRecording]:
    """Per axis: the samples its bridge published against those the recorder wrote and missed."""
    out = {}
    for axis in layout.axes:
        topic = recorded["topics"].get(topic_for_key(AxisKeys(axis, layout.prefix).state), {})
        report = bridges[axis]
        out[axis] = AxisRecording(
            report["ticks"] - report["stale_ticks"], topic.get("messages", 0), topic.get("missed", 0)
        )
    return out


def _table(out: Path, layout: CellLayout, axis: str) -> Table2:
    keys = AxisKeys(axis, layout.prefix)
    table = table_from_recording(out / RECORDING, keys, label=LABEL, title=f"Table 2, axis {axis}")
    write_table2(table, out, f"table2-{axis}")
    return table


def _pictures(
    out: Path, settings: DemoSettings, report: CellDemoReport, progress: Callable[[str], None]
) -> None:
    t0 = time.monotonic()
    from ..viz.session import write_session_rrd  # rerun: loaded when the demo draws

    write_session_rrd([out / RECORDING], out / "cell.rrd", load_params(settings.params_path))
    report.phases_s["pictures"] = time.monotonic() - t0
    progress(f"rerun recording of the cell, one column per axis: {out / 'cell.rrd'}")


def _summary_json(report: CellDemoReport, settings: DemoSettings) -> dict:
    return {
        "out": str(report.out),
        "axes": list(report.axes),
        "waypoints_per_axis": settings.waypoints,
        "seeds": {axis: settings.seed + k for k, axis in enumerate(report.axes)},
        "bridge_speed": settings.speed,
        "plant": settings.plant_profile,
        "drive": settings.drive,
        "solver": settings.solver,
        "wall_time_s": report.wall_time_s,
        "phases_s": report.phases_s,
        "recording": {axis: vars(r) for axis, r in report.recording.items()},
        "energy_error_pct": {
            axis: {f"{r.case.value} {r.law}": r.energy_error_pct for r in table.rows}
            for axis, table in report.tables.items()
        },
        "idle_ticks": {
            axis: sum(r.measured.idle_ticks_total for r in t.rows if r.measured)
            for axis, t in report.tables.items()
        },
    }
