"""``axisflow planner``: the online planner node, driving a running bridge."""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING

from ..acquisition.wire.keys import DEFAULT_AXIS, DEFAULT_PREFIX, AxisKeys
from ..arguments import (
    add_params_option,
    add_solver_options,
    backend_from_args,
    finite_float,
    non_negative_int,
    params_from_args,
    positive_int,
    waypoint_count,
)
from ..deploy.processes import stop_on_signals
from ..experiment.paper import LAWS
from ..model import AxisflowError
from ..planner import DEFAULT_OMEGA, Case
from .zenoh_options import add_zenoh_options, zenoh_options_from_args

if TYPE_CHECKING:
    from ..nodes.planner_node import RunReport


def _names(choices: tuple[str, ...], what: str) -> Callable[[str], tuple[str, ...]]:
    """An argparse type: comma-separated names from ``choices``, or ``all``."""

    def parse(text: str) -> tuple[str, ...]:
        names = tuple(dict.fromkeys(t.strip() for t in text.split(",") if t.strip()))
        if text.strip() == "all":
            return choices
        bad = [n for n in names if n not in choices]
        if bad or not names:
            raise argparse.ArgumentTypeError(f"{what} {text!r}: choose from {', '.join(choices)} or all")
        return names

    return parse


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "planner",
        help="the online planner node: plan each move while the previous one runs, on a live bridge",
        description="Plan the moves through way points one at a time while the axis executes the previous "
        "one (the paper's online scheme), send them to a running bridge appended (no idle tick), publish "
        "each plan on <prefix>/<axis>/plan and follow the bridge's move status. Prints per run the total "
        "time, model energy, solve times and slack; fails if the bridge rejects a move or a plan is late.",
    )
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--waypoints", metavar="FILE", help="way points [m]: one per line, or a JSON list")
    src.add_argument("--random", type=waypoint_count, metavar="N", help="N way points uniform in [0, L]")
    p.add_argument("--seed", type=non_negative_int, default=0, help="seed of --random (default 0)")
    cases = tuple(c.value for c in Case)
    p.add_argument(
        "--case",
        type=_names(cases, "--case"),
        default=(Case.MIN_TIME.value,),
        help=f"comma-separated cases, or all ({', '.join(cases)}; default min-time)",
    )
    p.add_argument(
        "--law",
        type=_names(LAWS, "--law"),
        default=("poly5",),
        help="comma-separated laws, or all (default poly5)",
    )
    p.add_argument(
        "--omega",
        type=finite_float,
        default=DEFAULT_OMEGA,
        help=f"ω of min-time-energy (default {DEFAULT_OMEGA})",
    )
    p.add_argument(
        "--lookahead",
        type=positive_int,
        default=1,
        metavar="K",
        help="planned moves kept queued behind the running one (default 1, the paper's scheme; more for a "
        "bridge at --speed 0)",
    )
    p.add_argument(
        "--lookahead-s",
        type=finite_float,
        default=0.0,
        metavar="S",
        help="and at least S seconds of drive time queued (default 0; e.g. 3 for a bridge at --speed 0)",
    )
    p.add_argument("--label", default="", help="label of this run in the plan records (e.g. nominal, refit)")
    p.add_argument(
        "--adapt",
        action="store_true",
        help="plan each next move with the newest parameter set `axisflow adapt` accepted for this axis "
        "(on <prefix>/<axis>/params; each plan record names its version; docs/adaptation.md)",
    )
    p.add_argument("--axis", default=DEFAULT_AXIS, help=f"axis name (default: {DEFAULT_AXIS})")
    p.add_argument("--prefix", default=DEFAULT_PREFIX, help=f"key prefix (default: {DEFAULT_PREFIX})")
    p.add_argument("--json", action="store_true", help="print one JSON object (no progress lines)")
    add_params_option(p)
    add_solver_options(p)
    add_zenoh_options(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..acquisition.bus.session import open_session
    from ..experiment.waypoints import load_waypoints, random_waypoints
    from ..nodes.planner_node import NodeRun, NodeSettings, PlannerNode

    params = params_from_args(args)
    points = (
        load_waypoints(args.waypoints, params)
        if args.waypoints
        else random_waypoints(args.random, args.seed, params)
    )
    settings = NodeSettings(
        keys=AxisKeys(args.axis, args.prefix),
        runs=tuple(NodeRun(Case(c), law) for c in args.case for law in args.law),
        omega=args.omega,
        lookahead=args.lookahead,
        lookahead_s=args.lookahead_s,
        label=args.label,
        adapt=args.adapt,
    )
    if not 0.0 <= args.omega <= 1.0:
        raise AxisflowError(f"--omega {args.omega} is outside [0, 1]")
    backend = backend_from_args(args)

    def progress(line: str) -> None:
        print(line, file=sys.stderr, flush=True)

    with (
        stop_on_signals() as stop,
        open_session(zenoh_options_from_args(args)) as session,
        PlannerNode(session, settings, params, backend, None if args.json else progress, stop) as node,
    ):
        reports = node.run(points)
    if args.json:
        print(json.dumps([_report_json(r) for r in reports], indent=1))
    else:
        for r in reports:
            print(r.summary())
    return 0


def _report_json(report: RunReport) -> dict[str, object]:
    moves = report.experiment
    return {
        "case": report.run.case.value,
        "law": report.run.law,
        "solver": report.solver,
        "moves": len(moves),
        "total_time_s": sum(m.plan.duration_s for m in moves),
        "energy_model_j": sum(m.plan.energy_j for m in moves),
        "solve_times_ms": [m.plan.solve_time_s * 1e3 for m in moves],
        "slack_ms": [m.slack_s * 1e3 for m in moves],
        "idle_ticks": report.idle_ticks,
        "move_ids": [m.command.move_id for m in moves],
        "params_versions": [m.params_version for m in moves],
    }
