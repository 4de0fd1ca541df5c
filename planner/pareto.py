"""The time–energy trade-off: sweep ω of case 2 over a sequence of way points.

For each ω ∈ [0, 1] every move between consecutive way points is planned for
min ω·T + (1 − ω)·E(T) with the exact back-end, and the totals (ΣT, ΣE) form one point of the curve
of a law. ω = 1 is the fastest feasible plan inside the case-2 bounds, ω = 0 the least energy (the
slowest allowed moves). Because each move is solved to its global optimum, every point is on the
law's Pareto front: no plan of the same law is both faster and cheaper in total (a weighted-sum
sweep finds the convex part of the front).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from itertools import pairwise
from typing import Any

import numpy as np

from ..model import AxisParams, MoveError, polynomial_law
from .backend import PlannerBackend
from .exact import solve_exact
from .problem import Case, MoveProblem
from .reference_laws import time_optimal

DEFAULT_OMEGAS: tuple[float, ...] = tuple(
    float(w)
    for w in np.unique(
        np.round(np.concatenate([np.linspace(0.0, 1.0, 21), [0.96, 0.97, 0.98, 0.985, 0.99, 0.995]]), 10)
    )
)
"""ω from 0 to 1 in steps of 0.05, denser above 0.95, where the total time falls from minutes to the
minimum-time total (the knee of the curve)"""


@dataclass(frozen=True)
class ParetoPoint:
    """Totals over all moves for one ω."""

    omega: float
    total_time_s: float
    total_energy_j: float
    objective_total: float


@dataclass(frozen=True)
class ParetoCurve:
    law: str
    points: tuple[ParetoPoint, ...]

    def to_json(self) -> dict[str, Any]:
        return {
            "law": self.law,
            "omega": [p.omega for p in self.points],
            "total_time_s": [p.total_time_s for p in self.points],
            "total_energy_j": [p.total_energy_j for p in self.points],
            "objective_total": [p.objective_total for p in self.points],
        }


def check_omegas(omegas: Sequence[float]) -> tuple[float, ...]:
    """Validate a sweep: finite, inside [0, 1], at least one value; returned sorted."""
    if len(omegas) == 0:
        raise MoveError("the ω sweep is empty: give at least one ω in [0, 1]")
    for w in omegas:
        if not math.isfinite(w) or not 0.0 <= w <= 1.0:
            raise MoveError(f"omega = {w} is outside [0, 1]")
    return tuple(sorted(float(w) for w in omegas))


def sweep(
    waypoints_m: Sequence[float],
    law: str,
    params: AxisParams,
    omegas: Sequence[float] = DEFAULT_OMEGAS,
    t_min_s: float | None = None,
    t_max_s: float | None = None,
    backend: PlannerBackend | None = None,
) -> ParetoCurve:
    """Total time and energy of the case-2 plans through ``waypoints_m`` for each ω (by default with
    the exact solver; another ``backend``, e.g. IPOPT, gives its own, possibly off-front, points)."""
    poly = polynomial_law(law)
    solve = solve_exact if backend is None else backend.solve
    points = []
    for w in check_omegas(omegas):
        times, energies, objectives = [], [], []
        for a, b in pairwise(waypoints_m):
            problem = MoveProblem(float(a), float(b), poly, Case.MIN_TIME_ENERGY, w, t_min_s, t_max_s)
            sol = solve(problem, params)
            times.append(sol.duration_s)
            energies.append(sol.energy_j)
            objectives.append(sol.objective)
        points.append(ParetoPoint(w, math.fsum(times), math.fsum(energies), math.fsum(objectives)))
    return ParetoCurve(law, tuple(points))


def time_optimal_point(waypoints_m: Sequence[float], params: AxisParams) -> ParetoPoint:
    """Totals of the time-optimal (bang–cruise–bang) moves: the physical limit of speed (ω = 1)."""
    profiles = [time_optimal(float(b) - float(a), params) for a, b in pairwise(waypoints_m)]
    t = math.fsum(p.duration_s for p in profiles)
    e = math.fsum(p.energy(params.energy_accounting) for p in profiles)
    return ParetoPoint(1.0, t, e, t)
