"""Bounds on iterative work: an iteration cap and a wall-clock deadline, with typed failures.

Every loop of the model and the planner that iterates until a condition holds (Newton steps,
bisections, secant searches, integrations to rest) is capped in steps and, where one call may run
long, given a :class:`Deadline`. Hitting either raises a :class:`SolveLimitError` naming the loop and
the bound; a planner back-end turns it into the status of its result object, never an endless loop.
"""

from __future__ import annotations

import math
import time

from .errors import AxisflowError


class SolveLimitError(AxisflowError):
    """An iterative computation hit its iteration cap or its deadline (root of the two below)."""


class IterationCapError(SolveLimitError):
    """A loop took its maximum number of steps without meeting its stopping condition."""


class DeadlineError(SolveLimitError):
    """A computation ran past its wall-clock deadline."""


class Deadline:
    """A wall-clock budget of ``seconds`` from now (monotonic clock); ``math.inf``: none."""

    __slots__ = ("_end", "seconds", "what")

    def __init__(self, seconds: float, what: str = "the computation") -> None:
        if not seconds > 0.0:
            raise ValueError(f"deadline = {seconds} s must be > 0 s")
        self.seconds, self.what = seconds, what
        self._end = time.monotonic() + seconds if math.isfinite(seconds) else math.inf

    @property
    def expired(self) -> bool:
        return time.monotonic() > self._end

    def check(self, where: str) -> None:
        """Raise :class:`DeadlineError` naming ``where`` if the deadline has passed."""
        if time.monotonic() > self._end:
            raise DeadlineError(f"{self.what} ran past its deadline of {self.seconds:g} s (in {where})")


def iteration_cap(where: str, steps: int) -> IterationCapError:
    """The error of a loop at ``where`` that took its ``steps`` steps (raise it)."""
    return IterationCapError(f"{where} did not converge within its cap of {steps} steps")
