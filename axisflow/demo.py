"""``axisflow demo``: the whole loop on the simulated axis, from a fresh clone, in a few minutes.

As a launch file would, it starts the drive bridge (simulated axis) and the recorder as processes of
their own, on an embedded Zenoh peer network on loopback, then, in this process:

1. **excitation**: runs the identification excitation through the bridge (recorded to
   ``excitation.mcap``);
2. **identification**: refits M_eq and a1…a4 from that recording (``refit/``: params.toml, report,
   fit.png);
3. **experiment, nominal**: the planner node runs the paper's experiment (both cases, all three laws,
   the same random way points) with the nominal parameters (``experiment-nominal.mcap``);
4. **experiment, refit**: the same with the refit parameters (``experiment-refit.mcap``);
5. **Table 2** of both recordings: planned energy E_th against the measured E_exp
   (``table2-nominal.*``, ``table2-refit.*``); the refit should bring them together — the reason to
   identify at all;
6. **pictures**: the rerun recording of the whole session (``session.rrd``: ``rerun session.rrd``) and
   the paper's figures (``figures/``: Fig. 2 from this excitation, Fig. 5 from the refit run).

Everything lands in one session folder. The bridge runs as fast as the recorder takes its samples
(``--speed 0``) so that ~25 minutes of axis time take a few minutes; the way point count defaults to
:data:`DEFAULT_WAYPOINTS` (the paper used 100). Ctrl-C stops everything cleanly: the recordings are
finished, no process is left running.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from .acquisition import AxisKeys
from .acquisition.bus.session import ZenohOptions, open_session
from .acquisition.drives.plant import DEFAULT_PROFILE, load_profile
from .excite import run_excitation
from .experiment import CASES, LAWS
from .identification.excitation import design_excitation
from .model import AxisflowError, AxisParams, load_params
from .model.files import write_atomic
from .paper import FIG5_WAYPOINTS
from .planner import DEFAULT_OMEGA, make_backend
from .planner_node import NodeRun, NodeSettings, PlannerNode
from .table2 import table_from_recording
from .table2_record import Table2, write_table2
from .waypoints import random_waypoints

DEFAULT_WAYPOINTS = 50
"""way points of Fig. 5 (the paper's 25)"""
DEFAULT_LOOKAHEAD = 1
DEFAULT_LOOKAHEAD_S = 10.0
"""drive time kept queued behind the running move [s]: at --speed 0 the bridge runs ~11× real time on
two cores shared by three processes, and a planner that loses the CPU for 150 ms (seen on a loaded
machine) finds the queue 1.6 s of drive time shorter"""
_RECORDER_SETTLE_S = 1.0
_STOP_TIMEOUT_S = 30.0


@dataclass(frozen=True)
class DemoSettings:
    out: Path
    waypoints: int = DEFAULT_WAYPOINTS
    seed: int = 0
    speed: float = 0.0
    solver: str = "exact"
    lookahead: int = DEFAULT_LOOKAHEAD
    lookahead_s: float = DEFAULT_LOOKAHEAD_S
    params_path: str | None = None
    plant_profile: str = DEFAULT_PROFILE
    """the simulated axis's packaged plant profile (ideal, realistic, warm-up)"""
    drive: str = "sim"
    """the bridge's drive: ``sim`` (the built-in simulated axis) or ``canopen-sim`` (a simulated CiA 402
    drive on an in-process CAN bus in the bridge's process: encoder counts, per-mille torque, one bus
    cycle of latency)"""


@dataclass
class DemoReport:
    out: Path
    tables: dict[str, Table2] = field(default_factory=dict)
    refit: dict = field(default_factory=dict)
    plant: str = ""
    """the simulated axis's plant, as its bridge described it"""
    wall_time_s: float = 0.0
    phases_s: dict[str, float] = field(default_factory=dict)


class _Children:
    """The bridge and recorder processes: started with the demo's Zenoh endpoint, stopped with SIGINT
    (a clean finish: the recorder writes its summary and footer), killed only if they hang."""

    def __init__(self, out: Path) -> None:
        self.out = out
        self.procs: dict[str, subprocess.Popen] = {}

    def start(self, name: str, *args: str) -> subprocess.Popen:
        log = open(self.out / f"{name}.log", "w")  # noqa: SIM115 - closed with the process
        cmd = [sys.executable, "-m", "axisflow", *args]
        env = {**os.environ, "CI": os.environ.get("CI", "1"), "RUST_LOG": os.environ.get("RUST_LOG", "error")}
        # a new process group: a Ctrl-C of the terminal reaches the demo, which stops them in order
        proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env=env, start_new_session=True)
        proc.log = log  # type: ignore[attr-defined]
        self.procs[name] = proc
        return proc

    def stop(self, name: str) -> int:
        proc = self.procs.pop(name, None)
        if proc is None:
            return 0
        if proc.poll() is None:
            proc.send_signal(signal.SIGINT)
            try:
                proc.wait(_STOP_TIMEOUT_S)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
        proc.log.close()  # type: ignore[attr-defined]
        return proc.returncode

    def stop_all(self) -> None:
        for name in list(self.procs)[::-1]:
            self.stop(name)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def run_demo(
    settings: DemoSettings, progress: Callable[[str], None], stop: threading.Event | None = None
) -> DemoReport:
    """Run the demo (see the module docstring) into ``settings.out``."""
    stop = stop or threading.Event()
    out = settings.out
    out.mkdir(parents=True, exist_ok=True)
    nominal = load_params(settings.params_path)
    waypoints = random_waypoints(settings.waypoints, settings.seed, nominal)
    plan = design_excitation(nominal)
    report = DemoReport(out)
    t_start = time.monotonic()
    port = _free_port()
    endpoint = f"tcp/127.0.0.1:{port}"
    children = _Children(out)
    params_args = ["--params", settings.params_path] if settings.params_path else []
    plant = load_profile(settings.plant_profile, nominal)
    report.plant = plant.describe()
    try:
        what = "simulated axis" if settings.drive == "sim" else f"drive {settings.drive}"
        progress(
            f"session folder {out}; bridge ({what}, plant {report.plant}, --speed {settings.speed:g}) "
            f"on {endpoint}"
        )
        bridge = children.start(
            "bridge", "bridge", "--drive", settings.drive, "--plant-profile", settings.plant_profile,
            "--speed", f"{settings.speed:g}", "--listen", endpoint, *params_args,
        )  # fmt: skip
        with open_session(ZenohOptions(connect=(endpoint,))) as session:
            keys = AxisKeys()
            # 1. excitation
            t0 = time.monotonic()
            with _recording(children, out / "excitation.mcap", endpoint, progress):
                progress(f"excitation: {len(plan.bursts)} bursts, {plan.duration_s:.0f} s of axis time")
                done = run_excitation(session, keys, nominal, plan)
                progress(f"  {done.format()}")
            report.phases_s["excitation"] = time.monotonic() - t0
            _check_alive(bridge)
            # 2. identification
            t0 = time.monotonic()
            from .identification.refit import IdentifySettings  # CasADi: loaded when the demo fits
            from .identify import identify_to

            # the excitation's moves only: what was recorded around them is of no use, and a sample
            # lost there (see acquisition.bus.session.settle) would stop the refit
            _ident, refit_report = identify_to(
                out / "refit", [out / "excitation.mcap"], nominal, IdentifySettings(window=done.window())
            )
            report.refit = refit_report
            refit = load_params(out / "refit" / "params.toml")
            report.phases_s["identification"] = time.monotonic() - t0
            progress(_refit_line(refit_report))
            # 3., 4. the experiment with each parameter set
            for label, params in (("nominal", nominal), ("refit", refit)):
                t0 = time.monotonic()
                path = out / f"experiment-{label}.mcap"
                with _recording(children, path, endpoint, progress):
                    progress(f"experiment, {label} parameters: {len(waypoints)} way points, 2 cases × 3 laws")
                    _run_experiment(session, keys, params, label, waypoints, settings, progress, stop)
                report.tables[label] = _table(out, path, label)
                report.phases_s[f"experiment-{label}"] = time.monotonic() - t0
        children.stop("bridge")
        t0 = time.monotonic()
        from .viz.figures import write_figures  # rerun and matplotlib: loaded when the demo draws
        from .viz.session import write_session_rrd

        recordings = [out / "excitation.mcap", out / "experiment-nominal.mcap", out / "experiment-refit.mcap"]
        write_session_rrd(recordings, out / "session.rrd", nominal)
        first = random_waypoints(FIG5_WAYPOINTS, settings.seed, nominal)
        write_figures(out / "figures", refit, first, excitation=out / "excitation.mcap")
        report.phases_s["pictures"] = time.monotonic() - t0
        progress(f"rerun recording {out / 'session.rrd'}, figures in {out / 'figures'}")
    finally:
        children.stop_all()
    report.wall_time_s = time.monotonic() - t_start
    write_atomic(out / "demo.json", json.dumps(_summary_json(report, settings), indent=1) + "\n")
    return report


class _recording:  # noqa: N801 - a context manager, read as a phrase
    """The recorder process for one phase: started, waited for, stopped cleanly at the end."""

    def __init__(
        self, children: _Children, path: Path, endpoint: str, progress: Callable[[str], None]
    ) -> None:
        self.children, self.path, self.endpoint, self.progress = children, path, endpoint, progress

    def __enter__(self) -> None:
        proc = self.children.start(
            f"recorder-{self.path.stem}", "record", "-o", str(self.path), "--connect", self.endpoint
        )
        deadline = time.monotonic() + 20.0
        while not (self.path.exists() and self.path.stat().st_size > 0):
            _check_alive(proc)
            if time.monotonic() > deadline:
                raise AxisflowError(f"the recorder did not start {self.path} within 20 s")
            time.sleep(0.05)
        time.sleep(_RECORDER_SETTLE_S)  # its subscription reaches the bridge

    def __exit__(self, *_exc: object) -> None:
        time.sleep(0.2)  # the last samples reach the recorder
        rc = self.children.stop(f"recorder-{self.path.stem}")
        if rc not in (0, None):
            raise AxisflowError(f"the recorder of {self.path} exited with {rc}; see {self.path.parent}")


def _check_alive(proc: subprocess.Popen) -> None:
    if proc.poll() is not None:
        raise AxisflowError(f"{' '.join(proc.args[2:4])} exited early with code {proc.returncode}")  # type: ignore[index]


def _run_experiment(
    session: object,
    keys: AxisKeys,
    params: AxisParams,
    label: str,
    waypoints: object,
    settings: DemoSettings,
    progress: Callable[[str], None],
    stop: threading.Event,
) -> None:
    runs = tuple(NodeRun(case, law) for case in CASES for law in LAWS)
    node_settings = NodeSettings(keys, runs, DEFAULT_OMEGA, settings.lookahead, settings.lookahead_s, label)
    backend = make_backend(settings.solver)

    def run_lines(line: str) -> None:  # the node's per-run summaries, not its every-10-moves lines
        if not line.startswith("  "):
            progress("  " + line)

    with PlannerNode(session, node_settings, params, backend, run_lines, stop) as node:  # type: ignore[arg-type]
        node.run(waypoints)  # type: ignore[arg-type]


def _table(out: Path, path: Path, label: str) -> Table2:
    table = table_from_recording(path, label=label, title=f"Table 2, {label} parameters")
    write_table2(table, out, f"table2-{label}")
    return table


def _refit_line(report: dict) -> str:
    parts = []
    for name, p in report["parameters"].items():
        parts.append(f"{name} {p['initial']:.4g} → {p['value']:.4g}")
    refit, nominal = report["fit"]["rms_nm"], report["fit_nominal"]["rms_nm"]
    return f"identification: {', '.join(parts)}; fit RMS {refit:.4f} N·m (nominal {nominal:.4f})"


def _summary_json(report: DemoReport, settings: DemoSettings) -> dict:
    return {
        "out": str(report.out),
        "waypoints": settings.waypoints,
        "seed": settings.seed,
        "bridge_speed": settings.speed,
        "plant": {"profile": settings.plant_profile, "description": report.plant},
        "drive": settings.drive,
        "solver": settings.solver,
        "wall_time_s": report.wall_time_s,
        "phases_s": report.phases_s,
        "energy_error_pct": {
            label: {f"{r.case.value} {r.law}": r.energy_error_pct for r in table.rows}
            for label, table in report.tables.items()
        },
        "idle_ticks": {
            label: sum(r.measured.idle_ticks_total for r in t.rows if r.measured)
            for label, t in report.tables.items()
        },
    }
