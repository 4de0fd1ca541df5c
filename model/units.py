"""SI units of every axis parameter, used in messages and docs."""

from __future__ import annotations


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
