"""``axisflow demo``: bridge, recorder, excitation, refit and the paper's experiment before and after."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from ..acquisition.drives.plant_profiles import DEFAULT_PROFILE, PROFILE_RESOURCES
from ..arguments import finite_float, non_negative_int, positive_int, waypoint_count
from ..demo.settings import DEFAULT_LOOKAHEAD, DEFAULT_LOOKAHEAD_S, DEFAULT_WAYPOINTS, DemoSettings
from ..deploy.processes import stop_on_signals
from ..model import AxisflowError
from ..planner import BACKENDS


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "demo",
        help="the whole loop on the simulated axis: excite, refit, Table 2 before and after (a few minutes)",
        description="Start the drive bridge (simulated axis) and the recorder as processes on an embedded "
        "Zenoh peer network on loopback; run the identification excitation, refit the friction from its "
        "recording, run the paper's experiment with the nominal and with the refit parameters, and print "
        "Table 2 (planned against measured energy) for both. Everything lands in one session folder.",
    )
    p.add_argument(
        "--out", metavar="DIR", default=None, help="session folder (default: a new one under logs/)"
    )
    p.add_argument(
        "--waypoints",
        type=waypoint_count,
        default=DEFAULT_WAYPOINTS,
        help=f"way points of the experiment (default {DEFAULT_WAYPOINTS}; the paper used 100)",
    )
    p.add_argument("--seed", type=non_negative_int, default=0, help="way point seed (default 0)")
    p.add_argument(
        "--speed",
        type=finite_float,
        default=0.0,
        metavar="X",
        help="the bridge's speed: X times real time, 0 = as fast as the recorder takes samples (default 0)",
    )
    p.add_argument(
        "--solver", choices=sorted(BACKENDS), default="exact", help="planner back-end (default exact)"
    )
    p.add_argument(
        "--lookahead",
        type=positive_int,
        default=DEFAULT_LOOKAHEAD,
        metavar="K",
        help=f"planned moves queued behind the running one (default {DEFAULT_LOOKAHEAD})",
    )
    p.add_argument(
        "--lookahead-s",
        type=finite_float,
        default=None,
        metavar="S",
        help=f"and at least S seconds of drive time queued (default {DEFAULT_LOOKAHEAD_S:g}; with --axes N, "
        f"{DEFAULT_LOOKAHEAD_S:g}·N: N bridges at --speed 0 share the machine with N planners)",
    )
    p.add_argument(
        "--params", metavar="FILE", default=None, help="nominal axis parameters (default: packaged)"
    )
    p.add_argument(
        "--plant-profile",
        choices=list(PROFILE_RESOURCES),
        default=DEFAULT_PROFILE,
        help=f"the simulated axis's plant profile (docs/plant.md; default {DEFAULT_PROFILE})",
    )
    p.add_argument(
        "--drive",
        choices=("sim", "canopen-sim"),
        default="sim",
        help="the bridge's drive: the built-in simulated axis (default), or a simulated CiA 402 drive over "
        "CANopen on an in-process bus (counts, per-mille torque; docs/drives.md)",
    )
    p.add_argument(
        "--adapt",
        action="store_true",
        help="instead: online re-identification on a warming axis, against the nominal parameters and a "
        "one-time refit (three warm-up axes at once: `axisflow bench adapt`, docs/adaptation.md)",
    )
    p.add_argument(
        "--adapt-minutes",
        type=finite_float,
        default=10.0,
        metavar="M",
        help="with --adapt: minutes of axis time of way points per axis (default 10)",
    )
    p.add_argument(
        "--axes",
        type=positive_int,
        default=1,
        metavar="N",
        help="a cell of N axes instead (docs/deployment.md): N bridges, one recorder and a planner per axis "
        "as processes through one Zenoh router, the experiment on each axis (way point seed + K on axis aK), "
        "Table 2 per axis from one recording (default 1: the demo above)",
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..demo.loop import run_demo
    from ..experiment.table2_markdown import table_markdown
    from ..model.files import check_output_dir

    out = Path(args.out) if args.out else Path("logs") / time.strftime("demo-%Y%m%d-%H%M%S")
    check_output_dir(out)
    if out.exists() and any(out.iterdir()):
        raise AxisflowError(f"session folder {out} is not empty: choose a new --out")
    if not args.speed >= 0.0:
        raise AxisflowError(f"--speed {args.speed} must be >= 0 (0 = as fast as possible)")
    if args.adapt:
        return _adapt(args, out)
    settings = DemoSettings(
        out=out,
        waypoints=args.waypoints,
        seed=args.seed,
        speed=args.speed,
        solver=args.solver,
        lookahead=args.lookahead,
        lookahead_s=DEFAULT_LOOKAHEAD_S * args.axes if args.lookahead_s is None else args.lookahead_s,
        params_path=args.params,
        plant_profile=args.plant_profile,
        drive=args.drive,
    )
    if args.axes > 1:  # a cell of several axes through one router: axisflow/deploy/cell.py
        return _run_cell(settings, args.axes)
    speed = "as fast as the recorder allows" if args.speed == 0 else f"at {args.speed:g}× real time"
    print(
        f"axisflow demo: {args.waypoints} way points (the paper: 100), solver {args.solver}, drive "
        f"{args.drive}, plant profile {args.plant_profile}, the bridge runs {speed}",
        file=sys.stderr,
        flush=True,
    )

    def progress(line: str) -> None:
        print(f"[{time.monotonic() - t0:6.1f} s] {line}", file=sys.stderr, flush=True)

    t0 = time.monotonic()
    with stop_on_signals() as stop:
        report = run_demo(settings, progress, stop)
    for table in report.tables.values():
        print(table_markdown(table))
    nominal, refit = report.tables.get("nominal"), report.tables.get("refit")
    if nominal and refit:
        print("E% (E_th − E_exp)/E_th per row, nominal → refit parameters:")
        for a, b in zip(nominal.rows, refit.rows, strict=True):
            print(f"  {a.case.value:16} {a.law}: {_pct(a.energy_error_pct)} → {_pct(b.energy_error_pct)}")
        idle = sum(r.measured.idle_ticks_total for t in (nominal, refit) for r in t.rows if r.measured)
        print(f"idle ticks between consecutive moves, all rows: {idle}")
    print(f"\nplant: {report.plant}")
    phases = ", ".join(f"{name} {seconds:.1f} s" for name, seconds in report.phases_s.items())
    print(f"phases: {phases} (demo.json has them)")
    print(f"demo finished in {report.wall_time_s:.0f} s; everything is in {report.out}/")
    if report.savings_line:
        print(report.savings_line)
    return 0


def _pct(value: float | None) -> str:
    return "     – %" if value is None else f"{value:+6.2f} %"


def _adapt(args: argparse.Namespace, out: Path) -> int:
    """The adaptation experiment as a demo (``axisflow bench adapt``'s run), its session folder under
    logs/."""
    from ..demo.adaptation import AdaptationSettings, adaptation_markdown, run_adaptation

    settings = AdaptationSettings(
        out=out, minutes=args.adapt_minutes, waypoints=args.waypoints, seed=args.seed
    )
    with stop_on_signals() as stop:
        results = run_adaptation(settings, lambda line: print(line, flush=True), stop)
    print(adaptation_markdown(results, settings))
    return 0


def _run_cell(settings: DemoSettings, axes: int) -> int:
    from ..demo.cell_demo import run_cell_demo
    from ..experiment.table2_markdown import table_markdown

    t0 = time.monotonic()

    def progress(line: str) -> None:
        print(f"[{time.monotonic() - t0:6.1f} s] {line}", file=sys.stderr, flush=True)

    with stop_on_signals() as stop:
        report = run_cell_demo(settings, axes, progress, stop)
    for table in report.tables.values():
        print(table_markdown(table))
    print("E% (E_th − E_exp)/E_th per row and axis; samples recorded of those published:")
    for axis, table in report.tables.items():
        errors = " ".join(_pct(r.energy_error_pct).strip() for r in table.rows)
        r = report.recording[axis]
        print(f"  {axis}: {errors}; {r.recorded} of {r.ticks} samples, {r.missed} missed")
    print(
        f"\ndemo of a {axes}-axis cell finished in {report.wall_time_s:.0f} s; everything is in {report.out}/"
    )
    return 0
