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
from .friction import FrictionLaw
from .transmission import Transmission
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
    "J_p": ParameterRange(1e-8, 1.0, "a 3 mm plastic pulley to a 0.5 m steel drum (or a pinion)"),
    "r": ParameterRange(
        1e-3, 0.5, "pitch radius: a 10-tooth pulley of 2 mm pitch (3 mm) to a 0.5 m drum of a heavy gantry"
    ),
    "i_r": ParameterRange(0.1, 1000.0, "a 1:10 step-up belt stage to a three-stage 1000:1 reducer"),
    "lead": ParameterRange(1e-4, 0.2, "a 0.1 mm/rev precision screw to a 200 mm/rev high-helix one"),
    "J_s": ParameterRange(0.0, 1.0, "a screw's inertia: ~1e-7 kg·m² for 6 mm, ~0.1 kg·m² for 80 mm × 6 m"),
    "L": ParameterRange(1e-2, 50.0, "a 1 cm micro stage to a 50 m gantry (belt axes are built to ~12 m)"),
    "a1": ParameterRange(0.0, 1e5, "up to ten times the working tension of the widest steel-cord belts"),
    "a2": ParameterRange(0.0, 1e5, "up to 1e5 N of viscous drag at 1 m/s (the default axis: 215 N)"),
    "a3": ParameterRange(0.0, 1e5, "as a1: the low-speed friction is a part of the dry friction"),
    "a4": ParameterRange(
        0.0, 1e4, "1/a4 is the speed where the low-speed term reaches a3·π/4, down to 0.1 mm/s; 0: no term"
    ),
    "f0": ParameterRange(
        -1e5, 1e5, "a constant force along +x of either sign: gravity on 10 t lifted vertically is ~1e5 N"
    ),
    "da1": ParameterRange(-1e5, 1e5, "as a1, of either sign; a1 ± da1 must both stay ≥ 0"),
    "da2": ParameterRange(-1e5, 1e5, "as a2, of either sign; a2 ± da2 must both stay ≥ 0"),
    "v_max": ParameterRange(1e-3, 20.0, "1 mm/s to 20 m/s (the fastest belt axes run at 5–10 m/s)"),
    "tau_max": ParameterRange(
        1e-3,
        1e4,
        "a micro servo's peak torque (1 mN·m) to a large torque motor's (linear motor: force, N)",
    ),
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


def _through(transmission: Transmission, limit: str, value: float, unit: str) -> tuple[str, str]:
    """(the values given, the formula) of a limit carried to the carriage by ``transmission``."""
    k = transmission
    if k.kind == "ball-screw":
        given = f"{limit} = {value} {unit}, i_r = {k.i_r}, lead = {k.lead} m"  # type: ignore[attr-defined]
        return given, f"{limit}·2π·i_r/lead"
    if k.keys:
        given = f"{limit} = {value} {unit}, i_r = {k.i_r}, r = {k.r} m"  # type: ignore[attr-defined]
        return given, f"{limit}·i_r/r"
    return f"{limit} = {value} {'N' if limit == 'tau_max' else unit}", limit


def check_combination(*, transmission: Transmission, tau_max: float, law: FrictionLaw, v_max: float) -> None:
    """Raise :class:`ParameterError` when the values together leave nothing to plan:

    * the asymmetry must leave each direction's friction ≥ 0: a1 ± da1 ≥ 0, a2 ± da2 ≥ 0;
    * the cart force limit F_max = tau_max/k (a belt: tau_max·i_r/r) must exceed |f0|, the force that
      holds the cart at rest against the constant load, and the force that starts it in each
      direction, φ_s(0⁺) = c_s = a1 ± da1 ± f0 (the Coulomb friction a1 of the paper's axis):
      otherwise the axis cannot hold itself or cannot move. Between c_s and the saturated dry friction
      c_s + a3·π/2 the axis moves, up to the speed where friction takes the whole force
      (φ_s(v_f) = F_max); the planner and the reference laws handle such an axis, so it is not
      refused (docs/parameters.md, "Physical ranges");
    * for a rotary motor, the motor speed at v_max, v_max/k, must stay below
      :data:`MAX_MOTOR_SPEED_RAD_S`.
    """
    for name, mean, delta, unit in (("a1", law.a1, law.da1, "N"), ("a2", law.a2, law.da2, "N·s/m")):
        if abs(delta) > mean:
            raise ParameterError(
                f"parameters {name} = {mean} {unit}, d{name} = {delta} {unit} give a negative friction "
                f"{name} - |d{name}| = {mean - abs(delta):.6g} {unit} in one direction: |d{name}| must not "
                f"exceed {name}"
            )
    f_max = tau_max * transmission.force_per_torque
    given, formula = _through(transmission, "tau_max", tau_max, "N·m")
    head = f"parameters {given} give a cart force limit F_max = {formula} = {f_max:.6g} N, not above"
    if f_max <= abs(law.f0):
        raise ParameterError(
            f"{head} the constant force |f0| = {abs(law.f0):.6g} N: the axis cannot hold itself at rest"
        )
    if law.is_symmetric and f_max <= law.a1:
        raise ParameterError(f"{head} the Coulomb friction a1 = {law.a1} N: the axis cannot move")
    for direction, label, sign in ((1.0, "+x", "+"), (-1.0, "-x", "-")):
        c = law.forward(direction).c
        if f_max <= c:
            raise ParameterError(
                f"{head} the force c = a1 {sign} da1 {sign} f0 = {c:.6g} N that friction and load oppose to "
                f"a move towards {label} from rest: the axis cannot move that way"
            )
    speed = v_max * transmission.radians_per_metre
    if transmission.keys and speed > MAX_MOTOR_SPEED_RAD_S:
        given, formula = _through(transmission, "v_max", v_max, "m/s")
        raise ParameterError(
            f"parameters {given} ask the motor for {formula} = {speed:.6g} rad/s "
            f"({speed * 60 / (2 * math.pi):.6g} rpm), above the fastest motor of the class, "
            f"{MAX_MOTOR_SPEED_RAD_S:.6g} rad/s (60000 rpm)"
        )


def ranges_table(keys: tuple[str, ...] | None = None) -> list[tuple[str, str, str]]:
    """(key, range with unit, why) per parameter (``keys``: those only, e.g. one transmission kind's),
    in file order: the table of ``params --help``."""
    chosen = PARAMETER_RANGES if keys is None else {k: PARAMETER_RANGES[k] for k in keys}
    return [(key, rng.describe(PARAMETER_UNITS[key]), rng.why) for key, rng in chosen.items()]


def kind_ranges(kind: str) -> list[tuple[str, str, str]]:
    """The ranges of one transmission kind's keys (:mod:`.transmission`)."""
    from .transmission import TRANSMISSION_KINDS

    return ranges_table(TRANSMISSION_KINDS[kind].keys)
