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
from axisflow.model.units import PARAMETER_UNITS
from hypothesis import given, settings
from hypothesis import strategies as st

from .axis_strategies import axis_params, outside

FAST = settings(max_examples=150, derandomize=True, deadline=None, database=None)


def _load(text: str):
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "axis.toml"
        path.write_text(text)
        return load_params(path)


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
    text = params_to_toml(default_params()).replace(
        f"{key} = {getattr(default_params(), key)!r}", f"{key} = {value!r}"
    )
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
    text = params_to_toml(default_params()).replace(
        f"{key} = {getattr(default_params(), key)!r}", f"{key} = {value!r}"
    )
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
    cannot_move = tau_max * i_r / r <= a1
    too_fast = v_max * i_r / r > MAX_MOTOR_SPEED_RAD_S
    if cannot_move or too_fast:
        with pytest.raises(ParameterError, match="F_max = tau_max·i_r/r" if cannot_move else "v_max·i_r/r"):
            check_combination(r=r, i_r=i_r, a1=a1, v_max=v_max, tau_max=tau_max)
    else:
        check_combination(r=r, i_r=i_r, a1=a1, v_max=v_max, tau_max=tau_max)
