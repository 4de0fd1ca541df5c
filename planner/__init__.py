"""Point-to-point planning: the paper's problem, its back-ends and their results.

Installs as ``axisflow.planner`` from the folder ``planner/`` (pyproject.toml maps each top-level
folder to a sub-package of ``axisflow``; docs/architecture.md draws their imports).

Each public name is loaded with its module on first use: importing one module of the planner (its
defaults, say) costs that module only.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..model import lazy_names

if TYPE_CHECKING:  # what a type checker sees; at run time __getattr__ loads each name from _HOMES
    from .backend import BACKENDS, PlannerBackend, make_backend  # noqa: F401
    from .certificates import Certificate, MinTimeCertificate, TimeEnergyCertificate  # noqa: F401
    from .errors import InfeasibleMoveError  # noqa: F401
    from .exact import Active, ExactBackend, ExactSolution, solve_exact  # noqa: F401
    from .problem import DEFAULT_OMEGA, DEFAULT_TIME_BOUNDS_S, REFERENCE_LAWS, Case, MoveProblem  # noqa: F401
    from .reference_laws import ReferenceProfile, least_energy, time_optimal  # noqa: F401
    from .result import PlanResult, SolveStatus  # noqa: F401

# each public name → its module, relative to this package
_HOMES: dict[str, str] = {
    "BACKENDS": "backend",
    "PlannerBackend": "backend",
    "make_backend": "backend",
    "Certificate": "certificates",
    "MinTimeCertificate": "certificates",
    "TimeEnergyCertificate": "certificates",
    "InfeasibleMoveError": "errors",
    "Active": "exact",
    "ExactBackend": "exact",
    "ExactSolution": "exact",
    "solve_exact": "exact",
    "DEFAULT_OMEGA": "problem",
    "DEFAULT_TIME_BOUNDS_S": "problem",
    "Case": "problem",
    "MoveProblem": "problem",
    "REFERENCE_LAWS": "problem",
    "ReferenceProfile": "reference_laws",
    "least_energy": "reference_laws",
    "time_optimal": "reference_laws",
    "PlanResult": "result",
    "SolveStatus": "result",
}


__getattr__ = lazy_names(__name__, _HOMES)


__all__ = sorted(_HOMES)
