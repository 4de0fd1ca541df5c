"""Units: the SI unit of every axis parameter (used in messages and docs), and the units a logged signal
may come in with their factors to SI (:func:`signal_unit`: the one place where a foreign log's columns
are converted)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import ParameterError


def with_unit(value: object, unit: str) -> str:
    """``value`` followed by its unit, or the bare value for a dimensionless quantity ("" unit)."""
    return f"{value} {unit}" if unit else f"{value}"


PARAMETER_UNITS: dict[str, str] = {
    "m": "kg",
    "J_m": "kg·m²",
    "J_g": "kg·m²",
    "J_p": "kg·m²",
    "r": "m",
    "i_r": "",
    "L": "m",
    "a1": "N",
    "a2": "N·s/m",
    "a3": "N",
    "a4": "s/m",
    "f0": "N",
    "da1": "N",
    "da2": "N·s/m",
    "lead": "m",
    "J_s": "kg·m²",
    "v_max": "m/s",
    "tau_max": "N·m",
    "M_eq": "kg",
    "energy_accounting": "",
}

PARAMETER_MEANINGS: dict[str, str] = {
    "m": "cart (carriage + payload) mass",
    "J_m": "motor rotor inertia",
    "J_g": "gearbox inertia, referred to the motor side",
    "J_p": "inertia of one pulley (two pulleys: driving and idler)",
    "r": "pulley (or pinion) pitch radius",
    "i_r": "reduction ratio (motor speed / pulley, screw or pinion speed)",
    "L": "usable stroke: positions lie in [0, L]",
    "a1": "Coulomb friction force, a1·sign(v)",
    "a2": "viscous friction coefficient, a2·v",
    "a3": "low-speed friction amplitude, a3·atan(a4·v)",
    "a4": "low-speed friction shape, a3·atan(a4·v)",
    "f0": "constant force along +x the motor supplies (offset; gravity on an incline: m·g·sin θ)",
    "da1": "Coulomb asymmetry: a1 + da1 for v > 0, a1 − da1 for v < 0",
    "da2": "viscous asymmetry: a2 + da2 for v > 0, a2 − da2 for v < 0",
    "lead": "ball screw lead: carriage travel per screw revolution",
    "J_s": "ball screw inertia about its axis",
    "v_max": "cart velocity limit",
    "tau_max": "motor torque limit",
    "energy_accounting": "how mechanical energy of a move is counted: signed, positive or absolute",
}


# ---- units of logged signals -------------------------------------------------------------------------
# What a foreign log (a drive scope's CSV, a MATLAB file) may measure its columns in, and the factor to
# the SI unit of the joint it becomes. A joint measures one side of the transmission: the carriage
# (m, m/s, N) or the motor (rad, rad/s, N·m); a unit of a position, velocity or force names its side.

CARRIAGE_SIDE = "carriage"
"""a joint on the carriage side: position [m], velocity [m/s], effort = force on the cart [N]"""
MOTOR_SIDE = "motor"
"""a joint on the motor side: angle [rad], speed [rad/s], effort = motor torque [N·m]"""
SIGNAL_QUANTITIES = ("time", "position", "velocity", "effort")


@dataclass(frozen=True)
class SignalUnit:
    """One unit of a logged signal: ``value [SI] = value [unit] × si_per_unit``."""

    name: str
    quantity: str
    """time, position, velocity or effort"""
    side: str | None
    """:data:`CARRIAGE_SIDE`, :data:`MOTOR_SIDE`, or None: a time, or an effort measured as something
    else (a voltage, a current) that a scale turns into the force or torque of the joint's side"""
    si_per_unit: float
    needs_scale: bool = False
    """True for an effort that is not a force or a torque (V, A): it needs a scale [N or N·m per unit]"""

    @property
    def si(self) -> str:
        """The SI unit of the values once converted ("" for an effort that needs a scale)."""
        return _SI.get((self.quantity, self.side), "")


_SI = {
    ("time", None): "s",
    ("position", CARRIAGE_SIDE): "m",
    ("position", MOTOR_SIDE): "rad",
    ("velocity", CARRIAGE_SIDE): "m/s",
    ("velocity", MOTOR_SIDE): "rad/s",
    ("effort", CARRIAGE_SIDE): "N",
    ("effort", MOTOR_SIDE): "N·m",
}
_TURN = 2.0 * math.pi


def _units(quantity: str, side: str | None, table: dict[str, float], **kw: bool) -> list[SignalUnit]:
    return [SignalUnit(name, quantity, side, factor, **kw) for name, factor in table.items()]


SIGNAL_UNITS: dict[str, dict[str, SignalUnit]] = {
    quantity: {u.name: u for u in units}
    for quantity, units in {
        "time": _units("time", None, {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9}),
        "position": _units("position", CARRIAGE_SIDE, {"m": 1.0, "mm": 1e-3, "um": 1e-6, "nm": 1e-9})
        + _units("position", MOTOR_SIDE, {"rad": 1.0, "deg": math.pi / 180.0, "rev": _TURN}),
        "velocity": _units(
            "velocity", CARRIAGE_SIDE, {"m/s": 1.0, "mm/s": 1e-3, "um/s": 1e-6, "m/min": 1.0 / 60.0}
        )
        + _units(
            "velocity",
            MOTOR_SIDE,
            {"rad/s": 1.0, "deg/s": math.pi / 180.0, "rev/s": _TURN, "rpm": _TURN / 60.0},
        ),
        "effort": _units("effort", CARRIAGE_SIDE, {"N": 1.0, "kN": 1e3})
        + _units("effort", MOTOR_SIDE, {"N·m": 1.0, "mN·m": 1e-3})
        + _units("effort", None, {"V": 1.0, "A": 1.0}, needs_scale=True),
    }.items()
}
"""every unit a logged signal may be given in, by quantity and name"""

UNIT_ALIASES: dict[str, str] = {
    "sec": "s",
    "µs": "us",
    "µm": "um",
    "µm/s": "um/s",
    "Nm": "N·m",
    "N.m": "N·m",
    "N*m": "N·m",
    "mNm": "mN·m",
    "mN.m": "mN·m",
    "1/min": "rpm",
    "r/min": "rpm",
    "°": "deg",
    "°/s": "deg/s",
}
"""other spellings of the units of :data:`SIGNAL_UNITS` (as scope exports write them)"""
COUNTS = "counts"
"""a position in encoder counts (velocity: ``counts/s``), converted with a number of counts per unit of
another position unit, e.g. 131072 counts per rev or 20 counts per um"""


def signal_unit(quantity: str, name: str, counts_per: tuple[float, str] | None = None) -> SignalUnit:
    """The unit ``name`` of a logged ``quantity`` (time, position, velocity, effort), aliases taken.

    ``counts`` (a position) and ``counts/s`` (a velocity) need ``counts_per`` = (counts, unit): that many
    counts per one ``unit`` of position (e.g. (131072, "rev")); the side is that unit's. A
    :class:`ParameterError` names an unknown unit and lists the known ones."""
    table = SIGNAL_UNITS[quantity]
    canonical = UNIT_ALIASES.get(name.strip(), name.strip())
    counted = {"position": COUNTS, "velocity": f"{COUNTS}/s"}.get(quantity)
    if canonical == counted:
        if counts_per is None:
            raise ParameterError(
                f"{quantity} unit {name!r} needs the counts per unit of position (e.g. 131072/rev, 20/um)"
            )
        per = counts_unit(*counts_per)
        return SignalUnit(canonical, quantity, per.side, per.si_per_unit)
    unit = table.get(canonical)
    if unit is None:
        known = ", ".join([*table, *([counted] if counted else [])])
        raise ParameterError(f"{quantity} unit {name!r} is not one of the known ones: {known}")
    return unit


def counts_unit(counts: float, per: str) -> SignalUnit:
    """One encoder count as a position unit: ``counts`` counts per one ``per`` (a position unit)."""
    if not (math.isfinite(counts) and counts > 0.0):
        raise ParameterError(f"counts per unit = {counts} must be a finite number > 0")
    unit = signal_unit("position", per)
    return SignalUnit(COUNTS, "position", unit.side, unit.si_per_unit / counts)
