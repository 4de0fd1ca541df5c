"""How the motor moves the carriage: the transmission kinds, each one small frozen record.

A transmission turns motor rotation into carriage travel. For every kind it gives one number, the
carriage travel per motor radian k [m/rad], and everything else follows from it (an ideal, stiff and
lossless transmission; its losses are friction, and friction is :mod:`.friction`'s):

    x = k·θ_m,   ẋ = k·ω_m,   F = τ_m/k   (force_per_torque = 1/k),
    M_eq = m + J_reflected/k²  (the rotating inertias seen at the carriage, :meth:`reflected_mass_kg`)

| kind | keys | k [m/rad] | reflected inertia [kg] |
|---|---|---|---|
| ``belt`` | J_m, J_g, J_p, r, i_r | r/i_r | ((J_m + J_g)·i_r² + 2·J_p)/r² (two pulleys) |
| ``ball-screw`` | J_m, J_g, J_s, lead, i_r | lead/(2π·i_r) | (J_m + J_g)/k² + J_s·(2π/lead)² |
| ``rack-pinion`` | J_m, J_g, J_p, r, i_r | r/i_r | ((J_m + J_g)·i_r² + J_p)/r² (one pinion) |
| ``linear-motor`` | — | 1 | 0 (the moving coil's mass is part of m) |

A belt and a rack and pinion are one shape, :class:`PulleyDrive`, that differs in the number of
wheels of inertia J_p turning at the output.

i_r is the reduction between the motor and the driven element (pulley, screw, pinion): a gearbox, a
belt stage, or 1 for a direct coupling. A **linear motor** has no rotary side: its "motor torque" is a
force [N] and its "motor angle" a position [m] (k = 1 m/rad, read as 1 m per m), so the motor-side
and carriage-side signals of a log are the same numbers.

The output element turns once per ``output_travel_m`` of carriage travel (2π·r of a pulley or
pinion, one lead of a screw); an encoder with a number of counts per turn of that element
resolves that travel divided by its counts (:mod:`.encoder`). A linear motor's scale is linear: its
output travel is :data:`LINEAR_SCALE_PERIOD_M` per "turn".
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

ArrayLike = float | np.ndarray

LINEAR_SCALE_PERIOD_M = 0.25
"""the travel a linear motor's encoder counts over as one "turn" [m]: with the 2^17 counts of the
axis's encoder, 1.9 µm per count (the belt axis's count is 1.917 µm)"""


class Transmission:
    """The interface of every kind (see the module docstring). Subclasses are frozen dataclasses."""

    kind: ClassVar[str]
    keys: ClassVar[tuple[str, ...]]
    """the kind's parameter keys, in file order"""

    @property
    def metres_per_radian(self) -> float:
        """k: carriage travel per motor radian [m/rad]."""
        raise NotImplementedError

    def reflected_mass_kg(self) -> float:
        """The rotating parts' inertia seen at the carriage [kg]."""
        raise NotImplementedError

    @property
    def output_travel_m(self) -> float:
        """Carriage travel per turn of the driven element [m] (what its encoder divides)."""
        raise NotImplementedError

    @property
    def force_per_torque(self) -> float:
        """Carriage force per motor torque [N/(N·m)] = 1/k."""
        return 1.0 / self.metres_per_radian

    @property
    def radians_per_metre(self) -> float:
        """Motor radians per metre of carriage travel [rad/m] = 1/k."""
        return 1.0 / self.metres_per_radian

    # ---- motor side ↔ carriage side ----------------------------------------------------------------
    def carriage_position(self, motor_angle_rad: ArrayLike) -> np.ndarray:
        """x [m] of a motor angle θ_m [rad]: k·θ_m."""
        return np.asarray(motor_angle_rad, dtype=float) * self.metres_per_radian

    def carriage_velocity(self, motor_speed_rad_s: ArrayLike) -> np.ndarray:
        """ẋ [m/s] of a motor speed ω_m [rad/s]: k·ω_m."""
        return np.asarray(motor_speed_rad_s, dtype=float) * self.metres_per_radian

    def carriage_force(self, motor_torque_nm: ArrayLike) -> np.ndarray:
        """F [N] of a motor torque τ_m [N·m]: τ_m/k."""
        return np.asarray(motor_torque_nm, dtype=float) * self.force_per_torque

    def motor_angle(self, position_m: ArrayLike) -> np.ndarray:
        """θ_m [rad] of a carriage position x [m]: x/k."""
        return np.asarray(position_m, dtype=float) * self.radians_per_metre

    def motor_speed(self, velocity_m_s: ArrayLike) -> np.ndarray:
        """ω_m [rad/s] of a carriage velocity ẋ [m/s]: ẋ/k."""
        return np.asarray(velocity_m_s, dtype=float) * self.radians_per_metre

    def motor_torque(self, force_n: ArrayLike) -> np.ndarray:
        """τ_m [N·m] of a carriage force F [N]: F·k."""
        return np.asarray(force_n, dtype=float) * self.metres_per_radian

    # ---- records -----------------------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """``{"kind": …, key: value, …}``: the ``[transmission]`` table of a parameter file."""
        return {"kind": self.kind} | {key: getattr(self, key) for key in self.keys}

    def replace(self, **changes: float) -> Transmission:
        """A copy with some keys changed."""
        return dataclasses.replace(self, **changes)  # type: ignore[type-var]


@dataclass(frozen=True)
class PulleyDrive(Transmission):
    """The shape of a drive whose output is a toothed wheel of pitch radius r on the carriage's belt
    or rack, behind a reduction i_r: k = r/i_r, and :attr:`wheels` wheels of inertia J_p turn with it
    (the belt's driving and idler pulleys, or the one pinion of a rack). :class:`Belt` and
    :class:`RackPinion` are its kinds."""

    keys: ClassVar[tuple[str, ...]] = ("J_m", "J_g", "J_p", "r", "i_r")
    wheels: ClassVar[int]
    """how many wheels of inertia J_p turn at the output"""
    J_m: float
    """motor rotor inertia [kg·m²]"""
    J_g: float
    """gearbox inertia referred to the motor [kg·m²]"""
    J_p: float
    """inertia of one pulley, or of the pinion [kg·m²]"""
    r: float
    """pulley (or pinion) pitch radius [m]"""
    i_r: float
    """gear reduction ratio (motor revolutions per pulley or pinion revolution) [-]"""

    @property
    def metres_per_radian(self) -> float:
        return self.r / self.i_r

    @property
    def radians_per_metre(self) -> float:
        return self.i_r / self.r  # as written in eq. (1), not 1/k rounded twice

    @property
    def force_per_torque(self) -> float:
        return self.i_r / self.r

    def reflected_mass_kg(self) -> float:
        return ((self.J_m + self.J_g) * self.i_r**2 + self.wheels * self.J_p) / self.r**2

    @property
    def output_travel_m(self) -> float:
        return 2.0 * math.pi * self.r


@dataclass(frozen=True)
class Belt(PulleyDrive):
    """Belt and pulleys with a gearbox: the paper's axis (two pulleys, driving and idler)."""

    kind: ClassVar[str] = "belt"
    wheels: ClassVar[int] = 2


@dataclass(frozen=True)
class BallScrew(Transmission):
    """A ball screw driven by the motor directly or through a gearbox or belt stage (ratio i_r)."""

    kind: ClassVar[str] = "ball-screw"
    keys: ClassVar[tuple[str, ...]] = ("J_m", "J_g", "J_s", "lead", "i_r")
    J_m: float
    """motor rotor inertia [kg·m²]"""
    J_g: float
    """gearbox (or belt stage) inertia referred to the motor [kg·m²]; 0 for a coupling"""
    J_s: float
    """the screw's inertia about its axis [kg·m²]"""
    lead: float
    """carriage travel per screw revolution [m/rev]"""
    i_r: float
    """reduction between the motor and the screw [-] (1: coupled directly)"""

    @property
    def metres_per_radian(self) -> float:
        return self.lead / (2.0 * math.pi * self.i_r)

    def reflected_mass_kg(self) -> float:
        per_screw_rad = 2.0 * math.pi / self.lead
        return (self.J_m + self.J_g) / self.metres_per_radian**2 + self.J_s * per_screw_rad**2

    @property
    def output_travel_m(self) -> float:
        return self.lead


@dataclass(frozen=True)
class RackPinion(PulleyDrive):
    """A pinion on a rack, driven through a gearbox (ratio i_r)."""

    kind: ClassVar[str] = "rack-pinion"
    wheels: ClassVar[int] = 1


@dataclass(frozen=True)
class LinearMotor(Transmission):
    """A direct linear motor: no rotary side (module docstring)."""

    kind: ClassVar[str] = "linear-motor"
    keys: ClassVar[tuple[str, ...]] = ()

    @property
    def metres_per_radian(self) -> float:
        return 1.0

    def reflected_mass_kg(self) -> float:
        return 0.0

    @property
    def output_travel_m(self) -> float:
        return LINEAR_SCALE_PERIOD_M


TRANSMISSION_KINDS: dict[str, type[Transmission]] = {
    cls.kind: cls for cls in (Belt, BallScrew, RackPinion, LinearMotor)
}
"""every kind by the name a parameter file gives it"""
DEFAULT_KIND = Belt.kind
"""the kind of a parameter file with no ``[transmission]`` table (its keys at the top level)"""
