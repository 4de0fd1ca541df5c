"""What a planner back-end returns for one move."""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

from ..model import Move, MoveError
from .certificates import Certificate
from .problem import MoveProblem


class SolveStatus(StrEnum):
    CONVERGED = "converged"
    """the solver met its optimality tolerance"""
    ITERATION_CAP = "stopped-at-cap"
    """the iteration cap stopped the solver: IPOPT's last iterate, or (exact back-end, a safeguard
    loop at its cap) the slowest allowed duration T_max; the 1 kHz check is in ``max_violation``"""
    DEADLINE = "deadline"
    """the solve ran past its deadline; the slowest allowed duration, T_max, is returned (its 1 kHz
    check in ``max_violation``)"""
    INFEASIBLE = "infeasible"
    """no duration within the bounds meets the limits"""
    FAILED = "failed"
    """the solver stopped for another reason (see message)"""


@dataclass(frozen=True)
class PlanResult:
    """The planned duration of one move and how it was obtained.

    ``max_violation`` is measured at the 1 kHz execution samples against the true limits
    (relative: 0.01 = 1 % over a limit), not at the solver's nodes.
    """

    problem: MoveProblem
    solver: str
    status: SolveStatus
    duration_s: float
    objective: float
    energy_j: float
    iterations: int
    solve_time_s: float
    max_violation: float
    message: str = ""
    certificate: Certificate | None = None
    """evidence of optimality (a bracket, a gap: :mod:`.certificates`); None when none is proved"""

    @property
    def success(self) -> bool:
        return self.status is SolveStatus.CONVERGED

    @property
    def zero_move(self) -> bool:
        """The move is shorter than one encoder count: nothing to execute (duration 0 s, energy 0 J;
        :func:`~axisflow.planner.evaluation.zero_move_result`)."""
        return self.duration_s == 0.0

    @property
    def move(self) -> Move:
        """The move to execute (a zero move has none: :class:`MoveError`)."""
        p = self.problem
        if self.zero_move:
            raise MoveError(
                f"the move {p.x0_m:.9g} m → {p.x1_m:.9g} m is a zero move (shorter than one encoder "
                "count): there is nothing to execute"
            )
        return Move(p.x0_m, p.x1_m, self.duration_s, p.law)
