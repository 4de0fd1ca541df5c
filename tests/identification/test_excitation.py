"""The excitation: rest-to-rest bursts inside the limits that cover the speeds and accelerations the
friction fit needs."""

import numpy as np
import pytest
from axisflow.identification.excitation import design_excitation
from axisflow.model import MoveError, cart_force, check_limits, default_params, motor_torque

P = default_params()


@pytest.fixture(scope="module")
def plan():
    return design_excitation(P, duration_s=90.0)


def test_bursts_are_rest_to_rest_at_the_centre_and_inside_every_limit(plan):
    assert 110.0 <= plan.duration_s <= 150.0
    for traj in plan.trajectories():
        assert traj.x0_m == traj.x1_m == pytest.approx(P.L / 2)
        assert traj.velocity_m_s[0] == traj.velocity_m_s[-1] == 0.0
        assert traj.acceleration_m_s2[0] == traj.acceleration_m_s2[-1] == 0.0
        report = check_limits(traj, P, extra_times_s=traj.t_s)
        assert report.min_position_m > 0.0 and report.max_position_m < P.L
        assert report.peak_velocity_m_s <= 0.8 * P.v_max
        assert report.peak_torque_nm <= 0.8 * P.tau_max + 1e-9


def test_knots_are_consistent_derivatives_of_the_path(plan):
    traj = plan.trajectories()[-1]
    h = traj.t_s[1] - traj.t_s[0]
    v_num = np.gradient(traj.position_m, h)
    a_num = np.gradient(traj.velocity_m_s, h)
    assert v_num[2:-2] == pytest.approx(traj.velocity_m_s[2:-2], abs=1e-4)
    assert a_num[2:-2] == pytest.approx(traj.acceleration_m_s2[2:-2], abs=2e-3)


def test_speeds_from_the_atan_knee_to_most_of_v_max_both_ways_and_strong_accelerations(plan):
    v = np.concatenate([t.velocity_m_s for t in plan.trajectories()])
    a = np.concatenate([t.acceleration_m_s2 for t in plan.trajectories()])
    speeds = np.abs(v)
    assert speeds.max() >= 0.6 * P.v_max
    assert v.min() <= -0.6 * P.v_max  # both directions
    # enough samples where a3·atan(a4·v) still bends (|a4·v| < 1) and where it has saturated (> 5)
    assert np.mean((speeds > 0.002) & (P.a4 * speeds < 1.0)) > 0.3
    assert np.mean(P.a4 * speeds > 5.0) > 0.05
    # inertia seen apart from friction: a large inertial torque, uncorrelated with the friction terms
    assert np.max(np.abs(motor_torque(P.M_eq * a, P))) > 0.25 * P.tau_max
    for regressor in (np.sign(v), v, np.arctan(P.a4 * v), cart_force(v, 0.0 * a, P)):
        assert abs(np.corrcoef(a, regressor)[0, 1]) < 0.1


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"duration_s": 1.0}, r"excitation duration = 1.0 s is outside \[5.0, 3600.0\] s"),
        ({"center_m": 0.01}, r"excitation centre = 0.01 m leaves no room in the stroke \[0, 0.8\] m"),
        ({"torque_margin": 1.5}, r"excitation torque margin = 1.5 of tau_max is outside"),
    ],
)
def test_impossible_settings_are_move_errors(kwargs, match):
    with pytest.raises(MoveError, match=match):
        design_excitation(P, **kwargs)


def test_an_axis_too_weak_for_any_burst_is_refused():
    with pytest.raises(MoveError, match="no excitation fits the limits"):
        design_excitation(P.replace(tau_max=0.3))
