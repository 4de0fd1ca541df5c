"""The physical range of every axis parameter, and the combinations that leave no problem to solve.

A parameter file is refused at load when a value lies outside its range (:data:`PARAMETER_RANGES`)
or when the values together describe an axis that cannot move (:func:`check_combination`). The
ranges are wide enough for any servo-driven belt axis of the paper's class and its smaller and
bigger siblings (a miniature belt stage to a gantry carriage); a value outside is a typing slip or a
unit slip (grams for kilograms, millimetres for metres), never an axis. They also keep the planner's
arithmetic inside what floating point carries: every solve on an axis inside them is bounded
(tests/model/test_params_properties.py, tests/planner/test_planner_properties.py).

This module is the one home of the ranges: ``axisflow params --help`` and docs/parameters.md show
this table.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import ParameterError
from .units import PARAMETER_UNITS, with_unit


@dataclass(frozen=True)
class ParameterRange:
    """The closed range [low, high] of one parameter (``low_open``: low itself excluded) and why."""

    low: float
    high: float
    why: str
    low_open: bool = False

    def __contains__(self, value: float) -> bool:
        above = value > self.low if self.low_open else value >= self.low
        return above and value <= self.high

    def describe(self, unit: str) -> str:
        """The range as text, e.g. ``[0.001, 10000] kg`` or ``(0, 1] kg·m²``."""
        text = f"{'(' if self.low_open else '['}{self.low:g}, {self.high:g}]"
        return with_unit(text, unit)


PARAMETER_RANGES: dict[str, ParameterRange] = {
    "m": ParameterRange(1e-3, 1e4, "a 1 g shuttle of a miniature stage to a 10 t gantry carriage with load"),
    "J_m": ParameterRange(
        1e-8, 1.0, "servo rotors: ~1e-7 kg·m² for a 20 mm frame, ~0.3 kg·m² for the largest frames"
    ),
    "J_g": ParameterRange(
        0.0, 1.0, "gearbox inertia at the motor, at most a large rotor's; 0 for a direct drive"
    ),
    "J_p": ParameterRange(1e-8, 1.0, "a 3 mm plastic pulley to a 0.5 m steel drum"),
    "r": ParameterRange(
        1e-3, 0.5, "pitch radius: a 10-tooth pulley of 2 mm pitch (3 mm) to a 0.5 m drum of a heavy gantry"
    ),
    "i_r": ParameterRange(0.1, 1000.0, "a 1:10 step-up belt stage to a three-stage 1000:1 reducer"),
    "L": ParameterRange(1e-2, 50.0, "a 1 cm micro stage to a 50 m gantry (belt axes are built to ~12 m)"),
    "a1": ParameterRange(0.0, 1e5, "up to ten times the working tension of the widest steel-cord belts"),
    "a2": ParameterRange(0.0, 1e5, "up to 1e5 N of viscous drag at 1 m/s (the default axis: 215 N)"),
    "a3": ParameterRange(0.0, 1e5, "as a1: the low-speed friction is a part of the dry friction"),
    "a4": ParameterRange(
        0.0, 1e4, "1/a4 is the speed where the low-speed term reaches a3·π/4, down to 0.1 mm/s; 0: no term"
    ),
    "v_max": ParameterRange(1e-3, 20.0, "1 mm/s to 20 m/s (the fastest belt axes run at 5–10 m/s)"),
    "tau_max": ParameterRange(1e-3, 1e4, "a micro servo's peak torque (1 mN·m) to a large torque motor's"),
}
"""the physical range of each parameter of :class:`~axisflow.model.params.AxisParams`"""

MAX_MOTOR_SPEED_RAD_S = 60_000.0 * 2.0 * math.pi / 60.0
"""the fastest motor of the class [rad/s] (60 000 rpm, a high-speed spindle; servos run to ~10 000
rpm): v_max·i_r/r above it asks the motor for a speed no motor turns"""


def check_range(key: str, value: float) -> None:
    """Raise :class:`ParameterError` naming the key, the value, the range and the unit when ``value``
    lies outside the range of ``key``."""
    rng = PARAMETER_RANGES[key]
    if value not in rng:
        unit = PARAMETER_UNITS[key]
        raise ParameterError(
            f"parameter {key} = {with_unit(value, unit)} is outside the physical range "
            f"{rng.describe(unit)} ({rng.why})"
        )


def check_combination(*, r: float, i_r: float, a1: float, v_max: float, tau_max: float) -> None:
    """Raise :class:`ParameterError` when the values together leave nothing to plan:

    * the cart force limit F_max = tau_max·i_r/r must exceed the Coulomb friction a1, the force that
      holds the cart at rest (φ(0⁺) = a1): otherwise the axis cannot move at all. Between a1 and the
      saturated dry friction a1 + a3·π/2 the axis moves, up to the speed where friction takes the
      whole force (φ(v_f) = F_max); the planner and the reference laws handle such an axis, so it is
      not refused (docs/parameters.md, "Physical ranges");
    * the motor speed at v_max, v_max·i_r/r, must stay below :data:`MAX_MOTOR_SPEED_RAD_S`.
    """
    f_max = tau_max * i_r / r
    if f_max <= a1:
        raise ParameterError(
            f"parameters tau_max = {tau_max} N·m, i_r = {i_r}, r = {r} m give a cart force limit "
            f"F_max = tau_max·i_r/r = {f_max:.6g} N, not above the Coulomb friction a1 = {a1} N: "
            "the axis cannot move"
        )
    speed = v_max * i_r / r
    if speed > MAX_MOTOR_SPEED_RAD_S:
        raise ParameterError(
            f"parameters v_max = {v_max} m/s, i_r = {i_r}, r = {r} m ask the motor for "
            f"v_max·i_r/r = {speed:.6g} rad/s ({speed * 60 / (2 * math.pi):.6g} rpm), above the fastest "
            f"motor of the class, {MAX_MOTOR_SPEED_RAD_S:.6g} rad/s (60000 rpm)"
        )


def ranges_table() -> list[tuple[str, str, str]]:
    """(key, range with unit, why) per parameter, in file order: the table of ``params --help``."""
    return [(key, rng.describe(PARAMETER_UNITS[key]), rng.why) for key, rng in PARAMETER_RANGES.items()]
