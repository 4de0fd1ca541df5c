"""Parameters of the axis model, eq. (1) of the paper with its terms, loaded from validated TOML.

A parameter file is a TOML table of SI values (units: :data:`axisflow.model.units.PARAMETER_UNITS`):

* the carriage and the limits: ``m``, ``L``, ``v_max``, ``tau_max``, ``energy_accounting``;
* the transmission (:mod:`.transmission`): a ``[transmission]`` table with its ``kind`` and the
  kind's keys, or, for a belt, those keys at the top level (the files of the paper's axis:
  ``J_m``, ``J_g``, ``J_p``, ``r``, ``i_r``);
* the friction law (:mod:`.friction`): a term is **on when its keys are given** (:mod:`.terms`):
  ``a1`` coulomb, ``a2`` viscous, ``f0`` offset, ``da1`` and ``da2`` asymmetry, ``a3`` and ``a4``
  atan (the keys of a two-key term come together). A file of the paper's shape (a1…a4) has the
  paper's three terms on and means what it always meant.

The package ships a default (``default_axis.toml``); any other file can be given with ``--params FILE``.
"""

from __future__ import annotations

import copy
import dataclasses
import math
from dataclasses import dataclass
from enum import StrEnum
from functools import lru_cache
from pathlib import Path
from typing import Any

from .errors import ParameterError
from .friction import ForwardLaw, FrictionLaw
from .parameter_ranges import PARAMETER_RANGES, check_combination, check_range
from .terms import LAW_TERMS, PAPER_TERMS, TERMS, canonical_terms
from .toml_file import read_toml
from .transmission import DEFAULT_KIND, TRANSMISSION_KINDS, Belt, Transmission
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


AXIS_KEYS: tuple[str, ...] = ("m", "L", "v_max", "tau_max")
"""the keys every file gives beside its transmission and its friction terms"""
FRICTION_KEYS: tuple[str, ...] = ("a1", "a2", "a3", "a4", "f0", "da1", "da2")
"""the friction law's keys (:data:`axisflow.model.friction.FRICTION_PARAMETERS`)"""


def _number(name: str, value: Any) -> float:
    unit = PARAMETER_UNITS[name]
    if isinstance(value, bool) or not isinstance(value, int | float):
        in_unit = f" in {unit}" if unit else ""
        raise ParameterError(f"parameter {name} must be a number{in_unit}, got {value!r}")
    if not math.isfinite(value):
        raise ParameterError(f"parameter {name} = {with_unit(value, unit)} is not finite")
    check_range(name, value)
    return float(value)


@dataclass(frozen=True)
class AxisParams:
    """Physical parameters of the axis (SI units), each inside its physical range and together
    describing an axis that can move and hold itself (:mod:`.parameter_ranges`).

    The transmission's keys read through: ``params.r`` of a belt axis is its pulley radius."""

    m: float
    """carriage (and payload) mass [kg]"""
    transmission: Transmission
    """how the motor moves the carriage (:mod:`.transmission`)"""
    L: float
    """stroke [m]; positions lie in [0, L]"""
    v_max: float
    """cart velocity limit [m/s]"""
    tau_max: float
    """motor torque limit [N·m] (a linear motor's force limit [N])"""
    a1: float = 0.0
    """Coulomb friction [N]"""
    a2: float = 0.0
    """viscous friction [N·s/m]"""
    a3: float = 0.0
    """low-speed friction amplitude [N]"""
    a4: float = 0.0
    """low-speed friction shape [s/m]"""
    f0: float = 0.0
    """constant force along +x the motor supplies [N] (gravity on an incline: m·g·sin θ)"""
    da1: float = 0.0
    """Coulomb asymmetry [N]: a1 + da1 towards +x, a1 − da1 towards −x"""
    da2: float = 0.0
    """viscous asymmetry [N·s/m]: a2 + da2 towards +x, a2 − da2 towards −x"""
    energy_accounting: EnergyAccounting = EnergyAccounting.POSITIVE
    terms: tuple[str, ...] = ()
    """the friction law's terms that are on (:mod:`.terms`): those named here and every term with a
    non-zero value; a term that is off has zero values"""

    def __post_init__(self) -> None:
        for name in (*AXIS_KEYS, *FRICTION_KEYS):
            object.__setattr__(self, name, _number(name, getattr(self, name)))
        if not isinstance(self.transmission, Transmission):
            raise ParameterError(f"transmission {self.transmission!r} is not a transmission record")
        for key in self.transmission.keys:
            _number(key, getattr(self.transmission, key))
        object.__setattr__(self, "terms", self._terms_on())
        law = self.friction
        check_combination(transmission=self.transmission, tau_max=self.tau_max, law=law, v_max=self.v_max)
        try:
            accounting = EnergyAccounting(self.energy_accounting)
        except ValueError:
            choices = ", ".join(e.value for e in EnergyAccounting)
            raise ParameterError(
                f"parameter energy_accounting = {self.energy_accounting!r} is not one of: {choices}"
            ) from None
        object.__setattr__(self, "energy_accounting", accounting)

    def _terms_on(self) -> tuple[str, ...]:
        named = canonical_terms(tuple(self.terms))
        off_law = [t for t in named if t not in LAW_TERMS]
        if off_law:
            raise ParameterError(
                f"terms {', '.join(off_law)} are not terms of the friction law ({', '.join(LAW_TERMS)})"
            )
        nonzero = {t for t in LAW_TERMS if any(getattr(self, p) != 0.0 for p in TERMS[t].parameters)}
        return canonical_terms(set(named) | nonzero)

    def __getattr__(self, name: str) -> Any:
        # only reached for names that are not fields: the transmission's keys (params.r of a belt)
        if name.startswith("__") or name == "transmission":
            raise AttributeError(name)
        transmission = self.__dict__.get("transmission")
        if transmission is not None and name in transmission.keys:
            return getattr(transmission, name)
        kind = transmission.kind if transmission is not None else "?"
        raise AttributeError(f"the axis parameters have no {name!r} (transmission kind {kind})")

    @property
    def kind(self) -> str:
        """The transmission's kind (``belt``, ``ball-screw``, ``rack-pinion``, ``linear-motor``)."""
        return self.transmission.kind

    @property
    def M_eq(self) -> float:
        """Equivalent translating mass [kg]: m + the transmission's reflected inertia (eq. 1 for a
        belt: m + ((J_m + J_g)·i_r² + 2·J_p)/r²)."""
        return self.m + self.transmission.reflected_mass_kg()

    @property
    def force_per_torque(self) -> float:
        """Cart force per motor torque [N/(N·m)]: i_r/r for a belt (:mod:`.transmission`)."""
        return self.transmission.force_per_torque

    @property
    def f_max(self) -> float:
        """Cart force equivalent of the motor torque limit [N]."""
        return self.tau_max * self.transmission.force_per_torque

    @property
    def friction(self) -> FrictionLaw:
        """The friction law (:mod:`.friction`)."""
        return FrictionLaw(self.a1, self.a2, self.a3, self.a4, self.f0, self.da1, self.da2)

    def forward(self, direction: float) -> ForwardLaw:
        """φ_s, the friction along a move in ``direction`` (its sign) in the move's frame."""
        return self.friction.forward(direction)

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
        """A copy with some fields changed (validated again); the transmission's keys (``r``, ``lead``,
        …) change the transmission."""
        moved = {k: changes.pop(k) for k in list(changes) if k in self.transmission.keys}
        if moved:
            changes["transmission"] = self.transmission.replace(**moved)
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        """The effective parameters as plain JSON-ready values (SI units), M_eq included; the keys of
        a parameter file (:func:`params_from_mapping` reads it back)."""
        out: dict[str, Any] = {"m": self.m}
        if self.transmission.kind == DEFAULT_KIND:
            out.update({k: getattr(self.transmission, k) for k in self.transmission.keys})
        else:
            out["transmission"] = self.transmission.to_dict()
        out["L"] = self.L
        out.update({k: getattr(self, k) for k in self.friction_keys})
        out["v_max"] = self.v_max
        out["tau_max"] = self.tau_max
        out["M_eq"] = self.M_eq
        out["energy_accounting"] = self.energy_accounting.value
        return out

    @property
    def friction_keys(self) -> tuple[str, ...]:
        """The keys of the terms that are on, in file order (a1, a2, a3, a4, f0, da1, da2)."""
        on = {p for t in self.terms for p in TERMS[t].parameters}
        return tuple(k for k in FRICTION_KEYS if k in on)


@lru_cache(maxsize=512)
def _forward_axis(params: AxisParams, direction: float) -> AxisParams:
    axis = copy.copy(params)
    a1, a2 = params.a1 + direction * params.da1, params.a2 + direction * params.da2
    for name, value in (("a1", a1), ("a2", a2), ("f0", direction * params.f0), ("da1", 0.0), ("da2", 0.0)):
        object.__setattr__(axis, name, value)
    return axis


def forward_axis(params: AxisParams, direction: float) -> AxisParams:
    """The axis as a move in ``direction`` (its sign) sees it, in the move's forward frame: a1 and a2
    the Coulomb and viscous friction of that direction, f0 the load along the motion (s·f0), no
    asymmetry; its forward law towards +x, φ(v) = a1 + f0 + a2·v + a3·atan(a4·v), is φ_s of the
    real axis (:mod:`.friction`), and f0 alone is the force at rest (Coulomb sign 0). The paper's
    axis (no offset, no asymmetry) is returned as it is; otherwise a cached copy, **not validated**
    (the copy of one direction need not hold in the other). For the planner, which works in a move's
    forward frame; never a parameter file."""

    if params.f0 == 0.0 and params.da1 == 0.0 and params.da2 == 0.0:
        return params
    return _forward_axis(params, 1.0 if direction >= 0.0 else -1.0)


PARAMETER_KEYS: tuple[str, ...] = ("m", *Belt.keys, "L", *FRICTION_KEYS, "v_max", "tau_max")
"""the keys of a belt axis's file with every term on, in file order (the paper's axis: a1…a4 only)"""
FILE_KEYS: tuple[str, ...] = (*PARAMETER_KEYS, "energy_accounting", "transmission")
"""every key a parameter file may have at its top level"""
_TRANSMISSION_TOP_KEYS = tuple(dict.fromkeys(k for cls in TRANSMISSION_KINDS.values() for k in cls.keys))


def _with_units(keys: list[str]) -> str:
    """``key [unit], …`` for a message (a dimensionless key bare)."""
    return ", ".join(f"{k} [{PARAMETER_UNITS[k]}]" if PARAMETER_UNITS[k] else k for k in keys)


def _transmission_from(data: dict[str, Any], source: str) -> Transmission:
    table = data.get("transmission")
    if table is None:  # the paper's flat belt keys
        missing = [k for k in Belt.keys if k not in data]
        if missing:
            raise ParameterError(f"{source}: missing key(s) {_with_units(missing)}")
        return Belt(**{k: _number(k, data[k]) for k in Belt.keys})
    if not isinstance(table, dict):
        raise ParameterError(f"{source}: transmission must be a table ([transmission]), got {table!r}")
    flat = [k for k in _TRANSMISSION_TOP_KEYS if k in data]
    if flat:
        raise ParameterError(
            f"{source}: key(s) {', '.join(flat)} belong in the [transmission] table when it is given"
        )
    kind = table.get("kind")
    cls = TRANSMISSION_KINDS.get(kind) if isinstance(kind, str) else None
    if cls is None:
        raise ParameterError(
            f"{source}: [transmission] kind = {kind!r} is not one of: {', '.join(TRANSMISSION_KINDS)}"
        )
    unknown = sorted(set(table) - {"kind", *cls.keys})
    if unknown:
        allowed = ", ".join(cls.keys) or "none"
        raise ParameterError(
            f"{source}: unknown key(s) {', '.join(unknown)} in [transmission] of kind {kind}; "
            f"its keys: {allowed}"
        )
    missing = [k for k in cls.keys if k not in table]
    if missing:
        raise ParameterError(
            f"{source}: [transmission] of kind {kind} is missing key(s) {_with_units(missing)}"
        )
    return cls(**{k: _number(k, table[k]) for k in cls.keys})


def params_from_mapping(data: dict[str, Any], source: str = "parameters") -> AxisParams:
    """Validate a parameter mapping (the module docstring's format) into :class:`AxisParams`;
    unknown or missing keys are errors. ``M_eq`` (of :meth:`AxisParams.to_dict`) is not a key."""
    allowed = set(FILE_KEYS) | set(_TRANSMISSION_TOP_KEYS)
    unknown = sorted(set(data) - allowed)
    if unknown:
        given = ", ".join(f"{k} = {data[k]!r}" for k in unknown)
        keys = ", ".join((*FILE_KEYS, *(k for k in _TRANSMISSION_TOP_KEYS if k not in FILE_KEYS)))
        raise ParameterError(f"{source}: unknown key(s) {given}; allowed keys: {keys}")
    missing = [k for k in (*AXIS_KEYS, "energy_accounting") if k not in data]
    if missing:
        raise ParameterError(f"{source}: missing key(s) {_with_units(missing)}")
    for term in LAW_TERMS:
        term_keys = TERMS[term].parameters
        present = [k for k in term_keys if k in data]
        if present and len(present) < len(term_keys):
            lacking = [k for k in term_keys if k not in data]
            raise ParameterError(
                f"{source}: the {term} term's keys {' and '.join(term_keys)} go together: "
                f"{', '.join(lacking)} is missing (give all of them, or none to switch the term off)"
            )
    terms = tuple(t for t in LAW_TERMS if TERMS[t].parameters and TERMS[t].parameters[0] in data)
    try:
        transmission = _transmission_from(data, source)
        values = {k: data[k] for k in (*AXIS_KEYS, *FRICTION_KEYS) if k in data}
        return AxisParams(
            transmission=transmission,
            energy_accounting=data["energy_accounting"],
            terms=terms,
            **values,
        )
    except ParameterError as exc:
        text = str(exc)
        raise ParameterError(text if text.startswith(source) else f"{source}: {text}") from None


def load_params(path: str | Path | None = None) -> AxisParams:
    """Load parameters from a TOML file, or the packaged default when ``path`` is None."""
    data, source = read_toml(
        path, package=__package__, resource=DEFAULT_PARAMS_RESOURCE, kind="parameter", error=ParameterError
    )
    return params_from_mapping(data, source)


def given_keys(path: str | Path | None) -> frozenset[str]:
    """The parameter keys a file gives itself (its transmission's keys included; none for the packaged
    default, ``path`` None): what a refit may take as the user's own values."""
    if path is None:
        return frozenset()
    data, _ = read_toml(
        path, package=__package__, resource=DEFAULT_PARAMS_RESOURCE, kind="parameter", error=ParameterError
    )
    table = data.get("transmission")
    inner = set(table) - {"kind"} if isinstance(table, dict) else set()
    return frozenset((set(data) - {"transmission"}) | inner)


def default_params() -> AxisParams:
    """The packaged default parameter set (an estimate; see docs/parameters.md)."""
    return load_params(None)


def params_to_toml(params: AxisParams) -> str:
    """Serialise parameters to the TOML file format read by :func:`load_params` (a belt's keys at the
    top level as in the paper's files; another kind in a ``[transmission]`` table at the end)."""

    def line(key: str, value: float) -> str:
        unit = PARAMETER_UNITS[key]
        return f"{key} = {value!r}" + (f"  # {unit}" if unit else "")

    k = params.transmission
    belt = k.kind == DEFAULT_KIND
    lines = [line("m", params.m)]
    if belt:
        lines += [line(key, getattr(k, key)) for key in k.keys]
    lines.append(line("L", params.L))
    lines += [line(key, getattr(params, key)) for key in params.friction_keys]
    lines += [line("v_max", params.v_max), line("tau_max", params.tau_max)]
    lines.append(f'energy_accounting = "{params.energy_accounting.value}"')
    if not belt:
        lines += ["", "[transmission]", f'kind = "{k.kind}"']
        lines += [line(key, getattr(k, key)) for key in k.keys]
    return "\n".join(lines) + "\n"


__all__ = [
    "PAPER_TERMS",
    "PARAMETER_RANGES",
    "AxisParams",
    "EnergyAccounting",
    "default_params",
    "forward_axis",
    "given_keys",
    "load_params",
    "params_from_mapping",
    "params_to_toml",
]
