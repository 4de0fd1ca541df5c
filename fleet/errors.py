"""The exception root of the fleet."""

from __future__ import annotations

from ..model import AxisflowError, AxisflowWarning


class FleetError(AxisflowError):
    """A fleet command cannot go on: a catalog that is not one, a scheduler that does not answer, a bad
    setting (the message names the value, the limit and the unit)."""


class FleetValueError(FleetError, ValueError):
    """A setting of a fleet command is out of its range."""


class FleetWarning(AxisflowWarning):
    """A part of the fleet's work failed and the rest went on (a log that cannot be read, a window that
    cannot be identified): one line each."""
