"""The true friction over the axis's life against closed forms: the first-order temperature at constant
friction power, the exponential fall of the friction with it, wear with distance, a1 along the stroke."""

import math

import pytest
from axisflow.acquisition.drives.friction_drift import FrictionDrift
from axisflow.acquisition.drives.plant import StrokeFrictionConfig, ThermalConfig, WearConfig
from axisflow.model import EXECUTION_PERIOD_S, default_params, friction_force

P = default_params()
THERMAL = ThermalConfig(ambient_c=20.0, resistance_k_per_w=0.1, time_constant_s=600.0,
                        viscous_per_k=0.012, coulomb_per_k=0.005)  # fmt: skip


def test_the_temperature_follows_the_first_order_law_at_constant_power():
    """At a constant speed with the friction held (the cold values), T(t) = T_ss + (T0 − T_ss)·e^(−t/τ),
    T_ss = T_amb + R·F_c(v)·v."""
    drift = FrictionDrift(P, None, THERMAL, None)
    v, ticks = 0.8, 120_000  # two minutes of drive time
    cold = (P.a1, P.a2, P.a3, P.a4)
    for _ in range(ticks):
        drift.step(cold, v, v * EXECUTION_PERIOD_S)
    power = float(friction_force(v, P)) * v
    steady = 20.0 + 0.1 * power
    expected = steady + (20.0 - steady) * math.exp(-ticks * EXECUTION_PERIOD_S / 600.0)
    assert drift.temperature_c == pytest.approx(expected, rel=1e-9)
    rise = expected - 20.0
    now = drift.true_params()
    assert now.a2 == pytest.approx(P.a2 * math.exp(-0.012 * rise), rel=1e-9)
    assert now.a1 == pytest.approx(P.a1 * math.exp(-0.005 * rise), rel=1e-9)
    assert now.a3 == pytest.approx(P.a3 * math.exp(-0.005 * rise), rel=1e-9)
    assert now.a4 == P.a4 and now.M_eq == P.M_eq
    assert drift.travelled_m == pytest.approx(v * ticks * EXECUTION_PERIOD_S)


def test_an_idle_axis_cools_back_to_ambient():
    drift = FrictionDrift(P, None, THERMAL, None)
    drift.temperature_c = 50.0
    for _ in range(60_000):
        drift.step((P.a1, P.a2, P.a3, P.a4), 0.0, 0.0)
    assert drift.temperature_c == pytest.approx(20.0 + 30.0 * math.exp(-60.0 / 600.0), rel=1e-9)


def test_wear_raises_coulomb_friction_with_distance():
    drift = FrictionDrift(P, None, None, WearConfig(coulomb_per_km=0.02))
    drift.step((P.a1, P.a2, P.a3, P.a4), 0.0, 500.0)
    assert drift.true_params().a1 == pytest.approx(P.a1 * 1.01)
    assert drift.true_params().a2 == P.a2
    assert math.isnan(drift.temperature_c)


def test_coulomb_friction_along_the_stroke_and_its_average():
    stroke = StrokeFrictionConfig(amplitudes=(0.04, 0.02), cycles=(1.0, 2.0), phases_rad=(0.7, 2.1))
    drift = FrictionDrift(P, stroke, None, None)
    for x in (0.0, 0.13, 0.4, 0.8):
        assert drift.friction_at(x)[0] == pytest.approx(P.a1 * stroke.factor(x, P.L), rel=1e-15)
    assert drift.true_params().a1 == pytest.approx(P.a1, rel=1e-14)  # whole cycles: the mean is a1
    assert drift.true_params(0.1, 0.7).a1 == pytest.approx(P.a1 * stroke.mean_factor(0.1, 0.7, P.L))
