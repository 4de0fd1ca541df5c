"""``axisflow plan``: plan one move and print the result."""

from __future__ import annotations

import argparse
import json
from typing import Any

from ..arguments import (
    add_params_option,
    add_solver_options,
    backend_from_args,
    finite_float,
    params_from_args,
)
from ..model import MoveError
from ..planner import DEFAULT_OMEGA, REFERENCE_LAWS, Case, MoveProblem
from ..planner.baseline_limits import BASELINE_LAWS

POLY_LAWS = ("poly3", "poly5", "poly7")


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "plan",
        help="plan one point-to-point move",
        description="Plan the duration of one rest-to-rest move x0 → x1 [m]. The polynomial laws are "
        "planned by the chosen solver; the reference laws show the physical limit: 'bang' is the "
        "time-optimal bang–cruise–bang move (min-time only), 'least-energy' the least-energy "
        "limit-respecting profile (full-force ramps, cruise, coast, braking). The baseline laws are what "
        "drives run today, computed by Ruckig under --limits: 'trapezoid' (CiA 402 profile position "
        "mode) and 'scurve' (time-optimal under velocity, acceleration and jerk limits); --t-min "
        "stretches them to that duration.",
    )
    p.add_argument("x0", type=finite_float, help="start position [m], in [0, L]")
    p.add_argument("x1", type=finite_float, help="end position [m], in [0, L]")
    p.add_argument(
        "--law",
        choices=POLY_LAWS + REFERENCE_LAWS + BASELINE_LAWS,
        default="poly5",
        help="motion law: a rest-to-rest polynomial, or a reference law of the physical limit (bang: "
        "bang–cruise–bang minimum time; least-energy: the least-energy profile), or a baseline "
        "(trapezoid, scurve) (default: poly5)",
    )
    p.add_argument(
        "--limits",
        metavar="V,A[,J]",
        default=None,
        help="the baseline's velocity [m/s], acceleration [m/s²] and jerk [m/s³] limits (default: the "
        "[baseline] table of --params, else v_max and the acceleration the torque limit gives there; "
        "the S-curve's jerk defaults to a/0.1 s)",
    )
    p.add_argument(
        "--case",
        choices=[c.value for c in Case],
        default=Case.MIN_TIME.value,
        help="objective: minimum time (eq. 2) or minimum ω·T + (1 − ω)·E (eq. 3) (default: min-time)",
    )
    p.add_argument(
        "--omega",
        type=finite_float,
        default=DEFAULT_OMEGA,
        help=f"time weight ω of the min-time-energy case, in [0, 1] (default {DEFAULT_OMEGA})",
    )
    p.add_argument("--t-min", type=finite_float, default=None, metavar="S", help="lower duration bound [s]")
    p.add_argument("--t-max", type=finite_float, default=None, metavar="S", help="upper duration bound [s]")
    add_params_option(p)
    add_solver_options(p)
    p.add_argument("--json", action="store_true", help="print the result as one JSON object")
    p.set_defaults(func=run)


def _reference(args: argparse.Namespace, problem: MoveProblem) -> dict[str, Any]:
    from ..planner.reference_laws import plan_reference

    params = params_from_args(args)
    problem.check_stroke(params)
    plan = plan_reference(
        args.law,
        problem.distance_m,
        params,
        minimise_time=problem.case is Case.MIN_TIME,
        omega=problem.omega,
        w0=problem.w0,
        t_min_s=problem.t_min_s,
        t_max_s=problem.t_max_s,
    )
    prof = plan.profile
    return {
        "solver": "reference",
        "status": "converged",
        "duration_s": plan.duration_s,
        "objective": plan.objective,
        "energy_j": plan.energy_j,
        "iterations": 0,
        "solve_time_ms": plan.solve_time_s * 1e3,
        "max_violation": 0.0,
        "message": f"{args.law} profile (a reference law: solved by its own method, not by --solver)",
        "certificate": {},
        "profile": {
            "cruise_velocity_m_s": prof.cruise_velocity_m_s,
            "brake_velocity_m_s": prof.brake_velocity_m_s,
            "accel_time_s": prof.accel_time_s,
            "cruise_time_s": prof.cruise_time_s,
            "coast_time_s": prof.coast_time_s,
            "brake_time_s": prof.brake_time_s,
            "switch_fraction": prof.switch_fraction,
        },
    }


def _baseline(args: argparse.Namespace) -> dict[str, Any]:
    from ..planner.baseline_laws import plan_baseline
    from ..planner.baseline_limits import baseline_limits

    params, limits = baseline_limits(args.params, args.limits)
    plan = plan_baseline(args.law, args.x0, args.x1, limits, params, args.t_min)
    return {"x0_m": args.x0, "x1_m": args.x1, "law": args.law, "case": Case.MIN_TIME.value, "omega": None} | (
        plan.to_dict()
    )


def run(args: argparse.Namespace) -> int:
    if args.law in BASELINE_LAWS:
        return _print(args, _baseline(args))
    if args.limits is not None:
        raise MoveError(
            f"--limits belongs to the baseline laws ({', '.join(BASELINE_LAWS)}), not to {args.law}"
        )
    params = params_from_args(args)
    law = args.law if args.law in POLY_LAWS else "poly5"  # MoveProblem validates bounds and ω
    problem = MoveProblem(
        args.x0, args.x1, law, Case(args.case), omega=args.omega, t_min_s=args.t_min, t_max_s=args.t_max
    )
    head = {
        "x0_m": problem.x0_m,
        "x1_m": problem.x1_m,
        "law": args.law,
        "case": problem.case.value,
        "omega": problem.omega if problem.case is Case.MIN_TIME_ENERGY else None,
    }
    if args.law in REFERENCE_LAWS:
        out = head | _reference(args, problem)
    else:
        backend = backend_from_args(args)
        backend.prepare(problem, params)
        r = backend.solve(problem, params)
        out = head | {
            "solver": r.solver,
            "status": r.status.value,
            "duration_s": r.duration_s,
            "objective": r.objective,
            "energy_j": r.energy_j,
            "iterations": r.iterations,
            "solve_time_ms": r.solve_time_s * 1e3,
            "max_violation": r.max_violation,
            "message": r.message,
            "certificate": r.certificate.to_dict() if r.certificate is not None else {},
        }
    return _print(args, out)


def _print(args: argparse.Namespace, out: dict[str, Any]) -> int:
    if args.json:
        print(json.dumps(out))
    else:
        for k, v in out.items():
            print(f"{k:>14}: {v}")
    return 0
