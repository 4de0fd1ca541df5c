"""The exception root of identification."""

from __future__ import annotations

from ..model import AxisflowError


class IdentificationError(AxisflowError, ValueError):
    """A log or a setting cannot be used for identification (the message names what and why)."""
