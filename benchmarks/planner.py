"""Planner: per-solve latency of the exact back-end against IPOPT (cap 10) on the same random moves.

Default run (``axisflow bench planner``): ``--moves`` random moves (laws and both cases in
turn, the parameters' energy accounting; a tenth very short, some full-stroke), each solved by
``exact`` and by ``ipopt`` with the paper's cap of 10 iterations. Two latencies per back-end:

* solve: the solver's own time — ``solve_exact`` (duration and certificate) and IPOPT's CasADi call;
  the figure the goals refer to;
* result: the whole ``PlanResult`` a caller of ``backend.solve`` gets — the solve plus the common
  scoring (energy, the 1 kHz limit check; IPOPT also its feasibility pre-check).

``--json`` prints ``{"moves", "exact": {"p50_us", "p99_us"}, "ipopt": {"p50_us", "p99_us"},
"speedup_p50"}`` (solve latencies).

``--agreement`` (the full study, 10 000 moves by default; its run time is in docs/planner.md): every law, both
cases and all three accountings in turn; ``exact`` against a converged IPOPT (max_iter 1000,
tol 1e-10, no limit margin, 2000 nodes), against IPOPT capped at 10 iterations (the paper's
setting: how often and by how much it falls short of the optimum, the data of Fig. 4b) and against
the same IPOPT uncapped (the share of the shortfall that is the cap's), plus the Fig. 4b sweep of
the iteration cap for d = 0.4 m, poly5. Limits are judged independently of the exact solver, on a
dense grid of 20 001 points per move; where exact and the converged IPOPT differ by more than
1e-6 in duration, a brute-force minimisation of the precise energy integral (bounded Brent on
``move_energy``) decides which is right.
"""

from __future__ import annotations

import argparse
import gc
import json
import math
import time
from collections import Counter
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from axisflow.planner import Case, MoveProblem, make_backend
from axisflow.planner.errors import InfeasibleMoveError

from axisflow.arguments import add_params_option, non_negative_int, params_from_args, positive_int

if TYPE_CHECKING:  # the model's numerics and the solvers load when the benchmark runs
    from axisflow.model import AxisParams

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
    """Solve the same moves with both back-ends; per-solve latencies [µs] (see the module doc)."""
    from axisflow.planner.exact import solve_exact

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
        exact.solve(p, params)
    t: dict[str, list[float]] = {"exact": [], "exact_result": [], "ipopt": [], "ipopt_result": []}
    by_kind: dict[str, list[float]] = {}
    gc.collect()
    gc.disable()  # as timeit does: a collection pause is not the solver's latency
    try:
        _time_all(problems, params, exact, ipopt, t, by_kind)
    finally:
        gc.enable()
    return {
        "moves": len(problems),
        "exact": {"p50_us": _pct(t["exact"], 50), "p99_us": _pct(t["exact"], 99)},
        "ipopt": {"p50_us": _pct(t["ipopt"], 50), "p99_us": _pct(t["ipopt"], 99)},
        "speedup_p50": _pct(t["ipopt"], 50) / _pct(t["exact"], 50),
        "_max_us": {k: max(v) for k, v in t.items()},
        "_result": {
            k: {"p50_us": _pct(t[k], 50), "p99_us": _pct(t[k], 99)} for k in ("exact_result", "ipopt_result")
        },
        "_by_kind": {k: {"p50_us": _pct(v, 50), "p99_us": _pct(v, 99)} for k, v in sorted(by_kind.items())},
        "_accounting": params.energy_accounting.value,
    }


def _print_latency(res: dict[str, Any]) -> None:
    e, i, r, mx = res["exact"], res["ipopt"], res["_result"], res["_max_us"]
    print(f"planner latency, {res['moves']} moves (energy accounting: {res['_accounting']})")
    print(f"{'':<26}{'p50 [µs]':>12}{'p99 [µs]':>12}{'max [µs]':>12}")
    rows = (
        ("exact, solve", e, mx["exact"]),
        ("ipopt (cap 10), solve", i, mx["ipopt"]),
        ("exact, result object", r["exact_result"], mx["exact_result"]),
        ("ipopt (cap 10), result", r["ipopt_result"], mx["ipopt_result"]),
    )
    for name, q, m in rows:
        print(f"{name:<26}{q['p50_us']:>12.1f}{q['p99_us']:>12.1f}{m:>12.1f}")
    print(f"speed-up, solve: p50 {res['speedup_p50']:.0f}×, p99 {i['p99_us'] / e['p99_us']:.0f}×")
    print(
        f"speed-up, result object: p50 {r['ipopt_result']['p50_us'] / r['exact_result']['p50_us']:.0f}×, "
        f"p99 {r['ipopt_result']['p99_us'] / r['exact_result']['p99_us']:.0f}×"
    )
    print("goal (solve): exact p50 ≤ 50 µs, p99 ≤ 200 µs, ≥ 100× IPOPT")
    print("exact solve by case/law:")
    for k, v in res["_by_kind"].items():
        print(f"  {k:<22} p50 {v['p50_us']:8.1f} µs   p99 {v['p99_us']:8.1f} µs")


def _time_all(problems, params, exact, ipopt, t, by_kind) -> None:  # noqa: ANN001
    """Time every exact solve and result, then every IPOPT result (its solve time is inside it)."""
    from axisflow.planner.exact import solve_exact

    for p in problems:
        t0 = time.perf_counter()
        solve_exact(p, params)
        dt = (time.perf_counter() - t0) * 1e6
        t["exact"].append(dt)
        by_kind.setdefault(f"{p.case.value}/{p.law.name}", []).append(dt)
    for p in problems:
        t0 = time.perf_counter()
        exact.solve(p, params)
        t["exact_result"].append((time.perf_counter() - t0) * 1e6)
    for p in problems:
        t0 = time.perf_counter()
        r = ipopt.solve(p, params)
        t["ipopt_result"].append((time.perf_counter() - t0) * 1e6)
        t["ipopt"].append(r.solve_time_s * 1e6)


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
    mismatch_brute_force_agrees: int = 0
    """among mismatches: the brute-force optimum's J is not below exact's (to 1e-12 relative)"""
    cap_statuses: Counter | None = None
    cap_short: int = 0
    """cap-10 objective above exact by more than 1e-6 relative"""
    cap_violating: int = 0
    cap_short_of_uncapped: int = 0
    """cap-10 objective above the same IPOPT's uncapped objective by more than 1e-6 relative"""
    cap_vs_uncapped: list | None = None
    cap_excess: list | None = None
    max_rel_dT: float = 0.0
    worst: dict | None = None


_DENSE_U = np.linspace(0.0, 1.0, 20_001)


def _dense_violation(problem: MoveProblem, params: AxisParams, duration_s: float) -> float:
    """Relative excess of the peak velocity / motor torque over its limit at a duration, on a dense
    grid of the normalised time (eq. 1 directly, independent of the exact solver's analysis)."""
    from axisflow.model import forward_friction

    law, D = problem.law, abs(problem.distance_m)
    if D == 0.0:
        return 0.0
    v = D / duration_s * law.shape(_DENSE_U, 1)
    a = D / duration_s**2 * law.shape(_DENSE_U, 2)
    force = params.M_eq * a + forward_friction(v, params)
    return max(float(np.abs(force).max()) / params.f_max - 1.0, float(v.max()) / params.v_max - 1.0, 0.0)


def _brute_force(problem: MoveProblem, params: AxisParams, candidates: list[float]) -> tuple[float, float]:
    """(T, J) minimising J = ω·T + (1 − ω)·move_energy over [0.99, 1.01]× the candidates' span by a
    bounded Brent search (the precise energy integral; no solver of ours), kept feasible on the
    dense grid."""
    from axisflow.model import Move, move_energy
    from axisflow.planner.evaluation import objective
    from scipy.optimize import minimize_scalar

    def j(t: float) -> float:
        if _dense_violation(problem, params, t) > 0.0 or not problem.t_min_s <= t <= problem.t_max_s:
            return math.inf
        return objective(problem, t, move_energy(Move(problem.x0_m, problem.x1_m, t, problem.law), params))

    lo = max(min(candidates) * 0.99, problem.t_min_s)
    hi = min(max(candidates) * 1.01, problem.t_max_s)
    res = minimize_scalar(j, bounds=(lo, hi), method="bounded", options={"xatol": 1e-13 * hi})
    best = min([(float(res.x), float(res.fun))] + [(t, j(t)) for t in candidates], key=lambda tj: tj[1])
    return best


def agreement(params: AxisParams, moves: int, seed: int, progress: bool = True) -> dict[str, Any]:
    """The agreement study (see the module docstring). Returns plain JSON data."""
    from axisflow.model import EnergyAccounting

    exact = make_backend("exact")
    ref = make_backend("ipopt", **REFERENCE_IPOPT)
    cap = make_backend("ipopt", max_iter=10)
    uncapped = make_backend("ipopt", max_iter=3000)
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
        t = tallies.setdefault(
            key, _Tally(cap_statuses=Counter(), cap_excess=[], cap_vs_uncapped=[], worst={})
        )
        t.n += 1
        try:
            e = exact.solve(problem, p)
        except InfeasibleMoveError:
            t.infeasible += 1
            continue
        r = ref.solve(problem, p)
        c = cap.solve(problem, p)
        u = uncapped.solve(problem, p)
        if e.max_violation > 0.0 or _dense_violation(problem, p, e.duration_s) > 1e-12:
            t.exact_violations += 1
        if r.success:
            t.ref_converged += 1
            rel = abs(e.duration_s - r.duration_s) / r.duration_s
            if rel <= MATCH_REL:
                t.matched += 1
            else:
                if e.objective < r.objective:
                    t.mismatch_exact_lower += 1
                _bf_t, bf_j = _brute_force(problem, p, [e.duration_s, r.duration_s])
                if e.objective <= bf_j * (1 + 1e-12):
                    t.mismatch_brute_force_agrees += 1
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
            elif r.duration_s < e.duration_s and _dense_violation(problem, p, r.duration_s) > 0.0:
                t.ref_shorter_infeasible += 1
        t.cap_statuses[c.status.value] += 1
        excess = (c.objective - e.objective) / abs(e.objective) if e.objective else 0.0
        t.cap_excess.append(excess)
        if excess > MATCH_REL:
            t.cap_short += 1
        if c.max_violation > 0.0:
            t.cap_violating += 1
        if u.success:
            behind = (c.objective - u.objective) / abs(u.objective) if u.objective else 0.0
            t.cap_vs_uncapped.append(behind)
            if behind > MATCH_REL:
                t.cap_short_of_uncapped += 1
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
            "mismatch_brute_force_agrees_with_exact": t.mismatch_brute_force_agrees,
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
            "cap10_short_of_uncapped": t.cap_short_of_uncapped,
            "cap10_vs_uncapped_rel_max": max(t.cap_vs_uncapped or [0.0]),
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
        f"{'case/accounting':<28}{'moves':>6}{'conv':>6}{'≤1e-6':>7}{'bf=ex':>6}{'max ΔT/T':>10}"
        f"{'no worse':>9}{'ref<ex,over':>12}{'ex viol':>8}{'cap short':>10}{'p50':>9}{'max':>9}"
        f"{'cap viol':>9}{'cap<unc':>8}{'max':>9}"
    )
    print(head)
    for key, g in res["groups"].items():
        print(
            f"{key:<28}{g['moves']:>6}{g['ipopt_converged']:>6}{g['matched_1e-6']:>7}"
            f"{g['mismatch_brute_force_agrees_with_exact']:>6}"
            f"{g['max_rel_duration_difference']:>10.1e}{g['exact_no_worse']:>9}"
            f"{g['ipopt_shorter_but_over_a_limit']:>12}{g['exact_limit_violations']:>8}"
            f"{g['cap10_short_of_optimum']:>10}{g['cap10_shortfall_rel_p50']:>9.1e}"
            f"{g['cap10_shortfall_rel_max']:>9.1e}{g['cap10_over_a_limit']:>9}"
            f"{g['cap10_short_of_uncapped']:>8}{g['cap10_vs_uncapped_rel_max']:>9.1e}"
        )
    print(
        "conv: converged reference IPOPT; ≤1e-6: durations equal to 1e-6; bf=ex: of the others, those where "
        "a brute-force search of the precise objective finds nothing below exact's; no worse: exact's "
        "objective ≤ the reference's; ref<ex,over: reference shorter but over a limit (dense grid); "
        "ex viol: exact over a limit; cap short: IPOPT cap 10 above the optimum by > 1e-6 (p50/max of "
        "the excess); cap<unc: IPOPT cap 10 above the same IPOPT uncapped by > 1e-6 (the cap's own share)"
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
        from axisflow.model.files import write_atomic

        write_atomic(args.out, json.dumps(res, indent=1) + "\n")
    return 0
