"""Point-to-point planning: the paper's problem, its back-ends and their results."""

from .backend import BACKENDS, PlannerBackend, make_backend
from .certificates import Certificate, MinTimeCertificate, TimeEnergyCertificate
from .errors import InfeasibleMoveError
from .exact import Active, ExactBackend, ExactSolution, solve_exact
from .problem import DEFAULT_OMEGA, DEFAULT_TIME_BOUNDS_S, Case, MoveProblem
from .reference_laws import REFERENCE_LAWS, ReferenceProfile, least_energy, time_optimal
from .result import PlanResult, SolveStatus

__all__ = [
    "BACKENDS",
    "DEFAULT_OMEGA",
    "DEFAULT_TIME_BOUNDS_S",
    "REFERENCE_LAWS",
    "Active",
    "Case",
    "Certificate",
    "ExactBackend",
    "ExactSolution",
    "InfeasibleMoveError",
    "MinTimeCertificate",
    "MoveProblem",
    "PlanResult",
    "PlannerBackend",
    "ReferenceProfile",
    "SolveStatus",
    "TimeEnergyCertificate",
    "least_energy",
    "make_backend",
    "solve_exact",
    "time_optimal",
]
