"""A servo drive's integer units and the axis's SI units: the one place where they are converted.

Drives count and scale in their own units (CiA 402 and most vendors' drives):

* **position** in encoder counts of the motor shaft: ``counts_per_rev`` counts per motor revolution
  (0x6064 position actual value, 0x607A target position), counted from ``zero_counts`` at x = 0;
* **velocity** in counts per second (0x606C velocity actual value, 0x60B1 velocity offset);
* **acceleration** in counts per second squared (0x6085 quick-stop deceleration);
* **torque** in per mille (0.1 %) of the motor's rated torque (0x6076, given in mN·m): 0x6077 torque
  actual value, 0x60B2 torque offset, both signed 16-bit.

Through the gearbox (ratio i_r) and the pulley (radius r) of the axis model, with the polarity
``direction`` (+1: the counts grow as the cart moves towards +x; −1: the motor is mounted the other way
round, and a positive drive torque pushes the cart towards −x):

    x = direction · 2π·r·(counts − zero_counts) / (counts_per_rev·i_r)      [m]
    ẋ = direction · 2π·r·(counts/s) / (counts_per_rev·i_r)                  [m/s]
    ẍ = direction · 2π·r·(counts/s²) / (counts_per_rev·i_r)                 [m/s²]
    τ_m = direction · per_mille / 1000 · rated_torque                         [N·m]

Distances (a following-error window) have no sign and no zero: ``distance_counts``.

The drive reports integers; going from SI to drive units rounds to the nearest integer (and saturates
torques to the signed 16-bit range), so a round trip is exact to half a unit. Every adapter, simulated
drive and realistic plant uses these functions and nothing else.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .errors import ParameterError
from .params import AxisParams

PER_MILLE = 1000.0
"""per mille units in the whole"""
INT16_MAX = 32767
"""largest magnitude of a signed 16-bit object (torque actual value, torque offset)"""
INT32_MIN, INT32_MAX = -(1 << 31), (1 << 31) - 1
"""range of a signed 32-bit object (position, velocity)"""
UINT32_MAX = (1 << 32) - 1
"""largest unsigned 32-bit object (a following-error window)"""

ArrayLike = float | int | np.ndarray


def metres_per_count(counts_per_rev: int, gear_ratio: float, r_m: float) -> float:
    """Cart travel of one count of an encoder with ``counts_per_rev`` counts per revolution of a shaft
    that turns ``gear_ratio`` times per pulley revolution (the motor: i_r; the pulley itself: 1) [m]."""
    return 2.0 * math.pi * r_m / (counts_per_rev * gear_ratio)


@dataclass(frozen=True)
class DriveUnits:
    """The unit conversions of one drive on one axis (see the module docstring)."""

    counts_per_rev: int
    """encoder counts per motor revolution"""
    rated_torque_nm: float
    """the motor's rated torque [N·m] (0x6076 holds it in mN·m)"""
    i_r: float
    """reduction ratio (motor revolutions per revolution of the driven element: pulley, screw, pinion)"""
    r: float
    """carriage travel per radian of the driven element [m]: a pulley's or pinion's radius, a screw's
    lead/2π, a linear motor's scale period/2π (its encoder counts ``counts_per_rev`` over
    :data:`~axisflow.model.transmission.LINEAR_SCALE_PERIOD_M` of travel, as :mod:`.encoder` has it)"""
    zero_counts: int = 0
    """the position count at x = 0 (a drive's counts start wherever it was switched on or homed)"""
    direction: int = 1
    """polarity: +1 if the counts grow towards +x, −1 if they grow towards −x"""

    def __post_init__(self) -> None:
        if isinstance(self.counts_per_rev, bool) or not isinstance(self.counts_per_rev, int):
            raise ParameterError(f"counts_per_rev = {self.counts_per_rev!r} must be an integer")
        if not 1 <= self.counts_per_rev <= 1 << 30:
            raise ParameterError(f"counts_per_rev = {self.counts_per_rev} counts must be in 1…2^30 counts")
        for name, value, unit in (
            ("rated_torque_nm", self.rated_torque_nm, "N·m"),
            ("i_r", self.i_r, ""),
            ("r", self.r, "m"),
        ):
            if not (math.isfinite(value) and value > 0.0):
                shown = f"{value} {unit}".strip()
                raise ParameterError(f"{name} = {shown} must be a finite number > 0")
        if not INT32_MIN <= self.zero_counts <= INT32_MAX:
            raise ParameterError(
                f"zero_counts = {self.zero_counts} counts is outside the signed 32-bit range"
            )
        if self.direction not in (1, -1) or isinstance(self.direction, bool):
            raise ParameterError(f"direction = {self.direction!r} must be 1 or -1")

    @classmethod
    def for_axis(
        cls,
        params: AxisParams,
        counts_per_rev: int,
        rated_torque_nm: float,
        zero_counts: int = 0,
        direction: int = 1,
    ) -> DriveUnits:
        """The units of a drive on the axis of ``params``: its transmission's i_r (1 for a linear motor)
        and the driven element's travel per turn over 2π (:attr:`r`; the transmission's
        ``output_travel_m``: 2π·r of a pulley or pinion, a screw's lead, a linear motor's scale period)."""
        k = params.transmission
        i_r = getattr(k, "i_r", 1.0)
        per_radian = k.output_travel_m / (2.0 * math.pi) if not hasattr(k, "r") else k.r
        return cls(counts_per_rev, rated_torque_nm, i_r, per_radian, zero_counts, direction)

    @cached_property
    def metres_per_count(self) -> float:
        """Cart travel of one encoder count [m] (the position resolution)."""
        return metres_per_count(self.counts_per_rev, self.i_r, self.r)

    @cached_property
    def newton_metres_per_unit(self) -> float:
        """Motor torque of one per mille unit [N·m] (the torque resolution)."""
        return self.rated_torque_nm / PER_MILLE

    # ---- drive → SI -------------------------------------------------------------------------------
    def position_m(self, counts: ArrayLike) -> ArrayLike:
        """Cart position [m] of a position count."""
        return (counts - self.zero_counts) * (self.direction * self.metres_per_count)

    def velocity_m_s(self, counts_per_s: ArrayLike) -> ArrayLike:
        """Cart velocity [m/s] of a velocity in counts/s."""
        return counts_per_s * (self.direction * self.metres_per_count)

    def acceleration_m_s2(self, counts_per_s2: ArrayLike) -> ArrayLike:
        """Cart acceleration [m/s²] of an acceleration in counts/s²."""
        return counts_per_s2 * (self.direction * self.metres_per_count)

    def torque_nm(self, per_mille: ArrayLike) -> ArrayLike:
        """Motor torque [N·m] (positive: pushing towards +x) of a torque in per mille of the rated."""
        return per_mille * (self.direction * self.newton_metres_per_unit)

    def distance_m(self, counts: ArrayLike) -> ArrayLike:
        """Length [m] of a distance of ``counts`` counts (no sign, no zero: a window or a tolerance)."""
        return counts * self.metres_per_count

    # ---- SI → drive (rounded to the drive's integers) --------------------------------------------
    def counts(self, position_m: float) -> int:
        """The position count nearest to ``position_m`` [m]."""
        steps = round(self.direction * position_m / self.metres_per_count)
        return _clamp(steps + self.zero_counts, INT32_MIN, INT32_MAX)

    def encoder_counts(self, position_m: float) -> int:
        """The count an incremental encoder shows at ``position_m`` [m]: the one at or below it in the
        encoder's own direction (scalar, for a simulated drive's 1 kHz loop; :meth:`quantise_position`
        is the array form for ``direction`` +1)."""
        steps = math.floor(self.direction * position_m / self.metres_per_count)
        return _clamp(steps + self.zero_counts, INT32_MIN, INT32_MAX)

    def counts_per_s(self, velocity_m_s: float) -> int:
        """The velocity [counts/s] nearest to ``velocity_m_s`` [m/s]."""
        return _clamp(round(self.direction * velocity_m_s / self.metres_per_count), INT32_MIN, INT32_MAX)

    def counts_per_s2(self, acceleration_m_s2: float) -> int:
        """The acceleration [counts/s²] nearest to ``acceleration_m_s2`` [m/s²]."""
        steps = round(self.direction * acceleration_m_s2 / self.metres_per_count)
        return _clamp(steps, INT32_MIN, INT32_MAX)

    def per_mille(self, torque_nm: float) -> int:
        """The torque [per mille of rated] nearest to ``torque_nm`` [N·m], saturated to ±32767."""
        steps = round(self.direction * torque_nm / self.newton_metres_per_unit)
        return _clamp(steps, -INT16_MAX, INT16_MAX)

    def distance_counts(self, distance_m: float) -> int:
        """The distance [counts] nearest to ``distance_m`` [m] (≥ 0: a window, saturated to 2^32 − 1)."""
        return _clamp(round(abs(distance_m) / self.metres_per_count), 0, UINT32_MAX)

    # ---- quantisation (what a drive would report), in SI -----------------------------------------
    def quantise_position(self, position_m: ArrayLike) -> ArrayLike:
        """``position_m`` as the drive's encoder sees it: the count below it, back in metres."""
        counts = np.floor(np.asarray(position_m, dtype=float) / self.metres_per_count)
        return counts * self.metres_per_count if np.ndim(counts) else float(counts) * self.metres_per_count

    def quantise_torque(self, torque_nm: ArrayLike) -> ArrayLike:
        """``torque_nm`` rounded to the drive's per mille steps (saturated), back in N·m."""
        unit = self.newton_metres_per_unit
        steps = np.clip(np.rint(np.asarray(torque_nm, dtype=float) / unit), -INT16_MAX, INT16_MAX)
        return steps * unit if np.ndim(steps) else float(steps) * unit


def _clamp(value: int, low: int, high: int) -> int:
    return int(low if value < low else high if value > high else value)
