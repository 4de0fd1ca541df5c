"""Properties of the parameter loader (hypothesis, derandomized): every file inside the documented
ranges loads to the same values; every value outside is refused naming the key, the value, the range
and the unit; the combination rules refuse exactly the axes they describe."""

from __future__ import annotations

import math
import tempfile
from pathlib import Path

import pytest
from axisflow.model import ParameterError, default_params, load_params, params_to_toml
from axisflow.model.parameter_ranges import MAX_MOTOR_SPEED_RAD_S, PARAMETER_RANGES, check_combination
from axisflow.model.params import PARAMETER_KEYS
from axisflow.model.transmission import Belt
from axisflow.model.units import PARAMETER_UNITS
from hypothesis import given, settings
from hypothesis import strategies as st

from .axis_strategies import axis_params, outside

DEFAULT_FILE_KEYS = tuple(k for k in PARAMETER_KEYS if f"\n{k} = " in "\n" + params_to_toml(default_params()))
"""the keys the default file gives (the terms it has on)"""
NEW_TERM_KEYS = tuple(k for k in PARAMETER_KEYS if k not in DEFAULT_FILE_KEYS)

FAST = settings(max_examples=150, derandomize=True, deadline=None, database=None)


def _load(text: str):
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "axis.toml"
        path.write_text(text)
        return load_params(path)


def _with(key: str, value: float) -> str:
    """The default file with ``key`` set to ``value`` (a key of a term the default has off is added with
    its term's other keys at 0)."""
    text = params_to_toml(default_params())
    if key in DEFAULT_FILE_KEYS:
        return text.replace(f"{key} = {getattr(default_params(), key)!r}", f"{key} = {value!r}")
    partner = {"da1": "da2", "da2": "da1"}.get(key)
    return text + f"{key} = {value!r}\n" + (f"{partner} = 0.0\n" if partner else "")


@pytest.mark.timeout(120)
@FAST
@given(axis_params())
def test_any_axis_inside_the_ranges_loads_as_written(params):
    assert _load(params_to_toml(params)) == params


@pytest.mark.timeout(120)
@FAST
@given(st.data())
def test_any_value_outside_its_range_is_refused_naming_key_value_range_and_unit(data):
    key = data.draw(st.sampled_from(PARAMETER_KEYS))
    value = data.draw(outside(key))
    text = _with(key, value)
    with pytest.raises(ParameterError) as refused:
        _load(text)
    message = str(refused.value)
    unit = PARAMETER_UNITS[key]
    assert f"parameter {key} = {value!r}" in message
    assert PARAMETER_RANGES[key].describe(unit) in message
    assert "\n" not in message


@pytest.mark.timeout(120)
@FAST
@given(st.sampled_from(PARAMETER_KEYS), st.sampled_from([math.inf, -math.inf, math.nan]))
def test_a_non_finite_value_is_refused(key, value):
    text = _with(key, value)
    with pytest.raises(ParameterError, match=rf"{key} = .*(not finite|outside)"):
        _load(text)


@pytest.mark.timeout(120)
@FAST
@given(
    tau_max=st.floats(1e-3, 1e4),
    i_r=st.floats(0.1, 1000.0),
    r=st.floats(1e-3, 0.5),
    a1=st.floats(0.0, 1e5),
    v_max=st.floats(1e-3, 20.0),
)
def test_the_combination_rules_refuse_exactly_the_axes_they_describe(tau_max, i_r, r, a1, v_max):
    from axisflow.model.friction import FrictionLaw

    belt = Belt(1e-4, 0.0, 1e-4, r, i_r)
    # i_r/r as the transmission rounds it (tau_max·i_r/r and tau_max·(i_r/r) differ in the last bit)
    cannot_move = tau_max * belt.force_per_torque <= a1
    too_fast = v_max * belt.radians_per_metre > MAX_MOTOR_SPEED_RAD_S
    law = FrictionLaw(a1=a1)
    if cannot_move or too_fast:
        with pytest.raises(ParameterError, match="F_max = tau_max·i_r/r" if cannot_move else "v_max·i_r/r"):
            check_combination(transmission=belt, tau_max=tau_max, law=law, v_max=v_max)
    else:
        check_combination(transmission=belt, tau_max=tau_max, law=law, v_max=v_max)


@pytest.mark.timeout(120)
@FAST
@given(
    f_max=st.floats(1.0, 1e4),
    a1=st.floats(0.0, 1e3),
    da1=st.floats(-1.0, 1.0),
    f0=st.floats(-2e4, 2e4),
)
def test_the_offset_and_asymmetry_rules_refuse_exactly_an_axis_that_cannot_hold_or_move(f_max, a1, da1, f0):
    """F_max must exceed |f0| (hold at rest) and c_s = a1 ± da1 ± f0 (start in each direction)."""
    from axisflow.model.friction import FrictionLaw
    from axisflow.model.transmission import LinearMotor

    law = FrictionLaw(a1=a1, f0=f0, da1=da1 * a1)
    refused = f_max <= abs(f0) or f_max <= law.forward(1).c or f_max <= law.forward(-1).c
    if refused:
        with pytest.raises(ParameterError, match=r"F_max = tau_max = .* not above the"):
            check_combination(transmission=LinearMotor(), tau_max=f_max, law=law, v_max=1.0)
    else:
        check_combination(transmission=LinearMotor(), tau_max=f_max, law=law, v_max=1.0)
