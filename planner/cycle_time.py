"""A cycle of moves planned for a given cycle time: each move at a given duration, or the ω that meets it.

A cycle is a sequence of rest-to-rest moves (x0_k, x1_k) run back to back; its cycle time is the sum
of their durations. Two ways to spend a cycle time that another profile (a baseline) takes:

* **move by move** (:func:`plan_at_durations`): each move along the polynomial law at exactly the
  duration T_k the other profile takes for it — case 2 with the duration bounds pinned to [T_k, T_k],
  whose only feasible duration is T_k. A move the law cannot make that fast (its torque or velocity
  limit needs longer) takes the fastest duration it can (case 2 with ω = 1 and bounds [T_k, 20 s]), and
  the cycle is longer by the difference (:attr:`CyclePlan.slower_moves`).
* **in total** (:func:`match_cycle_time`): the ω of case 2 whose plans, each move at its own optimum
  of ω·T + (1 − ω)·E(T), add up to the cycle time. Each move's J is convex in T, so its optimum
  T_k(ω) falls as ω rises and the total with it; the ω that meets a total is found by Brent's method. This
  is the least energy the law spends on the whole cycle in that time: ω/(1 − ω) is the Lagrange
  multiplier of the constraint ΣT_k = cycle time on min ΣE_k, and each E_k is convex, so the weighted
  optimum *is* the constrained one (a move may take longer than the other profile's and another
  shorter).

Durations of the ω plans lie in [:data:`CYCLE_T_MIN_S`, the case-2 upper bound 20 s]: down to one drive
tick, since a baseline's short moves take less than the paper's 0.3 s lower bound.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from enum import StrEnum

from ..model import AxisParams, polynomial_law
from ..model.sampling import EXECUTION_PERIOD_S
from .errors import InfeasibleMoveError
from .exact import ExactBackend, solve_exact
from .problem import DEFAULT_TIME_BOUNDS_S, Case, MoveProblem
from .result import PlanResult

CYCLE_T_MIN_S = EXECUTION_PERIOD_S
"""the shortest duration a move of an ω plan may take [s]: one drive tick"""
CYCLE_T_MAX_S = DEFAULT_TIME_BOUNDS_S[Case.MIN_TIME_ENERGY][1]
"""the longest [s]: the paper's case-2 upper bound"""
_BRENT_STEPS = 100
"""the cap of Brent's method on ω (it converges in ~10 steps)"""
_OMEGA_TOL = 1e-13
"""how close to the root Brent's method brings ω (the total then meets the cycle time to ~1e-9)"""
_PLAN_DEADLINE_S = 30.0
"""the deadline of one move's result object here [s]: offline planning, where a loaded machine must
not turn a table build into a refusal"""

Moves = Sequence[tuple[float, float]]
"""a cycle's moves: (x0, x1) [m] each"""


@dataclass(frozen=True)
class CyclePlan:
    """The plans of a cycle's moves (zero moves included, as duration 0)."""

    law: str
    omega: float | None
    """the ω every move was planned with; None for a plan at given durations"""
    results: tuple[PlanResult, ...]
    slower_moves: tuple[int, ...] = ()
    """the moves (by index) that could not take the duration asked of them and take longer"""

    @property
    def total_time_s(self) -> float:
        return math.fsum(r.duration_s for r in self.results)

    @property
    def total_energy_j(self) -> float:
        return math.fsum(r.energy_j for r in self.results)


class MatchStatus(StrEnum):
    MATCHED = "matched"
    """an ω meets the cycle time (ω to 1e-13)"""
    TOO_SLOW = "too-slow"
    """even ω = 1 (each move as fast as the law allows) takes longer than the cycle time"""
    TOO_FAST = "too-fast"
    """even ω = 0 (each move as slow as the bounds allow) is quicker than the cycle time"""


@dataclass(frozen=True)
class OmegaMatch:
    """What :func:`match_cycle_time` found: the ω, its plan, and how close its total came."""

    target_s: float
    status: MatchStatus
    plan: CyclePlan
    iterations: int
    solve_time_s: float

    @property
    def omega(self) -> float:
        assert self.plan.omega is not None
        return self.plan.omega


def _backend() -> ExactBackend:
    return ExactBackend(deadline_s=_PLAN_DEADLINE_S)


def plan_at_durations(moves: Moves, law: str, durations_s: Sequence[float], params: AxisParams) -> CyclePlan:
    """Each move along ``law`` at its duration (see the module docstring: move by move)."""
    poly = polynomial_law(law)
    backend = _backend()
    results, slower = [], []
    for k, ((x0, x1), t) in enumerate(zip(moves, durations_s, strict=True)):
        if t <= 0.0:  # a zero move of the other profile: nothing to run
            results.append(backend.solve(MoveProblem(x0, x1, poly, Case.MIN_TIME_ENERGY), params))
            continue
        try:
            r = backend.solve(MoveProblem(x0, x1, poly, Case.MIN_TIME_ENERGY, t_min_s=t, t_max_s=t), params)
        except InfeasibleMoveError:
            hi = max(t, CYCLE_T_MAX_S)
            r = backend.solve(
                MoveProblem(x0, x1, poly, Case.MIN_TIME_ENERGY, 1.0, t_min_s=t, t_max_s=hi), params
            )
            slower.append(k)
        results.append(r)
    return CyclePlan(law, None, tuple(results), tuple(slower))


def _problems(moves: Moves, law: str, omega: float) -> list[MoveProblem]:
    poly = polynomial_law(law)
    return [
        MoveProblem(x0, x1, poly, Case.MIN_TIME_ENERGY, omega, t_min_s=CYCLE_T_MIN_S, t_max_s=CYCLE_T_MAX_S)
        for x0, x1 in moves
    ]


def cycle_totals(moves: Moves, law: str, omega: float, params: AxisParams) -> tuple[float, float]:
    """(ΣT_k [s], ΣE_k [J]) of the plans at ``omega`` from the bare exact solutions (no 1 kHz scoring):
    a point of the law's Pareto front over the cycle."""
    solutions = [solve_exact(p, params) for p in _problems(moves, law, omega)]
    return math.fsum(s.duration_s for s in solutions), math.fsum(s.energy_j for s in solutions)


def plan_at_omega(moves: Moves, law: str, omega: float, params: AxisParams) -> CyclePlan:
    """Every move along ``law`` at the optimum of ω·T + (1 − ω)·E(T) (durations in
    [:data:`CYCLE_T_MIN_S`, :data:`CYCLE_T_MAX_S`])."""
    backend = _backend()
    return CyclePlan(law, omega, tuple(backend.solve(p, params) for p in _problems(moves, law, omega)))


def match_cycle_time(moves: Moves, law: str, cycle_time_s: float, params: AxisParams) -> OmegaMatch:
    """The ω whose plan of ``moves`` takes ``cycle_time_s`` in total (the module docstring): Brent's
    method on ΣT_k(ω) − cycle time, continuous and non-increasing in ω, to ω within 1e-13."""
    from scipy.optimize import brentq

    t0 = time.perf_counter()
    steps = 0
    if cycle_totals(moves, law, 1.0, params)[0] > cycle_time_s:
        status, omega = MatchStatus.TOO_SLOW, 1.0
    elif cycle_totals(moves, law, 0.0, params)[0] < cycle_time_s:
        status, omega = MatchStatus.TOO_FAST, 0.0
    else:
        status = MatchStatus.MATCHED
        omega, found = brentq(
            lambda w: cycle_totals(moves, law, w, params)[0] - cycle_time_s,
            0.0,
            1.0,
            xtol=_OMEGA_TOL,
            maxiter=_BRENT_STEPS,
            full_output=True,
        )
        steps = found.iterations
    plan = plan_at_omega(moves, law, omega, params)
    return OmegaMatch(cycle_time_s, status, plan, steps, time.perf_counter() - t0)
