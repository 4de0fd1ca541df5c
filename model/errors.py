"""The exception root of axisflow.

Every error that a user can cause (a bad parameter file, a move outside the stroke, an impossible
set of bounds) is an :class:`AxisflowError`. The command line prints its message and exits non-zero
without a traceback; anything else is a bug and keeps its traceback.
"""

from __future__ import annotations


class AxisflowError(Exception):
    """Root of all user-facing axisflow errors."""


class ParameterError(AxisflowError, ValueError):
    """A parameter file or value is invalid (unknown/missing key, bad value, wrong unit range)."""


class MoveError(AxisflowError, ValueError):
    """A move request is invalid: end points outside the stroke, non-finite numbers, bad weights."""


class AxisflowWarning(UserWarning):
    """Root of axisflow's warnings: something a user should know that does not stop the work (a
    damaged chunk of a log that was skipped). Libraries issue them with :func:`warnings.warn`; the
    command line prints each as one line on stderr."""
