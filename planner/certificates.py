"""What a planned duration is proved to be: the typed certificates a back-end may attach to a result.

Two kinds, one per case of the paper (the exact back-end returns them; IPOPT proves nothing and
attaches none):

* :class:`MinTimeCertificate` (case 1, min T): the smallest duration that meets the limits lies in
  (t_lower_s, t_upper_s], and the duration returned is t_upper_s. t_lower_s is proved infeasible (a
  limit is broken there), t_upper_s meets every limit; when the bound T_min decides, nothing shorter
  is allowed and t_lower_s = t_upper_s = T_min.
* :class:`TimeEnergyCertificate` (case 2, min J(T) = ω·T + (1 − ω)·E(T), J convex in T): ``gap_j``
  bounds J(returned) − min J from above and ``dJ_dT`` is the slope of J where the search ended. At
  an interior optimum, dJ/dT ≤ 0 at t_lower_s and ≥ 0 at t_upper_s (a bracket of the root of
  dJ/dT), and min J is at least the crossing of the tangents at both ends. At a bound or a limit the
  gap is 0 and dJ/dT has the sign that makes that end the minimiser; a limit adds
  ``t_infeasible_s``, a duration proved to break it.

Each has ``to_dict()`` (the JSON object ``axisflow plan --json`` prints) and ``from_dict()``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from ..model import MoveError


@dataclass(frozen=True)
class MinTimeCertificate:
    """The minimum duration lies in (t_lower_s, t_upper_s] [s]; t_upper_s is the duration returned."""

    t_lower_s: float
    """a duration proved infeasible (T_min itself when the lower bound decides)"""
    t_upper_s: float
    """the duration returned, proved to meet every limit"""

    @property
    def gap_s(self) -> float:
        """t_upper_s − t_lower_s [s]: how far the answer can be above the true minimum."""
        return self.t_upper_s - self.t_lower_s

    def to_dict(self) -> dict[str, float]:
        return {"t_lower_s": self.t_lower_s, "t_upper_s": self.t_upper_s, "gap_s": self.gap_s}

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> MinTimeCertificate:
        _check_keys(data, required={"t_lower_s", "t_upper_s", "gap_s"}, optional=set())
        return cls(float(data["t_lower_s"]), float(data["t_upper_s"]))


@dataclass(frozen=True)
class TimeEnergyCertificate:
    """Evidence that a case-2 duration minimises the convex J(T) = ω·T + (1 − ω)·E(T)."""

    gap_j: float
    """J(returned) − (a lower bound on min J), ≥ 0 (NaN when no bound was proved)"""
    dJ_dT: float
    """dJ/dT where the search ended (at a bound or a limit: the slope that makes it the minimiser)"""
    t_lower_s: float | None = None
    """with ``t_upper_s``: durations where dJ/dT ≤ 0 and ≥ 0, a bracket of an interior optimum [s]"""
    t_upper_s: float | None = None
    t_infeasible_s: float | None = None
    """a duration proved to break the velocity or torque limit, when a limit decides [s]"""

    def __post_init__(self) -> None:
        if (self.t_lower_s is None) != (self.t_upper_s is None):
            raise MoveError(
                "a time-energy bracket needs both ends, got "
                f"t_lower_s = {self.t_lower_s} and t_upper_s = {self.t_upper_s} [s]"
            )

    @property
    def has_bracket(self) -> bool:
        """True for an interior optimum (a bracket of the root of dJ/dT)."""
        return self.t_lower_s is not None

    def to_dict(self) -> dict[str, float]:
        out = {"gap_j": self.gap_j}
        if self.t_lower_s is not None and self.t_upper_s is not None:
            out |= {"t_lower_s": self.t_lower_s, "t_upper_s": self.t_upper_s}
        out["dJ_dT"] = self.dJ_dT
        if self.t_infeasible_s is not None:
            out["t_infeasible_s"] = self.t_infeasible_s
        return out

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> TimeEnergyCertificate:
        _check_keys(data, required={"gap_j", "dJ_dT"}, optional={"t_lower_s", "t_upper_s", "t_infeasible_s"})
        optional = {k: float(data[k]) for k in ("t_lower_s", "t_upper_s", "t_infeasible_s") if k in data}
        return cls(float(data["gap_j"]), float(data["dJ_dT"]), **optional)


Certificate = MinTimeCertificate | TimeEnergyCertificate


def certificate_from_dict(data: dict[str, Any]) -> Certificate | None:
    """The certificate that :meth:`to_dict` printed (an empty object: none)."""
    if not data:
        return None
    if "gap_s" in data:
        return MinTimeCertificate.from_dict(data)
    return TimeEnergyCertificate.from_dict(data)


def _check_keys(data: dict[str, Any], required: set[str], optional: set[str]) -> None:
    missing = required - data.keys()
    unknown = data.keys() - required - optional
    if missing or unknown:
        raise MoveError(
            f"bad certificate {data}: missing keys {sorted(missing)}, unknown keys {sorted(unknown)}"
        )
    for key, value in data.items():
        if isinstance(value, bool) or not isinstance(value, int | float) or math.isinf(value):
            raise MoveError(f"certificate {key} = {value!r} is not a finite number or NaN")
