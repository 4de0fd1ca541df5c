"""Point-to-point planning: the paper's problem, its back-ends and their results."""

from .backend import BACKENDS, PlannerBackend, make_backend
from .errors import InfeasibleMoveError
from .problem import DEFAULT_OMEGA, DEFAULT_TIME_BOUNDS_S, Case, MoveProblem
from .result import PlanResult, SolveStatus

__all__ = [
    "BACKENDS",
    "DEFAULT_OMEGA",
    "DEFAULT_TIME_BOUNDS_S",
    "Case",
    "InfeasibleMoveError",
    "MoveProblem",
    "PlanResult",
    "PlannerBackend",
    "SolveStatus",
    "make_backend",
]
