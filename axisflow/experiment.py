"""The paper's 100-way-point experiment (Sect. 3–4, Table 2), offline.

Way points are drawn uniformly in [0, L] with a recorded seed; the same way points serve every case
and law. Each of the 99 consecutive moves is planned as the paper did (one solve per move), and the
rows report total time, model energy, solve times and the worst 1 kHz limit violation. The online
experiment (on the simulated drive over Zenoh) fills ``energy_measured_j`` later.
"""

from __future__ import annotations

import dataclasses
import math
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, field
from itertools import pairwise
from typing import Any

import numpy as np

from .model import AxisParams, MoveError, polynomial_law
from .paper import PAPER_TABLE2, PAPER_WAYPOINTS
from .planner import DEFAULT_OMEGA, Case, MoveProblem, PlannerBackend, PlanResult
from .planner.reference_laws import least_energy, time_optimal

LAWS: tuple[str, ...] = ("poly3", "poly5", "poly7")
CASES: tuple[Case, ...] = (Case.MIN_TIME, Case.MIN_TIME_ENERGY)
MAX_WAYPOINTS = 100_000


def draw_waypoints(seed: int, count: int, stroke_m: float) -> np.ndarray:
    """``count`` way points uniform in [0, L] from numpy's default generator seeded with ``seed``."""
    if isinstance(count, bool) or not isinstance(count, int) or not 2 <= count <= MAX_WAYPOINTS:
        raise MoveError(f"waypoints = {count!r} must be an integer in [2, {MAX_WAYPOINTS}]")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise MoveError(f"seed = {seed!r} must be a non-negative integer")
    return np.random.default_rng(seed).uniform(0.0, stroke_m, count)


@dataclass(frozen=True)
class MoveLimits:
    """The physical limit of one move: the time-optimal (bang–cruise–bang) duration and the least
    energy of a limit-respecting profile at the planned duration (planner/reference_laws.py)."""

    time_limit_s: float
    energy_limit_j: float


@dataclass(frozen=True)
class ExperimentRow:
    """One case × law row: the plan of every move between consecutive way points."""

    case: Case
    law: str
    solver: str
    omega: float | None
    results: tuple[PlanResult, ...] = field(repr=False)
    limits: tuple[MoveLimits, ...] | None = field(default=None, repr=False)
    """per move, when computed (see :func:`physical_limits`)"""

    @property
    def objective_total(self) -> float:
        """Σ of each move's objective (eq. 2 or 3), the quantity each solve minimises."""
        return math.fsum(r.objective for r in self.results)

    @property
    def time_limit_ratio(self) -> float | None:
        """T_poly/T_limit over the row: total planned time over total time-optimal time."""
        if self.limits is None:
            return None
        return self.total_time_s / math.fsum(m.time_limit_s for m in self.limits)

    @property
    def energy_limit_ratio(self) -> float | None:
        """E_poly/E_limit over the row: total model energy over total least energy at the same
        durations."""
        if self.limits is None:
            return None
        return self.energy_model_j / math.fsum(m.energy_limit_j for m in self.limits)

    @property
    def durations_s(self) -> list[float]:
        return [r.duration_s for r in self.results]

    @property
    def total_time_s(self) -> float:
        return math.fsum(self.durations_s)

    @property
    def energy_model_j(self) -> float:
        return math.fsum(r.energy_j for r in self.results)

    @property
    def solve_times_ms(self) -> np.ndarray:
        return np.array([r.solve_time_s * 1e3 for r in self.results])

    @property
    def max_violation(self) -> float:
        return max((r.max_violation for r in self.results), default=0.0)

    @property
    def status_counts(self) -> dict[str, int]:
        return dict(Counter(r.status.value for r in self.results))

    def to_json(self) -> dict[str, Any]:
        times = self.solve_times_ms
        return {
            "case": self.case.value,
            "law": self.law,
            "solver": self.solver,
            "omega": self.omega,
            "durations_s": self.durations_s,
            "total_time_s": self.total_time_s,
            "energy_model_j": self.energy_model_j,
            "energy_measured_j": None,
            "energy_error_pct": None,
            "t_opt_ms_mean": float(times.mean()),
            "t_opt_ms_std": float(times.std(ddof=1)) if times.size > 1 else 0.0,
            "max_violation": self.max_violation,
        }

    def extra_json(self) -> dict[str, Any]:
        """The row's comparison with the physical limit (issue 3), written to ``limits.json`` so
        that ``table2.json`` keeps exactly the keys of issue 2."""
        out: dict[str, Any] = {
            "case": self.case.value,
            "law": self.law,
            "solver": self.solver,
            "objective_total": self.objective_total,
            "statuses": self.status_counts,
        }
        if self.limits is not None:
            out.update(
                {
                    "t_limit_s": [m.time_limit_s for m in self.limits],
                    "e_limit_j": [m.energy_limit_j for m in self.limits],
                    "t_limit_ratios": [
                        r.duration_s / m.time_limit_s if m.time_limit_s > 0 else None  # a zero move
                        for r, m in zip(self.results, self.limits, strict=True)
                    ],
                    "e_limit_ratios": [
                        r.energy_j / m.energy_limit_j if m.energy_limit_j > 0 else None
                        for r, m in zip(self.results, self.limits, strict=True)
                    ],
                    "total_time_limit_s": math.fsum(m.time_limit_s for m in self.limits),
                    "energy_limit_j": math.fsum(m.energy_limit_j for m in self.limits),
                    "t_limit_ratio": self.time_limit_ratio,
                    "e_limit_ratio": self.energy_limit_ratio,
                }
            )
        return out


@dataclass(frozen=True)
class ExperimentResult:
    seed: int
    waypoints_m: np.ndarray
    params: AxisParams
    rows: tuple[ExperimentRow, ...]

    def to_json(self) -> dict[str, Any]:
        return {
            "seed": self.seed,
            "waypoints_m": [float(w) for w in self.waypoints_m],
            "params": self.params.to_dict(),
            "rows": [row.to_json() for row in self.rows],
        }

    def limits_json(self) -> dict[str, Any]:
        """Per row: objective total, statuses and, when computed, T_limit/E_limit per move and in
        total (``limits.json``)."""
        return {"seed": self.seed, "rows": [row.extra_json() for row in self.rows]}


def plan_row(
    waypoints_m: np.ndarray,
    case: Case,
    law: str,
    backend: PlannerBackend,
    params: AxisParams,
    omega: float,
) -> ExperimentRow:
    """Plan every move between consecutive way points, one solve per move."""
    problems = [
        MoveProblem(float(a), float(b), polynomial_law(law), case, omega=omega)
        for a, b in pairwise(waypoints_m)
    ]
    for problem in problems:
        problem.check_stroke(params)
    backend.prepare(problems[0], params)
    results = tuple(backend.solve(problem, params) for problem in problems)
    return ExperimentRow(case, law, backend.name, omega if case is Case.MIN_TIME_ENERGY else None, results)


def physical_limits(row: ExperimentRow, params: AxisParams) -> ExperimentRow:
    """The row with its per-move physical limits: T_limit (bang–cruise–bang) and E_limit (least
    energy at the move's planned duration, under the parameters' accounting)."""
    limits = []
    for r in row.results:
        d = r.problem.distance_m
        t_lim = time_optimal(d, params).duration_s
        e_lim = least_energy(d, max(r.duration_s, t_lim), params).energy(params.energy_accounting)
        limits.append(MoveLimits(t_lim, e_lim))
    return dataclasses.replace(row, limits=tuple(limits))


def run_offline(
    params: AxisParams,
    backend: PlannerBackend,
    *,
    seed: int = 0,
    waypoints: int = PAPER_WAYPOINTS,
    omega: float = DEFAULT_OMEGA,
    laws: Sequence[str] = LAWS,
    cases: Sequence[Case] = CASES,
    limits: bool = True,
) -> ExperimentResult:
    """Plan the experiment's moves for each case × law on the same way points (and, with
    ``limits``, compare each move with the physical limit)."""
    if not 0.0 <= omega <= 1.0 or not math.isfinite(omega):
        raise MoveError(f"omega = {omega} is outside [0, 1]")
    points = draw_waypoints(seed, waypoints, params.L)
    rows = tuple(plan_row(points, case, law, backend, params, omega) for case in cases for law in laws)
    if limits:
        rows = tuple(physical_limits(row, params) for row in rows)
    return ExperimentResult(seed, points, params, rows)


def _dev(ours: float, paper: float) -> str:
    return f"{(ours - paper) / paper * 100.0:+.1f}"


def table_markdown(result: ExperimentResult) -> str:
    """Table 2 side by side with the paper (deviations only when the way point count matches)."""
    compare = len(result.waypoints_m) == PAPER_WAYPOINTS
    lines = [
        f"# Table 2, offline ({len(result.waypoints_m)} way points, seed {result.seed}, "
        f"energy accounting: {result.params.energy_accounting.value})",
        "",
        "| case | law | solver | T [s] | paper T [s] | ΔT [%] | E_th [J] | paper E_th [J] | ΔE [%] "
        "| t_opt [ms] | paper t_opt [ms] | statuses | max violation |",
        "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|",
    ]
    for row in result.rows:
        paper = PAPER_TABLE2.get((row.case.value, row.law))
        times = row.solve_times_ms
        std = times.std(ddof=1) if times.size > 1 else 0.0
        p_t = p_e = d_t = d_e = p_opt = "–"
        if paper is not None and compare:
            p_t, p_e = f"{paper.total_time_s:.2f}", f"{paper.energy_model_j:.0f}"
            d_t, d_e = (
                _dev(row.total_time_s, paper.total_time_s),
                _dev(row.energy_model_j, paper.energy_model_j),
            )
            p_opt = f"{paper.t_opt_ms_mean:.2f} ± {paper.t_opt_ms_std:.2f}"
        statuses = ", ".join(f"{k} {v}" for k, v in sorted(row.status_counts.items()))
        lines.append(
            f"| {row.case.value} | {row.law} | {row.solver} | {row.total_time_s:.2f} | {p_t} | {d_t} "
            f"| {row.energy_model_j:.0f} | {p_e} | {d_e} | {times.mean():.3f} ± {std:.3f} | {p_opt} "
            f"| {statuses} | {row.max_violation:.2e} |"
        )
    if any(row.limits is not None for row in result.rows):
        lines += [
            "",
            "## Against the physical limit",
            "",
            "| case | law | solver | objective Σ | T [s] | T_limit [s] | T/T_limit | E_th [J] | E_limit [J] "
            "| E/E_limit |",
            "|---|---|---|---:|---:|---:|---:|---:|---:|---:|",
        ]
        for row in result.rows:
            if row.limits is None:
                continue
            t_lim = math.fsum(m.time_limit_s for m in row.limits)
            e_lim = math.fsum(m.energy_limit_j for m in row.limits)
            lines.append(
                f"| {row.case.value} | {row.law} | {row.solver} | {row.objective_total:.2f} "
                f"| {row.total_time_s:.2f} | {t_lim:.2f} | {row.time_limit_ratio:.3f} "
                f"| {row.energy_model_j:.0f} | {e_lim:.0f} | {row.energy_limit_ratio:.3f} |"
            )
        lines += [
            "",
            "T_limit: Σ of each move's time-optimal (bang–cruise–bang) duration under the same velocity and "
            "torque limits and the full friction model; E_limit: Σ of the least energy of a limit-respecting "
            "profile (full-force ramps, cruise, coast, full braking) at each move's planned duration.",
        ]
    lines += [
        "",
        "T: total execution time of the moves; E_th: model energy (eq. 3) under the accounting above; "
        "t_opt: wall time of each solve, mean ± std (measured on this machine); max violation: worst "
        "relative excess over the velocity or torque limit at the 1 kHz execution samples.",
    ]
    return "\n".join(lines) + "\n"
