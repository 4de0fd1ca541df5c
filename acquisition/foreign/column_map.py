"""Which columns of a foreign log are the joint's time, position, velocity and effort, in which units:
a :class:`ColumnMap`, checked when it is made."""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import ForeignLogError


@dataclass(frozen=True)
class Signal:
    """One mapped column: its name (or number, from 1) in the file and its unit (None: the unit the
    file gives for it)."""

    column: str
    unit: str | None = None


@dataclass(frozen=True)
class ColumnMap:
    """How a foreign log becomes one JointState joint.

    Time comes from ``time`` (a column; its unit defaults to the file's, else s) or from ``rate_hz``
    (rows evenly spaced from 0), plus ``time_offset_s``. ``position`` is required; ``velocity`` and
    ``effort`` are optional (a JointState without them has empty arrays). The effort in the joint's
    unit is ``effort_scale`` × the column in its unit: the scale is a number or the name of a scalar
    variable of the file (``gtau``); an effort given in V or A needs one (N per V on the carriage side,
    N·m per V on the motor side). ``counts_per`` = (counts, unit) converts positions given in
    ``counts`` and velocities in ``counts/s`` (e.g. (131072, "rev")). ``joint`` names the joint (None:
    ``carriage`` or ``motor``, after the side its units measure)."""

    position: Signal
    time: Signal | None = None
    rate_hz: float | None = None
    time_offset_s: float = 0.0
    velocity: Signal | None = None
    effort: Signal | None = None
    effort_scale: float | str | None = None
    counts_per: tuple[float, str] | None = None
    joint: str | None = None

    def __post_init__(self) -> None:
        if (self.time is None) == (self.rate_hz is None):
            raise ForeignLogError(
                "give either a time column or a sample rate (for a log without time), not "
                + ("both" if self.time is not None else "neither")
            )
        if self.rate_hz is not None and not (math.isfinite(self.rate_hz) and 0.0 < self.rate_hz <= 1e9):
            raise ForeignLogError(f"sample rate = {self.rate_hz} Hz must be in (0, 1e9] Hz")
        if not (math.isfinite(self.time_offset_s) and abs(self.time_offset_s) <= 1e9):
            raise ForeignLogError(f"time offset = {self.time_offset_s} s must be finite, within ±1e9 s")
        if isinstance(self.effort_scale, float | int) and not (
            math.isfinite(self.effort_scale) and self.effort_scale != 0.0
        ):
            raise ForeignLogError(f"effort scale = {self.effort_scale} must be a finite number other than 0")
        if self.effort_scale is not None and self.effort is None:
            raise ForeignLogError("an effort scale needs an effort column")
        if self.joint is not None and not self.joint.strip():
            raise ForeignLogError("the joint's name must not be empty")


def parse_counts_per(text: str) -> tuple[float, str]:
    """``131072/rev`` → (131072.0, "rev"): counts per one unit of position."""
    number, sep, unit = text.partition("/")
    try:
        counts = float(number)
    except ValueError:
        counts = math.nan
    if not sep or not unit.strip() or not (math.isfinite(counts) and counts > 0):
        raise ForeignLogError(
            f"counts per unit {text!r} must be a number > 0 of counts per a unit of position, e.g. "
            "131072/rev or 20/um"
        )
    return counts, unit.strip()


def parse_scale(text: str) -> float | str:
    """A scale: a number (``35.15``), or the name of a scalar variable of the file (``gtau``)."""
    try:
        return float(text)
    except ValueError:
        if not text.strip():
            raise ForeignLogError(
                "the effort scale must be a number or a variable's name, not empty"
            ) from None
        return text.strip()
