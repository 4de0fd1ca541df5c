"""Parameters of the axis model, eq. (1) of the paper, loaded from validated TOML.

A parameter file is a flat TOML table with exactly the keys of :class:`AxisParams` (SI units, see
:data:`axisflow.model.units.PARAMETER_UNITS`). The package ships a default
(``default_axis.toml``); any other file can be given with ``--params FILE``.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from enum import StrEnum
from pathlib import Path
from typing import Any

from .errors import ParameterError
from .parameter_ranges import PARAMETER_RANGES, check_combination, check_range
from .toml_file import read_toml
from .units import PARAMETER_UNITS, with_unit

DEFAULT_PARAMS_RESOURCE = "default_axis.toml"


class EnergyAccounting(StrEnum):
    """How the mechanical energy of a move is counted.

    ``signed``: E = ∫F·ẋ dt, as printed in eq. (3); braking energy is credited back.
    ``positive``: E = ∫max(F·ẋ, 0) dt; the drive does not regenerate (braking is free, not refunded).
    ``absolute``: E = ∫|F·ẋ| dt; braking costs as much as driving.
    """

    SIGNED = "signed"
    POSITIVE = "positive"
    ABSOLUTE = "absolute"


@dataclass(frozen=True)
class AxisParams:
    """Physical parameters of the belt-driven axis (SI units), each inside its physical range and
    together describing an axis that can move (:mod:`.parameter_ranges`)."""

    m: float
    """cart mass [kg]"""
    J_m: float
    """motor rotor inertia [kg·m²]"""
    J_g: float
    """gearbox inertia referred to the motor [kg·m²]"""
    J_p: float
    """inertia of one pulley [kg·m²]"""
    r: float
    """pulley radius [m]"""
    i_r: float
    """gear reduction ratio [-]"""
    L: float
    """stroke [m]; positions lie in [0, L]"""
    a1: float
    """Coulomb friction [N]"""
    a2: float
    """viscous friction [N·s/m]"""
    a3: float
    """low-speed friction amplitude [N]"""
    a4: float
    """low-speed friction shape [s/m]"""
    v_max: float
    """cart velocity limit [m/s]"""
    tau_max: float
    """motor torque limit [N·m]"""
    energy_accounting: EnergyAccounting = EnergyAccounting.POSITIVE

    def __post_init__(self) -> None:
        for name in PARAMETER_RANGES:
            value = getattr(self, name)
            unit = PARAMETER_UNITS[name]
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise ParameterError(
                    f"parameter {name} must be a number{f' in {unit}' if unit else ''}, got {value!r}"
                )
            if not math.isfinite(value):
                raise ParameterError(f"parameter {name} = {with_unit(value, unit)} is not finite")
            check_range(name, value)
            object.__setattr__(self, name, float(value))
        check_combination(
            r=self.r,
            i_r=self.i_r,
            a1=self.a1,
            v_max=self.v_max,
            tau_max=self.tau_max,
        )
        try:
            accounting = EnergyAccounting(self.energy_accounting)
        except ValueError:
            choices = ", ".join(e.value for e in EnergyAccounting)
            raise ParameterError(
                f"parameter energy_accounting = {self.energy_accounting!r} is not one of: {choices}"
            ) from None
        object.__setattr__(self, "energy_accounting", accounting)

    @property
    def M_eq(self) -> float:
        """Equivalent translating mass [kg]: m + ((J_m + J_g)·i_r² + 2·J_p)/r² (eq. 1)."""
        return self.m + ((self.J_m + self.J_g) * self.i_r**2 + 2.0 * self.J_p) / self.r**2

    @property
    def force_per_torque(self) -> float:
        """Cart force per motor torque [N/(N·m)] = i_r / r."""
        return self.i_r / self.r

    @property
    def f_max(self) -> float:
        """Cart force equivalent of the motor torque limit [N]."""
        return self.tau_max * self.i_r / self.r

    def with_equivalent_mass(self, M_eq: float) -> AxisParams:
        """A copy whose equivalent mass is ``M_eq`` [kg]: the change goes into the cart mass m (the rotor,
        gearbox and pulley inertias keep their values) — how a refit or an adapted M_eq becomes a
        parameter file. A :class:`ParameterError` when ``M_eq`` is not above the rotating parts' share."""
        rotating = self.M_eq - self.m
        m = M_eq - rotating
        if not m > 0.0:
            raise ParameterError(
                f"M_eq = {M_eq:.6g} kg is not above the rotating parts' share {rotating:.6g} kg of the "
                "parameters: no cart mass would be left"
            )
        return self.replace(m=m)

    def replace(self, **changes: Any) -> AxisParams:
        """A copy with some fields changed (validated again)."""
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        """The effective parameters as plain JSON-ready values (SI units), M_eq included."""
        out: dict[str, Any] = {name: getattr(self, name) for name in PARAMETER_KEYS}
        out["M_eq"] = self.M_eq
        out["energy_accounting"] = self.energy_accounting.value
        return out


PARAMETER_KEYS: tuple[str, ...] = tuple(
    f.name for f in dataclasses.fields(AxisParams) if f.name != "energy_accounting"
)
FILE_KEYS: tuple[str, ...] = (*PARAMETER_KEYS, "energy_accounting")


def params_from_mapping(data: dict[str, Any], source: str = "parameters") -> AxisParams:
    """Validate a flat mapping into :class:`AxisParams`; unknown or missing keys are errors."""
    unknown = sorted(set(data) - set(FILE_KEYS))
    if unknown:
        given = ", ".join(f"{k} = {data[k]!r}" for k in unknown)
        raise ParameterError(f"{source}: unknown key(s) {given}; allowed keys: {', '.join(FILE_KEYS)}")
    missing = [k for k in FILE_KEYS if k not in data]
    if missing:
        units = ", ".join(f"{k} [{PARAMETER_UNITS[k]}]" if PARAMETER_UNITS[k] else k for k in missing)
        raise ParameterError(f"{source}: missing key(s) {units}")
    try:
        return AxisParams(**data)
    except ParameterError as exc:
        raise ParameterError(f"{source}: {exc}") from None


def load_params(path: str | Path | None = None) -> AxisParams:
    """Load parameters from a TOML file, or the packaged default when ``path`` is None."""
    data, source = read_toml(
        path, package=__package__, resource=DEFAULT_PARAMS_RESOURCE, kind="parameter", error=ParameterError
    )
    return params_from_mapping(data, source)


def default_params() -> AxisParams:
    """The packaged default parameter set (an estimate; see docs/parameters.md)."""
    return load_params(None)


def params_to_toml(params: AxisParams) -> str:
    """Serialise parameters to the TOML file format read by :func:`load_params`."""
    lines = []
    for key in PARAMETER_KEYS:
        unit = PARAMETER_UNITS[key]
        lines.append(f"{key} = {getattr(params, key)!r}" + (f"  # {unit}" if unit else ""))
    lines.append(f'energy_accounting = "{params.energy_accounting.value}"')
    return "\n".join(lines) + "\n"
