"""The planner back-end interface and the registry of back-ends by name."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Protocol

from ..model import MoveError

if TYPE_CHECKING:
    from ..model import AxisParams
    from .problem import MoveProblem
    from .result import PlanResult


class PlannerBackend(Protocol):
    """Solves one move; ``prepare`` does any one-off set-up so that ``solve`` can be timed alone."""

    name: str

    def prepare(self, problem: MoveProblem, params: AxisParams) -> None: ...

    def solve(self, problem: MoveProblem, params: AxisParams) -> PlanResult: ...


def _ipopt(**options: Any) -> PlannerBackend:
    from .ipopt_backend import IpoptBackend, IpoptSettings

    return IpoptBackend(IpoptSettings(**options))


def _exact(**options: Any) -> PlannerBackend:
    from .exact import ExactBackend

    if options:
        raise MoveError(f"the exact solver takes no options, got {', '.join(sorted(options))}")
    return ExactBackend()


BACKENDS: dict[str, Callable[..., PlannerBackend]] = {"exact": _exact, "ipopt": _ipopt}


def make_backend(name: str, **options: Any) -> PlannerBackend:
    """A back-end by name (``exact``, ``ipopt``), with back-end specific options (e.g. ``max_iter``)."""
    try:
        factory = BACKENDS[name]
    except KeyError:
        raise MoveError(f"unknown solver {name!r}; choose one of {', '.join(BACKENDS)}") from None
    return factory(**options)
