"""The limits of a baseline profile: what a drive is set to today, and whether the axis can follow it.

A baseline (:mod:`.baseline_laws`) is the profile a drive or a motion controller runs without
axisflow: a trapezoidal velocity profile (CiA 402 profile position mode: velocity and acceleration
limits, symmetric) or a jerk-limited S-curve (velocity, acceleration and jerk limits). Its limits come
from the command line (``--limits V,A[,J]``: :func:`parse_limits`), from a ``[baseline]`` table of the
parameter file (:func:`load_baseline_limits`)::

    [baseline]
    velocity_m_s = 1.2        # the drive's profile velocity [m/s]
    acceleration_m_s2 = 2.5   # its profile acceleration = deceleration [m/s²]
    jerk_m_s3 = 25.0          # the S-curve's jerk [m/s³] (a trapezoid needs none)

or, given neither, from the axis itself (:func:`axis_limits`: the fastest baseline it can follow).

**Reachable limits.** A drive set to limits its axis cannot deliver either faults or leaves its
profile; a comparison against such a profile would be against something no axis runs.
:func:`check_reachable` therefore refuses a velocity limit above the axis's v_max and an acceleration
above what the torque limit gives at the top speed after friction: the force of eq. (1),
F(v, a) = M_eq·a + friction(v), must stay within F_max = tau_max·i_r/r at every speed the profile
reaches, in both directions. Both profiles accelerate at most at ``a`` and move at most at ``v``, and
F(v, a) rises with both, so a limit set that passes the rule keeps every move of either profile within
the torque limit; the rule is what the axis can do *on any move*, not only on the moves at hand.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..model import AxisParams, MoveError, ParameterError, cart_force, cart_force_from_torque
from ..model.toml_file import read_toml

BASELINE_LAWS: tuple[str, ...] = ("trapezoid", "scurve")
"""the baseline laws by name, as ``--law`` and ``--baseline`` accept them"""
BASELINE_TABLE = "baseline"
"""the table of a parameter file that holds the baseline's limits"""
DEFAULT_JERK_TIME_S = 0.1
"""when no jerk limit is given: the S-curve builds its acceleration up in this time, j = a / 0.1 s (a
choice, stated wherever it is used; give ``J`` to override it)"""


_HAIR = 1e-9
"""the axis's own limits are taken this fraction inside the rule's bounds, so that no rounding of a
profile's cruise speed or peak force makes the fastest baseline break them"""


class BaselineLimitError(MoveError):
    """A baseline's limits are malformed, or beyond what the axis can follow (the limit named)."""


@dataclass(frozen=True)
class BaselineLimits:
    """The velocity [m/s], acceleration [m/s²] and jerk [m/s³] limits of a baseline profile; jerk
    None: not given (a trapezoid needs none; an S-curve then uses :data:`DEFAULT_JERK_TIME_S`)."""

    velocity_m_s: float
    acceleration_m_s2: float
    jerk_m_s3: float | None = None

    def __post_init__(self) -> None:
        for name, unit in (("velocity_m_s", "m/s"), ("acceleration_m_s2", "m/s²"), ("jerk_m_s3", "m/s³")):
            value = getattr(self, name)
            if value is None and name == "jerk_m_s3":
                continue
            if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
                raise BaselineLimitError(f"baseline {name} = {value!r} is not a finite number in {unit}")
            if value <= 0.0:
                raise BaselineLimitError(f"baseline {name} = {value} {unit} must be > 0 {unit}")
            object.__setattr__(self, name, float(value))

    def jerk_for(self, law: str) -> float:
        """The jerk limit [m/s³] the law runs with: ∞ for the trapezoid (a jump in acceleration), the
        given jerk or a/:data:`DEFAULT_JERK_TIME_S` for the S-curve."""
        if law == "trapezoid":
            return math.inf
        if self.jerk_m_s3 is not None:
            return self.jerk_m_s3
        return self.acceleration_m_s2 / DEFAULT_JERK_TIME_S

    def for_law(self, law: str) -> BaselineLimits:
        """The limits as the law uses them (the S-curve's jerk filled in; the trapezoid's dropped)."""
        check_law(law)
        jerk = None if law == "trapezoid" else self.jerk_for(law)
        return BaselineLimits(self.velocity_m_s, self.acceleration_m_s2, jerk)

    def to_dict(self) -> dict[str, float | None]:
        return {
            "velocity_m_s": self.velocity_m_s,
            "acceleration_m_s2": self.acceleration_m_s2,
            "jerk_m_s3": self.jerk_m_s3,
        }

    def describe(self) -> str:
        text = f"v {self.velocity_m_s:.4g} m/s, a {self.acceleration_m_s2:.4g} m/s²"
        return text + (f", j {self.jerk_m_s3:.4g} m/s³" if self.jerk_m_s3 is not None else "")


def check_law(law: str) -> str:
    """``law`` if it is a baseline law; else a :class:`BaselineLimitError` naming the choices."""
    if law not in BASELINE_LAWS:
        raise BaselineLimitError(f"unknown baseline {law!r}; choose one of {', '.join(BASELINE_LAWS)}")
    return law


def parse_limits(text: str) -> BaselineLimits:
    """``V,A`` or ``V,A,J`` (m/s, m/s², m/s³) as given to ``--limits``."""
    parts = [p.strip() for p in text.split(",")]
    if len(parts) not in (2, 3):
        raise BaselineLimitError(
            f"--limits {text!r}: give V,A or V,A,J (velocity m/s, acceleration m/s², jerk m/s³)"
        )
    values = []
    for name, part in zip(("velocity", "acceleration", "jerk"), parts, strict=False):
        try:
            values.append(float(part))
        except ValueError:
            raise BaselineLimitError(f"--limits {text!r}: the {name} {part!r} is not a number") from None
    return BaselineLimits(*values)


def limits_from_table(table: Mapping[str, Any], source: str) -> BaselineLimits:
    """The limits of a ``[baseline]`` table (keys velocity_m_s, acceleration_m_s2 and optionally
    jerk_m_s3; any other key is an error naming it)."""
    allowed = ("velocity_m_s", "acceleration_m_s2", "jerk_m_s3")
    unknown = sorted(set(table) - set(allowed))
    if unknown:
        raise BaselineLimitError(
            f"{source}: unknown key(s) {', '.join(unknown)} in [{BASELINE_TABLE}]; "
            f"allowed: {', '.join(allowed)}"
        )
    missing = [k for k in allowed[:2] if k not in table]
    if missing:
        raise BaselineLimitError(f"{source}: [{BASELINE_TABLE}] needs {' and '.join(missing)}")
    try:
        return BaselineLimits(table["velocity_m_s"], table["acceleration_m_s2"], table.get("jerk_m_s3"))
    except BaselineLimitError as exc:
        raise BaselineLimitError(f"{source}: [{BASELINE_TABLE}] {exc}") from None


def load_baseline_limits(path: str | Path | None) -> tuple[AxisParams, BaselineLimits | None]:
    """The axis parameters of the parameter file ``path`` (None: the packaged default) and the limits
    of its ``[baseline]`` table (None when it has none). The table is taken out before the parameters
    are validated, so a file with one is a parameter file like any other."""
    from ..model.params import params_from_mapping

    data, source = read_toml(
        path,
        package="axisflow.model",
        resource="default_axis.toml",
        kind="parameter",
        error=ParameterError,
    )
    table = data.pop(BASELINE_TABLE, None)
    params = params_from_mapping(data, source)
    if table is None:
        return params, None
    if not isinstance(table, dict):
        raise BaselineLimitError(f"{source}: {BASELINE_TABLE} must be a table ([{BASELINE_TABLE}])")
    return params, limits_from_table(table, source)


def _top_force_n(v: float, a: float, params: AxisParams) -> float:
    """The largest |F| [N] of eq. (1) at speed v and acceleration a, over both directions."""
    return float(np.max(np.abs(cart_force(np.array([v, -v]), np.array([a, -a]), params))))


def reachable_acceleration(velocity_m_s: float, params: AxisParams) -> float:
    """The largest acceleration [m/s²] the torque limit gives at ``velocity_m_s`` after friction, in
    either direction: (F_max − friction(v))/M_eq, from eq. (1) (≤ 0: the axis cannot reach that speed)."""
    f_max = float(cart_force_from_torque(params.tau_max, params))
    at_rest = _top_force_n(velocity_m_s, 0.0, params)  # friction alone
    per_unit = _top_force_n(velocity_m_s, 1.0, params) - at_rest  # the force of 1 m/s² (M_eq)
    return (f_max - at_rest) / per_unit


def check_reachable(limits: BaselineLimits, params: AxisParams) -> BaselineLimits:
    """``limits`` if the axis can follow them on every move (the module docstring's rule), else a
    :class:`BaselineLimitError` naming the limit, its value and what the axis gives."""
    v, a = limits.velocity_m_s, limits.acceleration_m_s2
    if v > params.v_max:
        raise BaselineLimitError(
            f"baseline velocity limit {v:g} m/s is above the axis's v_max = {params.v_max:g} m/s"
        )
    top = reachable_acceleration(v, params)
    if top <= 0.0:
        raise BaselineLimitError(
            f"baseline velocity limit {v:g} m/s: friction at that speed takes the whole force limit "
            f"(tau_max = {params.tau_max:g} N·m)"
        )
    if a > top:
        raise BaselineLimitError(
            f"baseline acceleration limit {a:g} m/s² is above what the axis gives at {v:g} m/s: "
            f"{top:.4g} m/s² (tau_max = {params.tau_max:g} N·m after friction)"
        )
    return limits


def axis_limits(params: AxisParams) -> BaselineLimits:
    """The fastest limits the axis can follow on every move: v_max and the acceleration the torque
    limit gives at v_max after friction (no jerk given: an S-curve uses :data:`DEFAULT_JERK_TIME_S`)."""
    v = params.v_max * (1.0 - _HAIR)
    top = reachable_acceleration(v, params)
    if top <= 0.0:
        raise BaselineLimitError(
            f"the axis cannot reach its own v_max = {params.v_max:g} m/s: friction there takes the whole "
            f"force limit (tau_max = {params.tau_max:g} N·m); give --limits"
        )
    return BaselineLimits(v, top * (1.0 - _HAIR))


def baseline_limits(
    params_path: str | Path | None, limits_text: str | None
) -> tuple[AxisParams, BaselineLimits]:
    """The axis parameters of ``params_path`` and the baseline's limits, from ``limits_text``
    (``V,A[,J]``, :func:`parse_limits`), else the file's ``[baseline]`` table, else the axis itself
    (:func:`axis_limits`); refused when the axis cannot follow them (:func:`check_reachable`)."""
    params, table = load_baseline_limits(params_path)
    if limits_text is not None:
        limits = parse_limits(limits_text)
    elif table is not None:
        limits = table
    else:
        return params, axis_limits(params)
    return params, check_reachable(limits, params)
