"""The baseline laws (trapezoid, S-curve) against Ruckig itself and the closed forms."""

import math

import numpy as np
import pytest
from axisflow.acquisition.bridge.move_queue import validate_move
from axisflow.acquisition.wire.messages import SAMPLED_LAW, Knots, MoveCommand
from axisflow.model import (
    EnergyAccounting,
    Move,
    check_limits,
    default_params,
    motion_energy,
    move_energy,
    polynomial_law,
)
from axisflow.planner.baseline_laws import JUMP_RAMP_S, baseline_move, plan_baseline
from axisflow.planner.baseline_limits import BaselineLimits, axis_limits
from axisflow.planner.errors import InfeasibleMoveError
from ruckig import InputParameter, Ruckig, Trajectory


def _ruckig_duration(x0, x1, v, a, j):
    inp = InputParameter(1)
    inp.current_position, inp.target_position = [x0], [x1]
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = [v], [a], [j]
    traj = Trajectory(1)
    Ruckig(1).calculate(inp, traj)
    return traj.duration


def _trapezoid_time(D, v, a):
    return D / v + v / a if v * v / a <= D else 2.0 * math.sqrt(D / a)


@pytest.mark.parametrize(("x0", "x1"), [(0.1, 0.7), (0.7, 0.1), (0.30, 0.34), (0.0, 0.8)])
def test_trapezoid_takes_the_closed_form_time_and_holds_its_limits(x0, x1):
    lim = BaselineLimits(1.2, 2.5)
    m = baseline_move("trapezoid", x0, x1, lim)
    D = abs(x1 - x0)
    assert m.duration_s == pytest.approx(_trapezoid_time(D, 1.2, 2.5), rel=1e-12)
    t = np.linspace(0.0, m.duration_s, 20001)
    s = m.sample(t)
    assert np.max(np.abs(s.velocity_m_s)) <= 1.2 * (1 + 1e-12)
    assert np.max(np.abs(s.acceleration_m_s2)) == pytest.approx(2.5, rel=1e-12)
    assert s.position_m[0] == x0 and s.position_m[-1] == x1
    # the velocity integrates to the distance
    assert np.trapezoid(s.velocity_m_s, t) == pytest.approx(x1 - x0, rel=1e-7)


def test_stretched_trapezoid_keeps_its_acceleration_and_cruises_at_the_closed_form_speed():
    D, a, T = 0.5, 2.5, 1.7
    m = baseline_move("trapezoid", 0.1, 0.1 + D, BaselineLimits(1.2, a), duration_s=T)
    v_closed = (a * T - math.sqrt(a * a * T * T - 4 * a * D)) / 2
    assert m.duration_s == pytest.approx(T, rel=1e-12)
    assert m.min_duration_s == pytest.approx(_trapezoid_time(D, 1.2, a), rel=1e-12)
    assert np.max(m.velocity_m_s) == pytest.approx(v_closed, rel=1e-9)
    assert m.stretched


@pytest.mark.parametrize(("x0", "x1"), [(0.05, 0.75), (0.75, 0.05), (0.4, 0.41)])
def test_scurve_is_ruckigs_profile(x0, x1):
    lim = BaselineLimits(1.0, 3.0, 20.0)
    m = baseline_move("scurve", x0, x1, lim)
    assert m.duration_s == _ruckig_duration(x0, x1, 1.0, 3.0, 20.0)
    s = m.sample(np.linspace(0.0, m.duration_s, 20001))
    assert np.max(np.abs(s.jerk_m_s3)) <= 20.0 * (1 + 1e-12)
    assert np.max(np.abs(s.acceleration_m_s2)) <= 3.0 * (1 + 1e-12)


def test_scurve_that_reaches_every_limit_takes_the_closed_form_time():
    v, a, j, D = 1.0, 3.0, 20.0, 0.7
    m = baseline_move("scurve", 0.05, 0.05 + D, BaselineLimits(v, a, j))
    assert m.duration_s == pytest.approx(D / v + v / a + a / j, rel=1e-12)


def test_a_duration_below_the_minimum_is_refused_with_both_durations():
    with pytest.raises(
        InfeasibleMoveError, match=r"duration 0\.5 s is shorter than the trapezoid's time-optimal"
    ):
        baseline_move("trapezoid", 0.0, 0.8, BaselineLimits(1.0, 2.0), duration_s=0.5)


@pytest.mark.parametrize("law", ["trapezoid", "scurve"])
@pytest.mark.parametrize("accounting", list(EnergyAccounting))
def test_friction_energy_matches_the_closed_form(law, accounting):
    """Coulomb and viscous friction only: E = a1·D + a2·∫ẋ² dt (friction power is never negative)."""
    p = default_params().replace(m=1e-3, J_m=1e-8, J_g=0.0, J_p=1e-8, a1=37.0, a2=81.0, a3=0.0)
    m = baseline_move(law, 0.1, 0.65, BaselineLimits(0.9, 2.0, 15.0), duration_s=1.3)
    t = np.linspace(0.0, m.duration_s, 100001)
    v2 = np.trapezoid(m.sample(t).velocity_m_s ** 2, t)
    expected = 37.0 * 0.55 + 81.0 * v2
    assert motion_energy(m, p, m.breaks_s, accounting) == pytest.approx(expected, rel=1e-8)


def test_trapezoid_without_friction_costs_its_kinetic_energy_once_counted_positive():
    p = default_params().replace(a1=0.0, a2=0.0, a3=0.0)
    m = baseline_move("trapezoid", 0.1, 0.7, BaselineLimits(1.0, 2.0))
    kinetic = 0.5 * p.M_eq * 1.0**2
    assert motion_energy(m, p, m.breaks_s, EnergyAccounting.SIGNED) == pytest.approx(0.0, abs=1e-9 * kinetic)
    assert motion_energy(m, p, m.breaks_s, EnergyAccounting.POSITIVE) == pytest.approx(kinetic, rel=1e-12)
    assert motion_energy(m, p, m.breaks_s, EnergyAccounting.ABSOLUTE) == pytest.approx(2 * kinetic, rel=1e-12)


def test_motion_energy_of_a_polynomial_move_is_move_energy():
    p = default_params()
    move = Move(0.7, 0.1, 0.9, polynomial_law("poly5"))
    assert motion_energy(move, p, [0.0, 0.9]) == pytest.approx(move_energy(move, p), rel=1e-12)


def test_plan_scores_peaks_in_continuous_time():
    p = default_params()
    r = plan_baseline("trapezoid", 0.05, 0.75, axis_limits(p), p)
    dense = check_limits(r.move, p, rate_hz=1e6)
    assert r.peak_torque_nm == pytest.approx(dense.peak_torque_nm, rel=1e-4)
    assert r.peak_torque_nm <= p.tau_max
    assert r.max_violation == 0.0


def test_zero_move_is_nothing_to_run():
    p = default_params()
    r = plan_baseline("scurve", 0.3, 0.3 + 1e-7, BaselineLimits(1.0, 2.0, 20.0), p)
    assert r.zero_move and r.duration_s == 0.0 and r.energy_j == 0.0


@pytest.mark.parametrize("law", ["trapezoid", "scurve"])
def test_the_wire_path_is_the_profile_and_the_bridge_accepts_it_at_the_axis_limits(law):
    """A full-stroke move at the fastest limits the axis allows: the sampled path the bridge receives
    runs the profile's setpoints (the trapezoid's within a·1 µs of velocity) and passes its check."""
    p = default_params()
    r = plan_baseline(law, 0.8, 0.0, axis_limits(p), p)
    path = r.move.trajectory()
    t = np.arange(0.0, r.duration_s, 1e-3)
    a = r.limits.acceleration_m_s2
    tol = a * JUMP_RAMP_S * 1.01 if law == "trapezoid" else 1e-12
    assert np.max(np.abs(path.sample(t).velocity_m_s - r.move.sample(t).velocity_m_s)) <= tol
    assert abs(path.duration_s - r.duration_s) <= JUMP_RAMP_S * 1.01
    cmd = MoveCommand(0, "a0", 1, 0, SAMPLED_LAW, path.x0_m, path.x1_m, path.duration_s, Knots.of(path))
    validate_move(MoveCommand.decode(cmd.encode()), p)  # raises if rejected
