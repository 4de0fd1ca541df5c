"""A cell: several axes through one Zenoh router, their processes started as a launch file would.

A robot cell has several axes, each driven from a machine near its drive, and one place where
everything is recorded (docs/deployment.md). On one machine — the demo, the tests, the benchmark — a
:class:`Cell` starts the processes such a deployment runs on several, each an ``axisflow`` command of
its own, through a :class:`~axisflow.deploy.processes.Launcher`:

* one **router** (``axisflow router --listen EP``), the only listener of the cell;
* one **bridge** per axis (``axisflow bridge --axis aK``), axes named ``a0``, ``a1``, …
  (:func:`axis_names`), each a Zenoh **client** of the router;
* one **recorder** (``axisflow record``) of every key of the cell, a client too;
* for the demo, one **planner** per axis (``axisflow planner --axis aK``), a client too.

:class:`CellLayout` is the launch description: the command line of each process. Every process says
when it is ready (the router: it listens; a bridge: it holds its token; the recorder: its subscriber
has joined), so nothing waits on a sleep; the recorder starts before the bridges, which wait for its
subscriber before their first tick (so it records each from its first sample). :meth:`Cell.restart_router`
stops the router and starts another on the same endpoint: the bridges keep their axes safe and every
client reconnects by itself (docs/deployment.md, tests/deploy/test_cell.py).

:func:`run_cell_demo` is ``axisflow demo --axes N``: N bridges, one recorder, a planner per axis; axis
``aK`` runs the paper's experiment (both cases, all three laws, the nominal parameters) over its own
random way points — seed + K, so that the axes move differently, as a cell's axes do — then Table 2 of
each axis is measured from the one recording.
"""

from __future__ import annotations

import json
import signal
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from ..acquisition.bus.options import check_endpoint
from ..acquisition.wire.keys import DEFAULT_PREFIX, AxisKeys, all_keys, topic_for_key
from ..demo.settings import DemoSettings
from ..experiment.table2 import table_from_recording
from ..experiment.table2_record import Table2, write_table2
from ..model import AxisflowError, load_params
from ..model.files import write_atomic
from .processes import READY_TIMEOUT_S, STOP_TIMEOUT_S, Child, Exited, Launcher, free_port, last_line

MAX_AXES = 32
"""axes a cell of ``axisflow demo --axes`` may have (one bridge process each, on one machine)"""
PROGRESS_PERIOD_S = 10.0
"""how often the demo says where each axis's planner is [s]"""
RECORDING = "cell.mcap"
"""the demo's one recording, in its session folder"""
LABEL = "nominal"
"""the plan label of the demo's runs (the nominal parameters)"""


class CellError(AxisflowError):
    """A process of the cell failed or did not get ready."""


def axis_names(count: int) -> tuple[str, ...]:
    """The axes of a cell of ``count``: ``a0``, ``a1``, …"""
    if not 1 <= count <= MAX_AXES:
        raise AxisflowError(f"--axes {count} must be in 1…{MAX_AXES} (one bridge process per axis)")
    return tuple(f"a{k}" for k in range(count))


@dataclass(frozen=True)
class CellLayout:
    """The launch description of a cell on this machine: which ``axisflow`` commands run, with which
    arguments (every process but the router is a client of the router at ``endpoint``)."""

    axes: tuple[str, ...]
    endpoint: str
    prefix: str = DEFAULT_PREFIX
    bridge_speed: float = 1.0
    """the bridges' ``--speed`` (0: as fast as the recorder takes their samples)"""
    bridge_options: tuple[str, ...] = ()
    """more arguments of every bridge (``--plant-profile``, ``--params``, ``--drive``)"""

    def __post_init__(self) -> None:
        check_endpoint(self.endpoint)
        for axis in self.axes:
            AxisKeys(axis, self.prefix)  # a valid key chunk, or a KeyExprError naming it
        if not self.axes or len(set(self.axes)) != len(self.axes):
            raise AxisflowError(f"a cell needs distinct axes, not {', '.join(self.axes) or 'none'}")

    @classmethod
    def on_loopback(
        cls, count: int, bridge_speed: float = 1.0, bridge_options: tuple[str, ...] = ()
    ) -> CellLayout:
        """``count`` axes around a router on a free port of 127.0.0.1."""
        endpoint = f"tcp/127.0.0.1:{free_port()}"
        return cls(axis_names(count), endpoint, bridge_speed=bridge_speed, bridge_options=bridge_options)

    @property
    def client(self) -> tuple[str, ...]:
        """The Zenoh options of every process but the router."""
        return ("--mode", "client", "--connect", self.endpoint)

    def router(self) -> tuple[str, ...]:
        return ("router", "--listen", self.endpoint)

    def bridge(
        self, axis: str, duration_s: float | None = None, wait_subscribers_s: float = 0.0
    ) -> tuple[str, ...]:
        duration = ("--duration", f"{duration_s:g}") if duration_s is not None else ()
        return (
            "bridge", "--axis", axis, "--prefix", self.prefix, "--speed", f"{self.bridge_speed:g}",
            "--wait-subscribers", f"{wait_subscribers_s:g}", *duration, "--json", *self.bridge_options,
            *self.client,
        )  # fmt: skip

    def recorder(self, path: Path) -> tuple[str, ...]:
        return ("record", "-o", str(path), "--keys", all_keys(self.prefix), "--json", *self.client)

    def planner(self, axis: str, options: tuple[str, ...]) -> tuple[str, ...]:
        return ("planner", "--axis", axis, "--prefix", self.prefix, *options, *self.client)


@dataclass(frozen=True)
class RouterRestart:
    """When :meth:`Cell.restart_router` stopped the router and when its successor listened
    (``time.monotonic()`` seconds)."""

    asked_s: float
    stopped_s: float
    listening_s: float

    @property
    def down_s(self) -> float:
        """From the stop asked to the new router listening [s]."""
        return self.listening_s - self.asked_s


class Cell:
    """The processes of a cell (see the module docstring); a context manager: leaving stops whatever
    still runs (SIGINT, the recorder finishing its file)."""

    def __init__(self, layout: CellLayout, logs: Path) -> None:
        self.layout = layout
        self.launcher = Launcher(logs)
        self.router: Child | None = None
        self.recorder: Child | None = None
        self.bridges: dict[str, Child] = {}

    def __enter__(self) -> Cell:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.launcher.close(STOP_TIMEOUT_S)

    def _ready(self, child: Child) -> Child:
        try:
            self.launcher.wait_ready(child, READY_TIMEOUT_S)
        except AxisflowError as exc:
            raise CellError(f"{exc} (its output: {child.err_path})") from None
        return child

    def start_router(self) -> Child:
        self.router = self._ready(self.launcher.start("router", *self.layout.router(), ready=True))
        return self.router

    def start_recorder(self, path: Path) -> Child:
        self.recorder = self._ready(self.launcher.start("recorder", *self.layout.recorder(path), ready=True))
        return self.recorder

    def start_bridges(self, duration_s: float | None = None, wait_subscribers_s: float = 0.0) -> None:
        """Every axis's bridge, started together; returns once each holds its token."""
        for axis in self.layout.axes:
            args = self.layout.bridge(axis, duration_s, wait_subscribers_s)
            self.bridges[axis] = self.launcher.start(f"bridge-{axis}", *args, ready=True)
        for child in self.bridges.values():
            self._ready(child)

    def restart_router(self) -> RouterRestart:
        """Stop the router (SIGINT) and start another on the same endpoint."""
        assert self.router is not None, "start_router first"
        asked = time.monotonic()
        self._check(self.launcher.stop(self.router, STOP_TIMEOUT_S))
        stopped = time.monotonic()
        self.start_router()
        return RouterRestart(asked, stopped, time.monotonic())

    def wait_bridges(self, timeout_s: float) -> dict[str, dict]:
        """The reports of the bridges (started with a duration), once they have ended by themselves."""
        return {
            axis: self._check(self.launcher.wait(c, timeout_s)).json() for axis, c in self.bridges.items()
        }

    def stop_bridges(self) -> dict[str, dict]:
        """SIGINT to every bridge; their reports by axis."""
        for child in self.bridges.values():
            if child.poll() is None:
                child.send_signal(signal.SIGINT)
        return self.wait_bridges(STOP_TIMEOUT_S)

    def stop_recorder(self) -> dict:
        """SIGINT to the recorder (it proves nothing is on the way, then finishes its file): its summary."""
        assert self.recorder is not None, "start_recorder first"
        return self._check(self.launcher.stop(self.recorder, STOP_TIMEOUT_S)).json()

    def stop_router(self) -> None:
        if self.router is not None:
            self._check(self.launcher.stop(self.router, STOP_TIMEOUT_S))

    def check_alive(self) -> None:
        """A :class:`CellError` if the router, the recorder or a bridge has ended."""
        for child in (self.router, self.recorder, *self.bridges.values()):
            if child is not None and child.poll() is not None:
                raise CellError(
                    f"{child.command} ended with code {child.returncode}: {last_line(child.stderr_text())}"
                )

    def _check(self, end: Exited) -> Exited:
        if end.returncode != 0 or end.timed_out:
            how = "hung and was killed" if end.timed_out else f"exited with code {end.returncode}"
            raise CellError(f"{end.name} {how}: {last_line(end.stderr)} (see {self.launcher.logs})")
        return end


# ---- axisflow demo --axes N ----------------------------------------------------------------------------


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
