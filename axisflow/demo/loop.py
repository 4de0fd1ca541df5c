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
(``--speed 0``; between the phases, with nobody recording, it waits) so that ~25 minutes of axis time
take a few minutes; the way point count defaults to :data:`~axisflow.demo.settings.DEFAULT_WAYPOINTS`
(the paper used 100). The bridge and the recorders are started by a
:class:`~axisflow.deploy.processes.Launcher`: Ctrl-C (or SIGTERM) stops everything cleanly — the recordings
are finished — and even a SIGKILL of the demo leaves no process running (they follow the launcher's
lifeline). Each phase begins once its recorder's subscriber has joined (its ready byte, then its token
seen by this session) and ends with the recorder's own stop, which proves nothing was still on the way
(acquisition.bus.readiness).
"""

from __future__ import annotations

import json
import socket
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from ..acquisition import AxisKeys
from ..acquisition.drives.plant import load_profile
from ..acquisition.wire.keys import recorder_token
from ..deploy.processes import READY_TIMEOUT_S, Child, Launcher, free_port
from ..experiment.offline import CASES
from ..experiment.paper import FIG5_WAYPOINTS, LAWS
from ..experiment.table2 import table_from_recording
from ..experiment.table2_markdown import write_table2
from ..experiment.table2_record import Table2
from ..experiment.waypoints import random_waypoints
from ..model import AxisflowError, AxisParams, load_params
from ..model.files import write_atomic
from ..planner import DEFAULT_OMEGA, make_backend
from .settings import DemoSettings

SAVINGS_WAYPOINTS = 6
"""way points of the demo's closing comparison with a trapezoid (the first of the experiment's)"""


@dataclass
class DemoReport:
    out: Path
    tables: dict[str, Table2] = field(default_factory=dict)
    refit: dict = field(default_factory=dict)
    plant: str = ""
    """the simulated axis's plant, as its bridge described it"""
    wall_time_s: float = 0.0
    phases_s: dict[str, float] = field(default_factory=dict)
    savings: dict = field(default_factory=dict)
    """the saving against a trapezoid at equal cycle time, per run of axisflow's law, model and measured"""
    savings_line: str = ""


def run_demo(
    settings: DemoSettings, progress: Callable[[str], None], stop: threading.Event | None = None
) -> DemoReport:
    """Run the demo (see the module docstring) into ``settings.out``."""
    from ..acquisition.bus.session import ZenohOptions, open_session
    from ..identification.excitation import design_excitation
    from ..nodes.excite import run_excitation

    stop = stop or threading.Event()
    out = settings.out
    out.mkdir(parents=True, exist_ok=True)
    nominal = load_params(settings.params_path)
    waypoints = random_waypoints(settings.waypoints, settings.seed, nominal)
    plan = design_excitation(nominal)
    report = DemoReport(out)
    t_start = time.monotonic()
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    children = Launcher(out / "logs")
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
            ready=True,
        )  # fmt: skip
        children.wait_ready(bridge, READY_TIMEOUT_S)
        report.phases_s["start-up"] = time.monotonic() - t_start
        with open_session(ZenohOptions(connect=(endpoint,))) as session:
            keys = AxisKeys()
            # 1. excitation
            t0 = time.monotonic()
            with _recording(children, session, out / "excitation.mcap", endpoint):
                progress(f"excitation: {len(plan.bursts)} bursts, {plan.duration_s:.0f} s of axis time")
                done = run_excitation(session, keys, nominal, plan, stop=stop)
                progress(f"  {done.format()}")
            report.phases_s["excitation"] = time.monotonic() - t0
            _check_stop(stop)
            children.check_alive(bridge)
            # 2. identification
            t0 = time.monotonic()
            from ..experiment.refit_folder import identify_to
            from ..identification.refit import IdentifySettings  # CasADi: loaded when the demo fits

            # the excitation's moves only: what was recorded around them is of no use
            _ident, refit_report = identify_to(
                out / "refit", [out / "excitation.mcap"], nominal, IdentifySettings(window=done.window())
            )
            report.refit = refit_report
            refit = load_params(out / "refit" / "params.toml")
            report.phases_s["identification"] = time.monotonic() - t0
            progress(_refit_line(refit_report))
            _check_stop(stop)
            # 3., 4. the experiment with each parameter set
            for label, params in (("nominal", nominal), ("refit", refit)):
                t0 = time.monotonic()
                path = out / f"experiment-{label}.mcap"
                with _recording(children, session, path, endpoint):
                    progress(f"experiment, {label} parameters: {len(waypoints)} way points, 2 cases × 3 laws")
                    _run_experiment(session, keys, params, label, waypoints, settings, progress, stop)
                report.phases_s[f"experiment-{label}"] = time.monotonic() - t0
                t0 = time.monotonic()
                report.tables[label] = _table(out, path, label)
                report.phases_s[f"table2-{label}"] = time.monotonic() - t0
                _check_stop(stop)
            # 5. the saving against a trapezoid at equal cycle time, on a few of the way points
            t0 = time.monotonic()
            from ..savings.cycle_moves import moves_of_waypoints
            from ..savings.study import compare_on_session, measured_savings, saving_line

            moves = moves_of_waypoints(waypoints[:SAVINGS_WAYPOINTS])
            with _recording(children, session, out / "savings.mcap", endpoint):
                progress(
                    f"savings: {len(moves)} moves against a trapezoid at equal cycle time, refit parameters"
                )
                comparison = compare_on_session(session, moves, refit, progress, stop)  # type: ignore[arg-type]
            report.savings = measured_savings(comparison, out / "savings.mcap")
            report.savings_line = saving_line(comparison, report.savings)
            report.phases_s["savings"] = time.monotonic() - t0
        t0 = time.monotonic()
        children.stop(bridge)
        report.phases_s["bridge-stop"] = time.monotonic() - t0
        t0 = time.monotonic()
        from ..viz.figures import write_figures  # rerun and matplotlib: loaded when the demo draws
        from ..viz.session import write_session_rrd

        recordings = [out / "excitation.mcap", out / "experiment-nominal.mcap", out / "experiment-refit.mcap"]
        write_session_rrd(recordings, out / "session.rrd", nominal)
        report.phases_s["session-rrd"] = time.monotonic() - t0
        t0 = time.monotonic()
        first = random_waypoints(FIG5_WAYPOINTS, settings.seed, nominal)
        write_figures(out / "figures", refit, first, excitation=out / "excitation.mcap")
        report.phases_s["figures"] = time.monotonic() - t0
        progress(f"rerun recording {out / 'session.rrd'}, figures in {out / 'figures'}")
    finally:
        children.close()
    report.wall_time_s = time.monotonic() - t_start
    write_atomic(out / "demo.json", json.dumps(_summary_json(report, settings), indent=1) + "\n")
    return report


def _check_stop(stop: threading.Event) -> None:
    """Between phases: a stop (SIGINT/SIGTERM) ends the demo here."""
    if stop.is_set():
        raise KeyboardInterrupt


class _recording:  # noqa: N801 - a context manager, read as a phrase
    """The recorder process for one phase: started, ready (joined) before the phase begins, stopped
    cleanly at its end (its stop proves nothing was still on the way: acquisition.bus.readiness)."""

    def __init__(self, children: Launcher, session: object, path: Path, endpoint: str) -> None:
        self.children, self.session, self.path, self.endpoint = children, session, path, endpoint
        self.proc: Child | None = None

    def __enter__(self) -> None:
        from ..acquisition.bus.readiness import wait_for_token

        args = ("record", "-o", str(self.path), "--connect", self.endpoint)
        self.proc = self.children.start(f"recorder-{self.path.stem}", *args, ready=True)
        self.children.wait_ready(self.proc, READY_TIMEOUT_S)
        # this session, which sends the moves, knows the recorder's subscriber once it sees its token
        token = recorder_token(socket.gethostname(), self.proc.pid)
        if not wait_for_token(self.session, token, READY_TIMEOUT_S):  # type: ignore[arg-type]
            raise AxisflowError(f"the recorder of {self.path} was ready, but its token {token} never came")

    def __exit__(self, *_exc: object) -> None:
        assert self.proc is not None
        end = self.children.stop(self.proc)
        if end.returncode != 0:
            raise AxisflowError(
                f"the recorder of {self.path} exited with {end.returncode}; see {end.name}.err in "
                f"{self.children.logs}"
            )


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
    from ..nodes.planner_node import NodeRun, NodeSettings, PlannerNode

    runs = tuple(NodeRun(case, law) for case in CASES for law in LAWS)
    node_settings = NodeSettings(keys, runs, DEFAULT_OMEGA, settings.lookahead, settings.lookahead_s, label)
    backend = make_backend(settings.solver)

    # the node's progress (every tenth move), then each run's summary
    with PlannerNode(session, node_settings, params, backend, progress, stop) as node:  # type: ignore[arg-type]
        for report in node.run(waypoints):  # type: ignore[arg-type]
            progress("  " + report.summary())


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
        "savings": report.savings,
        "savings_line": report.savings_line,
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
