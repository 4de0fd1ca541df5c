"""The savings comparison planned on the model: a baseline against axisflow's law at equal cycle time.

For the moves of a cycle (x0_k, x1_k) and the axis's identified model, three runs of the same moves:

* ``baseline`` — each move time-optimal under the baseline's limits (a trapezoid or an S-curve by
  Ruckig, :mod:`axisflow.planner.baseline_laws`); its durations add up to the baseline's cycle time;
* ``equal-time`` — each move along axisflow's law (a polynomial of the paper) at the baseline's duration
  of that move (:func:`~axisflow.planner.cycle_time.plan_at_durations`): the same cycle, move by move;
* ``matched-omega`` — every move at the optimum of case 2, ω·T + (1 − ω)·E, with the ω whose plans
  take the baseline's cycle time in total (:func:`~axisflow.planner.cycle_time.match_cycle_time`): the
  least energy the law spends on the cycle in that time.

Each move is scored on the model the same way whatever its law (:func:`score`): energy by eq. (3) under
the axis's accounting, the peaks of |τ_m| and of the mechanical power F·ẋ, and ∫τ_m² dt (the trend of
the motor's copper losses, which mechanical energy does not count), at the 1 kHz execution samples and
at :data:`SCORE_POINTS` evenly spaced times. For the figure, the law's Pareto front over ω
(:data:`~axisflow.planner.pareto.DEFAULT_OMEGAS`) and both baselines' totals at the same limits.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from ..model import (
    AxisParams,
    Motion,
    Move,
    SampledTrajectory,
    cart_force,
    motor_speed,
    motor_torque,
    polynomial_law,
)
from ..model.limits import execution_times
from ..planner import PlanResult
from ..planner.baseline_laws import BaselinePlan, plan_baseline
from ..planner.baseline_limits import BASELINE_LAWS, BaselineLimits
from ..planner.cycle_time import MatchStatus, Moves, cycle_totals, match_cycle_time, plan_at_durations
from ..planner.pareto import DEFAULT_OMEGAS

RUN_LABELS: tuple[str, ...] = ("baseline", "equal-time", "matched-omega")
"""the three runs, in the order they are planned, run and reported"""
SCORE_POINTS = 2001
"""evenly spaced times of a move at which its peaks are taken besides the 1 kHz samples"""


@dataclass(frozen=True)
class MoveScore:
    """What the model says of one move (see the module docstring)."""

    energy_j: float
    peak_torque_nm: float
    peak_power_w: float
    torque_sq_integral: float
    """∫τ_m² dt over the move [N²·m²·s] (1 kHz samples, trapezoidal rule)"""


def score(motion: Motion, energy_j: float, params: AxisParams) -> MoveScore:
    """A move's peaks and ∫τ_m² dt on the model (its energy computed by its planner)."""
    t = np.concatenate(
        [execution_times(motion.duration_s), np.linspace(0.0, motion.duration_s, SCORE_POINTS)]
    )
    s = motion.sample(t)
    tau = motor_torque(cart_force(s.velocity_m_s, s.acceleration_m_s2, params), params)
    power = tau * motor_speed(s.velocity_m_s, params)
    ticks = execution_times(motion.duration_s).size
    tau_ticks = tau[:ticks]
    sq = float(np.dot(np.diff(t[:ticks]), 0.5 * (tau_ticks[1:] ** 2 + tau_ticks[:-1] ** 2)))
    return MoveScore(energy_j, float(np.max(np.abs(tau))), float(np.max(power)), sq)


@dataclass(frozen=True)
class PlannedMove:
    """One move of a run as planned: what is sent to the bridge and what the model says of it."""

    index: int
    """k for the k-th move of the cycle (from 1)"""
    x0_m: float
    x1_m: float
    duration_s: float
    law: str
    case: str
    solver: str
    omega: float
    status: str
    objective: float
    max_violation: float
    solve_time_s: float
    score: MoveScore
    path: SampledTrajectory | None = None
    """the baseline's path as the bridge receives it (law ``sampled``); None for a polynomial law"""
    certificate: dict[str, float] | None = None

    @property
    def zero_move(self) -> bool:
        return self.duration_s == 0.0

    @classmethod
    def of_plan(cls, index: int, r: PlanResult, params: AxisParams) -> PlannedMove:
        p = r.problem
        zero = MoveScore(0.0, 0.0, 0.0, 0.0)
        move = None if r.zero_move else Move(p.x0_m, p.x1_m, r.duration_s, p.law)
        return cls(
            index, p.x0_m, p.x1_m, r.duration_s, p.law.name, p.case.value, r.solver, p.omega, r.status.value,
            r.objective, r.max_violation, r.solve_time_s,
            zero if move is None else score(move, r.energy_j, params),
            certificate=r.certificate.to_dict() if r.certificate is not None else {},
        )  # fmt: skip

    @classmethod
    def of_baseline(cls, index: int, b: BaselinePlan, params: AxisParams) -> PlannedMove:
        zero = MoveScore(0.0, 0.0, 0.0, 0.0)
        return cls(
            index, b.x0_m, b.x1_m, b.duration_s, b.law, "min-time", "ruckig", 1.0, "converged",
            b.duration_s, b.max_violation, b.solve_time_s,
            zero if b.move is None else score(b.move, b.energy_j, params),
            path=None if b.move is None else b.move.trajectory(),
        )  # fmt: skip


@dataclass(frozen=True)
class PlannedRun:
    """One run of the comparison (a label of :data:`RUN_LABELS`): its moves as planned."""

    label: str
    law: str
    omega: float | None
    moves: tuple[PlannedMove, ...]
    slower_moves: tuple[int, ...] = ()
    """moves (by index) that took longer than the baseline's duration (``equal-time`` only)"""

    @property
    def cycle_time_s(self) -> float:
        return math.fsum(m.duration_s for m in self.moves)

    @property
    def energy_j(self) -> float:
        return math.fsum(m.score.energy_j for m in self.moves)


@dataclass(frozen=True)
class FrontPoint:
    """A total of the law's plans over the cycle at one ω (a point of its Pareto front)."""

    omega: float
    cycle_time_s: float
    energy_j: float


@dataclass(frozen=True)
class Comparison:
    """The three runs planned on the model, the law's front and both baselines' totals."""

    baseline_law: str
    limits: BaselineLimits
    law: str
    runs: tuple[PlannedRun, PlannedRun, PlannedRun]
    match_status: MatchStatus
    front: tuple[FrontPoint, ...]
    baseline_points: dict[str, FrontPoint]
    """each baseline law's time-optimal totals under the limits (ω = NaN)"""

    def run(self, label: str) -> PlannedRun:
        return next(r for r in self.runs if r.label == label)


def plan_comparison(
    moves: Moves,
    baseline_law: str,
    limits: BaselineLimits,
    law: str,
    params: AxisParams,
    progress: Callable[[str], None] | None = None,
    front: bool = True,
) -> Comparison:
    """Plan the comparison of the module docstring for ``moves`` on ``params`` (``front``: with the
    law's Pareto front for the figure)."""
    say = progress or (lambda _line: None)
    polynomial_law(law)  # an unknown law is refused before any planning
    bases = {
        name: [plan_baseline(name, x0, x1, limits, params) for x0, x1 in moves] for name in BASELINE_LAWS
    }
    chosen = bases[baseline_law]
    baseline = PlannedRun(
        "baseline",
        baseline_law,
        None,
        tuple(PlannedMove.of_baseline(k, b, params) for k, b in enumerate(chosen, start=1)),
    )
    say(
        f"  {baseline_law}: {len(moves)} moves, cycle time {baseline.cycle_time_s:.3f} s, "
        f"E {baseline.energy_j:.1f} J"
    )
    by_move = plan_at_durations(moves, law, [b.duration_s for b in chosen], params)
    equal = PlannedRun(
        "equal-time", law, None, _moves(by_move.results, params), tuple(k + 1 for k in by_move.slower_moves)
    )
    say(
        f"  {law} at the baseline's durations: cycle time {equal.cycle_time_s:.3f} s, "
        f"E {equal.energy_j:.1f} J"
    )
    match = match_cycle_time(moves, law, baseline.cycle_time_s, params)
    matched = PlannedRun("matched-omega", law, match.omega, _moves(match.plan.results, params))
    say(
        f"  {law} at ω = {match.omega:.6f} ({match.status.value}, {match.iterations} steps): cycle time "
        f"{matched.cycle_time_s:.3f} s, E {matched.energy_j:.1f} J"
    )
    omegas = DEFAULT_OMEGAS if front else ()
    points_of_front = tuple(FrontPoint(w, *cycle_totals(moves, law, w, params)) for w in omegas)
    points = {
        name: FrontPoint(
            math.nan, math.fsum(b.duration_s for b in plans), math.fsum(b.energy_j for b in plans)
        )
        for name, plans in bases.items()
    }
    return Comparison(
        baseline_law,
        limits.for_law(baseline_law),
        law,
        (baseline, equal, matched),
        match.status,
        points_of_front,
        points,
    )


def _moves(results: Sequence[PlanResult], params: AxisParams) -> tuple[PlannedMove, ...]:
    return tuple(PlannedMove.of_plan(k, r, params) for k, r in enumerate(results, start=1))
