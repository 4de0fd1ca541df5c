"""Hypothesis strategies for axis parameters inside (and just outside) their physical ranges.

Every value is drawn log-uniformly over its range (and its ends), so that a 1 g cart and a 10 t one are
equally likely; the composite :func:`axis_params` keeps the two combination rules of
:mod:`axisflow.model.parameter_ranges` (F_max above a1, the motor speed at v_max below the fastest
motor) by drawing the dependent values inside what the others leave.
"""

from __future__ import annotations

import math

from axisflow.model import AxisParams, EnergyAccounting, default_params
from axisflow.model.parameter_ranges import MAX_MOTOR_SPEED_RAD_S, PARAMETER_RANGES
from axisflow.model.params import AXIS_KEYS
from axisflow.model.transmission import Belt
from hypothesis import strategies as st


def log_uniform(lo: float, hi: float) -> st.SearchStrategy[float]:
    """10^u with u uniform in [log10 lo, log10 hi] (0 < lo ≤ hi), and one time in five an end."""
    if lo >= hi:
        return st.just(lo)
    inner = st.floats(math.log10(lo), math.log10(hi)).map(lambda e: min(max(10.0**e, lo), hi))
    return st.one_of(inner, inner, inner, inner, st.sampled_from([lo, hi]))


def in_range(key: str, hi: float | None = None, lo: float | None = None) -> st.SearchStrategy[float]:
    """A value inside the range of ``key`` (optionally narrowed to [lo, hi]); ranges from 0 also
    draw 0 and values down to 1e-9 of the top."""
    rng = PARAMETER_RANGES[key]
    top = rng.high if hi is None else min(hi, rng.high)
    bottom = rng.low if lo is None else max(lo, rng.low)
    if bottom > 0.0:
        return log_uniform(bottom, top)
    return st.one_of(st.just(0.0), log_uniform(1e-9 * top, top))


@st.composite
def axis_params(draw: st.DrawFn, accounting: EnergyAccounting | None = None) -> AxisParams:
    """Parameters inside every range and both combination rules."""
    r = draw(in_range("r"))
    v_lo = PARAMETER_RANGES["v_max"].low
    i_r = draw(in_range("i_r", hi=MAX_MOTOR_SPEED_RAD_S * r / v_lo * (1.0 - 1e-9)))
    v_max = draw(in_range("v_max", hi=MAX_MOTOR_SPEED_RAD_S * r / i_r * (1.0 - 1e-9)))
    tau_hi = PARAMETER_RANGES["tau_max"].high
    a1 = draw(in_range("a1", hi=0.5 * tau_hi * i_r / r))
    tau_max = draw(in_range("tau_max", lo=a1 * r / i_r * (1.0 + 1e-9)))
    values = {key: draw(in_range(key)) for key in ("m", "J_m", "J_g", "J_p", "L", "a2", "a3", "a4")}
    chosen = accounting or draw(st.sampled_from(list(EnergyAccounting)))
    belt = Belt(**{k: values.pop(k) for k in ("J_m", "J_g", "J_p")}, r=r, i_r=i_r)
    return AxisParams(
        transmission=belt, v_max=v_max, a1=a1, tau_max=tau_max, energy_accounting=chosen, **values
    )


@st.composite
def sibling_params(draw: st.DrawFn) -> AxisParams:
    """The default axis with every parameter scaled by 10^u, u uniform in [−1, 1] (clipped to its
    range; the combination rules kept by drawing again): the realistic neighbourhood, where the
    time-energy optimum is interior and the torque limit decides."""
    nominal = default_params()
    scaled = {}
    for key in (*AXIS_KEYS, *Belt.keys, "a1", "a2", "a3", "a4"):
        rng = PARAMETER_RANGES[key]
        factor = 10.0 ** draw(st.floats(-1.0, 1.0))
        scaled[key] = min(max(getattr(nominal, key) * factor, rng.low), rng.high)
    scaled["tau_max"] = max(scaled["tau_max"], 1.5 * scaled["a1"] * scaled["r"] / scaled["i_r"])
    scaled["v_max"] = min(scaled["v_max"], 0.5 * MAX_MOTOR_SPEED_RAD_S * scaled["r"] / scaled["i_r"])
    accounting = draw(st.sampled_from(list(EnergyAccounting)))
    belt = Belt(**{k: scaled.pop(k) for k in Belt.keys})
    return AxisParams(transmission=belt, energy_accounting=accounting, **scaled)


def outside(key: str) -> st.SearchStrategy[float]:
    """A finite value outside the range of ``key``: below its low end (or at it, when open) or above
    its high end, by up to 300 orders of magnitude."""
    rng = PARAMETER_RANGES[key]
    above = st.floats(rng.high, 1e300, exclude_min=True, allow_nan=False)
    below = (
        st.floats(-1e300, rng.low, exclude_max=not rng.low_open, allow_nan=False)
        if rng.low > 0.0 or not rng.low_open
        else st.floats(-1e300, 0.0, allow_nan=False)
    )
    return st.one_of(above, below)
