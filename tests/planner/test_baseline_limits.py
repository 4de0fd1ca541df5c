"""Baseline limits: parsing, the [baseline] table, and what the axis can follow."""

import pytest
from axisflow.model import ParameterError, cart_force, default_params, motor_torque, params_to_toml
from axisflow.planner.baseline_limits import (
    DEFAULT_JERK_TIME_S,
    BaselineLimitError,
    BaselineLimits,
    axis_limits,
    check_reachable,
    load_baseline_limits,
    parse_limits,
    reachable_acceleration,
)


def test_parse_limits():
    assert parse_limits("1.2,2.5") == BaselineLimits(1.2, 2.5)
    assert parse_limits("1.2, 2.5, 30") == BaselineLimits(1.2, 2.5, 30.0)
    with pytest.raises(BaselineLimitError, match="give V,A or V,A,J"):
        parse_limits("1.2")
    with pytest.raises(BaselineLimitError, match="the acceleration 'x' is not a number"):
        parse_limits("1.2,x")
    with pytest.raises(BaselineLimitError, match=r"velocity_m_s = -1.0 m/s must be > 0 m/s"):
        parse_limits("-1,2")
    with pytest.raises(BaselineLimitError, match="not a finite number"):
        parse_limits("1,inf")


def test_scurve_jerk_defaults_to_the_stated_ramp_time():
    lim = BaselineLimits(1.0, 3.0)
    assert lim.for_law("scurve").jerk_m_s3 == pytest.approx(3.0 / DEFAULT_JERK_TIME_S)
    assert lim.for_law("trapezoid").jerk_m_s3 is None
    with pytest.raises(BaselineLimitError, match="unknown baseline 'sine'; choose one of trapezoid, scurve"):
        lim.for_law("sine")


def test_the_axis_limits_are_the_edge_of_what_it_can_follow():
    p = default_params()
    lim = axis_limits(p)
    check_reachable(lim, p)
    # at v_max, accelerating at the limit takes the whole torque
    tau = float(motor_torque(cart_force(p.v_max, lim.acceleration_m_s2, p), p))
    assert tau == pytest.approx(p.tau_max, rel=1e-8)
    assert reachable_acceleration(p.v_max, p) == pytest.approx(lim.acceleration_m_s2, rel=1e-8)


def test_unreachable_limits_are_refused_naming_the_limit_and_the_value():
    p = default_params()
    with pytest.raises(BaselineLimitError, match=r"velocity limit 2 m/s is above the axis's v_max = 1.5 m/s"):
        check_reachable(BaselineLimits(2.0, 1.0), p)
    with pytest.raises(
        BaselineLimitError,
        match=r"acceleration limit 5 m/s² is above what the axis gives at 1.5 m/s: 3.04 m/s²",
    ):
        check_reachable(BaselineLimits(1.5, 5.0), p)


def test_the_baseline_table_of_a_parameter_file(tmp_path):
    p = default_params()
    path = tmp_path / "axis.toml"
    path.write_text(
        params_to_toml(p) + "\n[baseline]\nvelocity_m_s = 1.2\nacceleration_m_s2 = 2.5\njerk_m_s3 = 25.0\n"
    )
    params, lim = load_baseline_limits(path)
    assert params == p
    assert lim == BaselineLimits(1.2, 2.5, 25.0)
    assert load_baseline_limits(None) == (p, None)
    path.write_text(params_to_toml(p) + "\n[baseline]\nvelocity = 1.2\nacceleration_m_s2 = 2.5\n")
    with pytest.raises(BaselineLimitError, match=r"unknown key\(s\) velocity in \[baseline\]"):
        load_baseline_limits(path)
    path.write_text(params_to_toml(p) + "foo = 1\n")
    with pytest.raises(ParameterError, match=r"unknown key\(s\) foo"):
        load_baseline_limits(path)
