"""Way points planned into moves: axisflow's planner for the untimed points, the law at the asked
duration for the timed ones.

For way point k (from x_{k−1}, the previous point or where the axis will be, to x_k):

* **no ``time_from_start``**: the move the planner back-end finds for the node's case, law and ω (the
  options of ``axisflow planner``); refused if the back-end fails or its plan breaks a limit at the
  1 kHz samples (the planner node's rule);
* **``time_from_start`` t_k**: the move must end at t_k after the trajectory's start, on the drive's
  tick grid: its duration is T_k = ⌈t_k/Δt⌉·Δt − (the planned end of the move before), a whole number
  of 1 ms ticks, so every timed point is reached at the first tick at or after t_k and the rounding
  never accumulates. A polynomial law with fixed end points and a fixed duration is one move: the
  move of that duration *is* the law at T_k (its energy the planner's evaluation, eq. (1)); it is
  refused when T_k is shorter than the law's minimum time over the distance (the exact back-end's
  minimum-time solve, decided by v_max or tau_max), naming both durations. A timed point at the
  position the axis already holds (within one encoder count) is a hold: a move of zero distance that
  keeps the axis there for T_k.

Why the law at T_k, not the least-energy profile of :func:`axisflow.planner.reference_laws.least_energy`:
that profile is the cheapest of all profiles of duration T (full force, cruise, coast, full braking),
a bound to compare with, but its force jumps between full drive and full braking — steps of the motor
torque a drive should not be asked for. The polynomial laws are smooth; a user who picked ``--law``
picked the smoothness, and at a fixed duration the law leaves nothing to optimise (docs/ros2.md).

A point shorter than one encoder count from the one before and without a time is a zero move
(:func:`~axisflow.planner.evaluation.zero_move_result`): nothing is sent, as in the planner node.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ...model import EXECUTION_PERIOD_S, MAX_MOVE_DURATION_S, AxisParams, move_ticks, polynomial_law
from ...model.encoder import axis_resolution_m
from ...planner import Case, ExactBackend, MoveProblem, PlannerBackend, PlanResult, SolveStatus
from ...planner.evaluation import finish
from .errors import TrajectoryRefusedError
from .settings import MotionSettings
from .trajectory_request import TrajectoryRequest

REFUSED_STATUSES = (SolveStatus.DEADLINE, SolveStatus.FAILED, SolveStatus.INFEASIBLE)
"""plan statuses never sent (as the planner node: a capped IPOPT iterate is sent if it meets the limits)"""
FIXED_DURATION = "fixed duration"
"""the ``solver`` of the plan of a timed point: the law evaluated at the asked duration"""


@dataclass(frozen=True)
class PlannedMove:
    """The move to way point ``point``: where from and to, how long, and when it ends."""

    point: int
    start_m: float
    end_m: float
    duration_s: float
    """0 for a zero move (nothing is sent)"""
    energy_j: float
    end_tick: int
    """ticks from the trajectory's start to the end of this move (the arrival at its way point)"""
    timed: bool
    """the point asked for its arrival time"""
    plan: PlanResult | None
    """the planner's result (None for a hold)"""

    @property
    def arrive_s(self) -> float:
        """The planned arrival at the way point after the trajectory's start [s]."""
        return self.end_tick * EXECUTION_PERIOD_S

    @property
    def sent(self) -> bool:
        """Whether the move is sent to the bridge (not a zero move)."""
        return self.duration_s > 0.0


@dataclass(frozen=True)
class TrajectoryPlan:
    """Every way point of a request, planned from ``start_position_m``."""

    request: TrajectoryRequest
    start_position_m: float
    moves: tuple[PlannedMove, ...]

    @property
    def sent(self) -> tuple[PlannedMove, ...]:
        return tuple(m for m in self.moves if m.sent)

    @property
    def duration_s(self) -> float:
        return self.moves[-1].arrive_s if self.moves else 0.0

    @property
    def energy_j(self) -> float:
        return math.fsum(m.energy_j for m in self.moves)

    @property
    def end_position_m(self) -> float:
        return self.moves[-1].end_m if self.moves else self.start_position_m


class TrajectoryPlanner:
    """Plans requests for one axis with one back-end (see the module docstring)."""

    def __init__(self, backend: PlannerBackend, params: AxisParams, motion: MotionSettings) -> None:
        self.backend, self.params, self.motion = backend, params, motion
        self._law = polynomial_law(motion.law)
        self._exact = ExactBackend()

    def prepare(self) -> None:
        """The back-ends' one-off set-up for the law and case (so that no trajectory pays for it)."""
        L = self.params.L
        self.backend.prepare(self._problem(0.0, L), self.params)
        self._exact.prepare(MoveProblem(0.0, L, self._law, Case.MIN_TIME), self.params)

    def plan(self, request: TrajectoryRequest, start_position_m: float) -> TrajectoryPlan:
        """The moves through the request's way points from ``start_position_m``; raises
        :class:`TrajectoryRefusedError` naming the first point that cannot be reached as asked."""
        moves: list[PlannedMove] = []
        x0, ticks = float(start_position_m), 0
        for k, point in enumerate(request.points):
            x1 = point.position_m
            if not 0.0 <= x1 <= self.params.L:
                raise TrajectoryRefusedError(
                    f"point {k}: position {x1:.9g} m is outside the stroke [0, {self.params.L}] m"
                )
            if point.arrive_s is None:
                move = self._planned(k, x0, x1, ticks)
            else:
                move = self._timed(k, x0, x1, point.arrive_s, ticks)
            moves.append(move)
            ticks = move.end_tick
            x0 = move.end_m
        return TrajectoryPlan(request, float(start_position_m), tuple(moves))

    def _problem(self, x0: float, x1: float) -> MoveProblem:
        return MoveProblem(x0, x1, self._law, self.motion.case, self.motion.omega)

    def _planned(self, k: int, x0: float, x1: float, ticks: int) -> PlannedMove:
        problem = self._problem(x0, x1)
        plan = self.backend.solve(problem, self.params)
        what = (
            f"point {k}: the {plan.solver} plan of {x0:.6g} → {x1:.6g} m "
            f"({self._law.name}, {problem.case.value})"
        )
        if plan.status in REFUSED_STATUSES:
            raise TrajectoryRefusedError(f"{what} failed: status {plan.status.value} ({plan.message})")
        if plan.max_violation > 0.0:
            raise TrajectoryRefusedError(
                f"{what} breaks a limit by {plan.max_violation:.3g} (relative) at the 1 kHz samples"
            )
        if plan.zero_move:
            return PlannedMove(k, x0, x1, 0.0, 0.0, ticks, False, plan)
        end = ticks + move_ticks(plan.duration_s)
        return PlannedMove(k, x0, x1, plan.duration_s, plan.energy_j, end, False, plan)

    def _timed(self, k: int, x0: float, x1: float, arrive_s: float, ticks: int) -> PlannedMove:
        end = move_ticks(arrive_s)
        before = ticks * EXECUTION_PERIOD_S
        if end <= ticks:
            raise TrajectoryRefusedError(
                f"point {k} asks to arrive at {arrive_s:.6g} s, but the axis reaches "
                f"{'point ' + str(k - 1) if k else 'its start'} only at {before:.6g} s"
            )
        duration = (end - ticks) * EXECUTION_PERIOD_S
        if duration > MAX_MOVE_DURATION_S:
            raise TrajectoryRefusedError(
                f"point {k}: a move of {duration:.6g} s is longer than the longest move, "
                f"{MAX_MOVE_DURATION_S:g} s"
            )
        if abs(x1 - x0) < axis_resolution_m(self.params):  # a hold where the axis is
            return PlannedMove(k, x0, x0, duration, 0.0, end, True, None)
        fastest = self._fastest(x0, x1)
        if duration < fastest.duration_s:
            raise TrajectoryRefusedError(
                f"point {k} asks to arrive {arrive_s - before:.6g} s after "
                f"{'point ' + str(k - 1) if k else 'the start'} ({x0:.6g} → {x1:.6g} m): faster than the "
                f"fastest {self._law.name} move, {fastest.duration_s:.6g} s "
                f"(v_max = {self.params.v_max} m/s, tau_max = {self.params.tau_max} N·m)"
            )
        problem = MoveProblem(x0, x1, self._law, Case.MIN_TIME, t_min_s=duration, t_max_s=duration)
        plan = finish(
            problem,
            self.params,
            solver=FIXED_DURATION,
            status=SolveStatus.CONVERGED,
            duration_s=duration,
            iterations=0,
            solve_time_s=0.0,
            message=f"the {self._law.name} law at the asked {duration:.6g} s",
        )
        if plan.max_violation > 0.0:  # feasibility is monotone in T: only a bug of the bound gets here
            raise TrajectoryRefusedError(
                f"point {k}: the {self._law.name} move {x0:.6g} → {x1:.6g} m in {duration:.6g} s breaks a "
                f"limit by {plan.max_violation:.3g} (relative) at the 1 kHz samples"
            )
        return PlannedMove(k, x0, x1, duration, plan.energy_j, end, True, plan)

    def _fastest(self, x0: float, x1: float) -> PlanResult:
        """The law's minimum-time move over x0 → x1 with no lower bound but one tick."""
        problem = MoveProblem(
            x0, x1, self._law, Case.MIN_TIME, t_min_s=EXECUTION_PERIOD_S, t_max_s=MAX_MOVE_DURATION_S
        )
        return self._exact.solve(problem, self.params)
