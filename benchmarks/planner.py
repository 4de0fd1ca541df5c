"""Planner: per-solve latency of the exact back-end against IPOPT (cap 10) on the same random moves.

Default run (``axisflow bench planner``, ~15 s): ``--moves`` random moves (laws and both cases in
turn, the parameters' energy accounting; a tenth very short, some full-stroke), each solved by
``exact`` and by ``ipopt`` with the paper's cap of 10 iterations. Latency is the solver's own time
(``PlanResult.solve_time_s``: the exact solve; IPOPT's CasADi call), not the common 1 kHz scoring.
``--json`` prints ``{"moves", "exact": {"p50_us", "p99_us"}, "ipopt": {"p50_us", "p99_us"},
"speedup_p50"}``.

``--agreement`` (the full study, 10 000 moves by default; 699 s measured on the 2-core VM): every law, both
cases and all three accountings in turn; ``exact`` against a converged IPOPT (max_iter 1000,
tol 1e-10, no limit margin, 2000 nodes) and against IPOPT capped at 10 iterations (the paper's
setting: how often and by how much it falls short, the data of Fig. 4b), plus the Fig. 4b sweep of
the iteration cap for d = 0.4 m, poly5.
"""

from __future__ import annotations

import argparse
import gc
import json
import math
import time
from collections import Counter
from dataclasses import dataclass
from typing import Any

import numpy as np
from axisflow.model import AxisParams, EnergyAccounting
from axisflow.planner import Case, MoveProblem, make_backend
from axisflow.planner.errors import InfeasibleMoveError
from axisflow.planner.exact_backend import law_model, solve_exact

from axisflow.cli.common import add_params_option, non_negative_int, params_from_args, positive_int

LAWS = ("poly3", "poly5", "poly7")
REFERENCE_IPOPT = {"max_iter": 1000, "tol": 1e-10, "limit_margin": 0.0, "nodes": 2000}
"""the converged IPOPT of the agreement study"""
MATCH_REL = 1e-6


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--moves", type=positive_int, default=None, help="moves (default 2000; 10000 with --agreement)"
    )
    parser.add_argument("--seed", type=non_negative_int, default=0, help="random seed (default 0)")
    parser.add_argument(
        "--agreement",
        action="store_true",
        help="run the agreement study (exact vs converged and capped IPOPT) instead of the latency run",
    )
    parser.add_argument("--out", metavar="FILE", default=None, help="also write the JSON result to FILE")
    add_params_option(parser)


def random_moves(count: int, seed: int, stroke_m: float) -> list[tuple[float, float]]:
    """``count`` moves (x0, x1): uniform in [0, L]; every 10th very short (1e-5…1e-2 m), every 20th
    full-stroke (alternating direction)."""
    rng = np.random.default_rng(seed)
    moves = []
    for i in range(count):
        x0, x1 = (float(x) for x in rng.uniform(0.0, stroke_m, 2))
        if i % 20 == 1:
            x0, x1 = (0.0, stroke_m) if (i // 20) % 2 == 0 else (stroke_m, 0.0)
        elif i % 10 == 3:
            d = float(10 ** rng.uniform(-5, -2)) * (1 if rng.random() < 0.5 else -1)
            x1 = min(max(x0 + d, 0.0), stroke_m)
        moves.append((x0, x1))
    return moves


def _pct(values: list[float], q: float) -> float:
    return float(np.percentile(np.asarray(values), q)) if values else math.nan


# ---- latency ------------------------------------------------------------------------------------
def latency(params: AxisParams, moves: int, seed: int) -> dict[str, Any]:
    """Solve the same moves with both back-ends; per-solve latencies [µs]."""
    problems = []
    for i, (x0, x1) in enumerate(random_moves(moves, seed, params.L)):
        case = Case.MIN_TIME if (i // 3) % 2 == 0 else Case.MIN_TIME_ENERGY
        problems.append(MoveProblem(x0, x1, LAWS[i % 3], case))
    exact = make_backend("exact")
    ipopt = make_backend("ipopt", max_iter=10)
    for law in LAWS:
        for case in Case:
            p = MoveProblem(0.1, 0.5, law, case)
            exact.prepare(p, params)
            ipopt.prepare(p, params)
    for p in problems[:50]:  # warm caches and the interpreter
        solve_exact(p, params)
    t_exact: list[float] = []
    by_kind: dict[str, list[float]] = {}
    gc.collect()
    gc.disable()  # as timeit does: a collection pause is not the solver's latency
    try:
        t_ipopt = _time_both(problems, params, ipopt, t_exact, by_kind)
    finally:
        gc.enable()
    return {
        "moves": len(problems),
        "exact": {"p50_us": _pct(t_exact, 50), "p99_us": _pct(t_exact, 99)},
        "ipopt": {"p50_us": _pct(t_ipopt, 50), "p99_us": _pct(t_ipopt, 99)},
        "speedup_p50": _pct(t_ipopt, 50) / _pct(t_exact, 50),
        "_max_us": {"exact": max(t_exact), "ipopt": max(t_ipopt)},
        "_by_kind": {k: {"p50_us": _pct(v, 50), "p99_us": _pct(v, 99)} for k, v in sorted(by_kind.items())},
        "_accounting": params.energy_accounting.value,
    }


def _print_latency(res: dict[str, Any]) -> None:
    e, i = res["exact"], res["ipopt"]
    print(f"planner latency, {res['moves']} moves (energy accounting: {res['_accounting']})")
    print(f"{'solver':<14}{'p50 [µs]':>12}{'p99 [µs]':>12}{'max [µs]':>12}")
    print(f"{'exact':<14}{e['p50_us']:>12.1f}{e['p99_us']:>12.1f}{res['_max_us']['exact']:>12.1f}")
    print(f"{'ipopt (cap 10)':<14}{i['p50_us']:>12.1f}{i['p99_us']:>12.1f}{res['_max_us']['ipopt']:>12.1f}")
    print(f"speed-up p50: {res['speedup_p50']:.0f}×   p99: {i['p99_us'] / e['p99_us']:.0f}×")
    print("goal: exact p50 ≤ 50 µs, p99 ≤ 200 µs, ≥ 100× IPOPT")
    print("exact by case/law:")
    for k, v in res["_by_kind"].items():
        print(f"  {k:<22} p50 {v['p50_us']:8.1f} µs   p99 {v['p99_us']:8.1f} µs")


def _time_both(problems, params, ipopt, t_exact, by_kind):  # noqa: ANN001
    """Time every exact solve (appending µs to ``t_exact`` and ``by_kind``), then every IPOPT solve."""
    for p in problems:
        t0 = time.perf_counter()
        solve_exact(p, params)
        dt = (time.perf_counter() - t0) * 1e6
        t_exact.append(dt)
        by_kind.setdefault(f"{p.case.value}/{p.law.name}", []).append(dt)
    return [ipopt.solve(p, params).solve_time_s * 1e6 for p in problems]


# ---- agreement ----------------------------------------------------------------------------------
@dataclass
class _Tally:
    n: int = 0
    ref_converged: int = 0
    matched: int = 0
    """|T_exact − T_ref| ≤ 1e-6·T_ref among converged references"""
    mismatch_exact_lower: int = 0
    """|ΔT|/T > 1e-6 but the exact objective is lower (IPOPT's discretised energy moved its optimum)"""
    exact_better_or_equal: int = 0
    """objective(exact) ≤ objective(ref)·(1 + 1e-9) among converged references"""
    ref_shorter_infeasible: int = 0
    """reference shorter than exact, and then over a limit in continuous time"""
    exact_violations: int = 0
    infeasible: int = 0
    cap_statuses: Counter | None = None
    cap_short: int = 0
    """cap-10 objective above exact by more than 1e-6 relative"""
    cap_violating: int = 0
    cap_excess: list | None = None
    max_rel_dT: float = 0.0
    worst: dict | None = None


def _continuous_violation(problem: MoveProblem, params: AxisParams, duration_s: float) -> float:
    """Relative excess of the continuous-time peak torque/velocity over the limit at a duration."""
    lm = law_model(problem.law, params)
    D = abs(problem.distance_m)
    if D == 0.0:
        return 0.0
    f, _, _ = lm.peak_force(1.0 / duration_s, D, lm.u_acc_peak)
    v = problem.law.peak_velocity_factor * D / duration_s
    return max(f / params.f_max - 1.0, v / params.v_max - 1.0, 0.0)


def agreement(params: AxisParams, moves: int, seed: int, progress: bool = True) -> dict[str, Any]:
    """The agreement study (see the module docstring). Returns plain JSON data."""
    exact = make_backend("exact")
    ref = make_backend("ipopt", **REFERENCE_IPOPT)
    cap = make_backend("ipopt", max_iter=10)
    tallies: dict[str, _Tally] = {}
    t_start = time.perf_counter()
    accountings = list(EnergyAccounting)
    for i, (x0, x1) in enumerate(random_moves(moves, seed, params.L)):
        law = LAWS[i % 3]
        case = Case.MIN_TIME if (i // 3) % 2 == 0 else Case.MIN_TIME_ENERGY
        acc = accountings[(i // 6) % 3]
        p = params.replace(energy_accounting=acc)
        problem = MoveProblem(x0, x1, law, case)
        key = f"{case.value}/{acc.value}"
        t = tallies.setdefault(key, _Tally(cap_statuses=Counter(), cap_excess=[], worst={}))
        t.n += 1
        try:
            e = exact.solve(problem, p)
        except InfeasibleMoveError:
            t.infeasible += 1
            continue
        r = ref.solve(problem, p)
        c = cap.solve(problem, p)
        if e.max_violation > 0.0 or _continuous_violation(problem, p, e.duration_s) > 1e-12:
            t.exact_violations += 1
        if r.success:
            t.ref_converged += 1
            rel = abs(e.duration_s - r.duration_s) / r.duration_s
            if rel <= MATCH_REL:
                t.matched += 1
            elif e.objective < r.objective:
                t.mismatch_exact_lower += 1
            if rel > t.max_rel_dT:
                t.max_rel_dT = rel
                t.worst = {
                    "x0_m": x0,
                    "x1_m": x1,
                    "law": law,
                    "exact_s": e.duration_s,
                    "ipopt_s": r.duration_s,
                }
            if e.objective <= r.objective * (1 + 1e-9):
                t.exact_better_or_equal += 1
            elif r.duration_s < e.duration_s and _continuous_violation(problem, p, r.duration_s) > 0.0:
                t.ref_shorter_infeasible += 1
        t.cap_statuses[c.status.value] += 1
        excess = (c.objective - e.objective) / abs(e.objective) if e.objective else 0.0
        t.cap_excess.append(excess)
        if excess > MATCH_REL:
            t.cap_short += 1
        if c.max_violation > 0.0:
            t.cap_violating += 1
        if progress and (i + 1) % 500 == 0:
            print(f"  {i + 1}/{moves} moves, {time.perf_counter() - t_start:.0f} s", flush=True)
    groups = {}
    for key, t in sorted(tallies.items()):
        ex = t.cap_excess or []
        shortfalls = [x for x in ex if x > MATCH_REL]
        groups[key] = {
            "moves": t.n,
            "infeasible": t.infeasible,
            "ipopt_converged": t.ref_converged,
            "matched_1e-6": t.matched,
            "mismatch_exact_objective_lower": t.mismatch_exact_lower,
            "max_rel_duration_difference": t.max_rel_dT,
            "worst_move": t.worst,
            "exact_no_worse": t.exact_better_or_equal,
            "ipopt_shorter_but_over_a_limit": t.ref_shorter_infeasible,
            "exact_limit_violations": t.exact_violations,
            "cap10_statuses": dict(t.cap_statuses or {}),
            "cap10_short_of_optimum": t.cap_short,
            "cap10_shortfall_rel_p50": _pct(shortfalls, 50),
            "cap10_shortfall_rel_p99": _pct(shortfalls, 99),
            "cap10_shortfall_rel_max": max(shortfalls, default=0.0),
            "cap10_over_a_limit": t.cap_violating,
        }
    return {
        "moves": moves,
        "seed": seed,
        "reference_ipopt": REFERENCE_IPOPT,
        "groups": groups,
        "fig4b": fig4b(params),
        "wall_time_s": time.perf_counter() - t_start,
    }


def fig4b(params: AxisParams, caps: range = range(1, 21)) -> dict[str, Any]:
    """Fig. 4b: IPOPT's duration, solve time and limit violation against its iteration cap, for the
    poly5 move of d = 0.4 m (0.2 → 0.6 m), both cases, next to the exact optimum."""
    out: dict[str, Any] = {}
    for case in Case:
        problem = MoveProblem(0.2, 0.6, "poly5", case)
        e = make_backend("exact").solve(problem, params)
        rows = []
        for k in caps:
            b = make_backend("ipopt", max_iter=k)
            b.prepare(problem, params)
            r = b.solve(problem, params)
            rows.append(
                {
                    "max_iter": k,
                    "status": r.status.value,
                    "duration_s": r.duration_s,
                    "objective_excess_rel": (r.objective - e.objective) / e.objective,
                    "solve_time_ms": r.solve_time_s * 1e3,
                    "max_violation": r.max_violation,
                }
            )
        out[case.value] = {
            "exact_duration_s": e.duration_s,
            "exact_solve_time_ms": e.solve_time_s * 1e3,
            "caps": rows,
        }
    return out


def _print_agreement(res: dict[str, Any]) -> None:
    print(f"agreement study: {res['moves']} moves, seed {res['seed']}, {res['wall_time_s']:.0f} s")
    print(f"reference IPOPT: {res['reference_ipopt']}")
    head = (
        f"{'case/accounting':<28}{'moves':>6}{'conv':>6}{'≤1e-6':>7}{'max ΔT/T':>10}{'no worse':>9}"
        f"{'ref<ex,over':>12}{'ex viol':>8}{'cap short':>10}{'p50':>9}{'max':>9}{'cap viol':>9}"
    )
    print(head)
    for key, g in res["groups"].items():
        print(
            f"{key:<28}{g['moves']:>6}{g['ipopt_converged']:>6}{g['matched_1e-6']:>7}"
            f"{g['max_rel_duration_difference']:>10.1e}{g['exact_no_worse']:>9}"
            f"{g['ipopt_shorter_but_over_a_limit']:>12}{g['exact_limit_violations']:>8}"
            f"{g['cap10_short_of_optimum']:>10}{g['cap10_shortfall_rel_p50']:>9.1e}"
            f"{g['cap10_shortfall_rel_max']:>9.1e}{g['cap10_over_a_limit']:>9}"
        )
    print("Fig. 4b (poly5, 0.2 → 0.6 m): IPOPT against its iteration cap")
    for case, data in res["fig4b"].items():
        print(
            f"  {case}: exact {data['exact_duration_s']:.6f} s in {data['exact_solve_time_ms'] * 1e3:.0f} µs"
        )
        for row in data["caps"]:
            print(
                f"    cap {row['max_iter']:>2}: {row['status']:<15} T = {row['duration_s']:.6f} s  "
                f"excess {row['objective_excess_rel']:+.2e}  {row['solve_time_ms']:.2f} ms  "
                f"violation {row['max_violation']:.1e}"
            )


def run(args: argparse.Namespace) -> int:
    params = params_from_args(args)
    if args.agreement:
        res = agreement(params, args.moves or 10_000, args.seed, progress=not args.json)
        if args.json:
            print(json.dumps(res))
        else:
            _print_agreement(res)
    else:
        res = latency(params, args.moves or 2000, args.seed)
        if args.json:
            print(json.dumps({k: v for k, v in res.items() if not k.startswith("_")}))
        else:
            _print_latency(res)
    if args.out:
        from axisflow.files import write_atomic

        write_atomic(args.out, json.dumps(res, indent=1) + "\n")
    return 0
