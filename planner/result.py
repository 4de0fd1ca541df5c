"""What a planner back-end returns for one move."""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

from ..model import Move
from .certificates import Certificate
from .problem import MoveProblem


class SolveStatus(StrEnum):
    CONVERGED = "converged"
    """the solver met its optimality tolerance"""
    ITERATION_CAP = "stopped-at-cap"
    """the iteration cap stopped the solver; the last iterate is returned"""
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
    def move(self) -> Move:
        p = self.problem
        return Move(p.x0_m, p.x1_m, self.duration_s, p.law)
