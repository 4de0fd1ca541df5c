"""``axisflow plan``: plan one move and print the result."""

from __future__ import annotations

import argparse
import json

from ..planner import DEFAULT_OMEGA, Case, MoveProblem
from .common import add_params_option, add_solver_options, backend_from_args, finite_float, params_from_args


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "plan",
        help="plan one point-to-point move",
        description="Plan the duration of one rest-to-rest move x0 → x1 [m].",
    )
    p.add_argument("x0", type=finite_float, help="start position [m], in [0, L]")
    p.add_argument("x1", type=finite_float, help="end position [m], in [0, L]")
    p.add_argument("--law", choices=("poly3", "poly5", "poly7"), default="poly5")
    p.add_argument("--case", choices=[c.value for c in Case], default=Case.MIN_TIME.value)
    p.add_argument(
        "--omega",
        type=finite_float,
        default=DEFAULT_OMEGA,
        help="time weight ω of the min-time-energy case, in [0, 1] (default 0.9)",
    )
    p.add_argument("--t-min", type=finite_float, default=None, metavar="S", help="lower duration bound [s]")
    p.add_argument("--t-max", type=finite_float, default=None, metavar="S", help="upper duration bound [s]")
    add_params_option(p)
    add_solver_options(p)
    p.add_argument("--json", action="store_true", help="print the result as one JSON object")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    params = params_from_args(args)
    problem = MoveProblem(
        args.x0, args.x1, args.law, Case(args.case), omega=args.omega, t_min_s=args.t_min, t_max_s=args.t_max
    )
    backend = backend_from_args(args)
    backend.prepare(problem, params)
    r = backend.solve(problem, params)
    out = {
        "x0_m": problem.x0_m,
        "x1_m": problem.x1_m,
        "law": problem.law.name,
        "case": problem.case.value,
        "omega": problem.omega if problem.case is Case.MIN_TIME_ENERGY else None,
        "solver": r.solver,
        "status": r.status.value,
        "duration_s": r.duration_s,
        "objective": r.objective,
        "energy_j": r.energy_j,
        "iterations": r.iterations,
        "solve_time_ms": r.solve_time_s * 1e3,
        "max_violation": r.max_violation,
        "message": r.message,
        "certificate": r.certificate,
    }
    if args.json:
        print(json.dumps(out))
    else:
        for k, v in out.items():
            print(f"{k:>14}: {v}")
    return 0
