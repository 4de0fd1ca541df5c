"""Reference laws: closed forms without friction, an ODE simulation with it, and the polynomial laws."""

import math

import numpy as np
import pytest
from axisflow.model import (
    EnergyAccounting,
    Move,
    MoveError,
    ParameterError,
    default_params,
    forward_friction,
    move_energy,
    polynomial_law,
)
from axisflow.planner import Case, InfeasibleMoveError, MoveProblem
from axisflow.planner.exact import solve_exact
from axisflow.planner.reference_laws import least_energy, plan_reference, time_optimal
from scipy.integrate import solve_ivp


@pytest.fixture(scope="module")
def params():
    return default_params()


def test_bang_without_friction_matches_the_closed_forms(params):
    p = params.replace(a1=0.0, a2=0.0, a3=0.0, a4=0.0)
    acc = p.f_max / p.M_eq
    # triangular: peak speed below v_max
    d = 0.5 * p.v_max**2 / acc  # reaches v_max/√2
    prof = time_optimal(d, p)
    assert prof.duration_s == pytest.approx(2.0 * np.sqrt(d / acc), rel=1e-10)
    assert prof.switch_fraction == pytest.approx(0.5, rel=1e-9)
    # trapezoidal: cruise at v_max
    d = 0.8
    prof = time_optimal(d, p)
    assert prof.cruise_velocity_m_s == p.v_max
    assert prof.duration_s == pytest.approx(d / p.v_max + p.v_max / acc, rel=1e-10)
    assert prof.energy("signed") == pytest.approx(0.0, abs=1e-9)  # no friction: kinetic energy returned
    assert prof.energy("positive") == pytest.approx(0.5 * p.M_eq * p.v_max**2, rel=1e-10)


@pytest.mark.parametrize("distance_m", [0.003, 0.05, 0.3, 0.8])
def test_bang_profile_integrated_as_an_ode_stops_at_the_target(distance_m, params):
    prof = time_optimal(distance_m, params)
    p = params
    t_acc, t_cruise = prof.accel_time_s, prof.cruise_time_s

    def rhs(t, y):
        _x, v = y
        if t < t_acc:
            force = p.f_max
        elif t < t_acc + t_cruise:
            return [v, 0.0]
        else:
            force = -p.f_max
        fric = float(forward_friction(v, p))  # forward frame: the Coulomb sign is +1
        return [v, (force - fric) / p.M_eq]

    sol = solve_ivp(
        rhs, (0.0, prof.duration_s), [0.0, 0.0], rtol=1e-11, atol=1e-13, max_step=prof.duration_s / 2000
    )
    x_end, v_end = sol.y[:, -1]
    assert x_end == pytest.approx(distance_m, rel=1e-6, abs=1e-9)
    assert abs(v_end) <= 1e-6 * max(prof.cruise_velocity_m_s, 1e-3)
    assert prof.cruise_velocity_m_s <= p.v_max
    assert prof.switch_fraction > 0.5  # friction helps braking: the switch is past mid-stroke


@pytest.mark.parametrize("law", ["poly3", "poly5", "poly7"])
def test_polynomial_laws_are_slower_and_costlier_than_the_limit(law, params):
    for d in (0.01, 0.2, 0.8):
        t_poly = solve_exact(MoveProblem(0.0, d, law, Case.MIN_TIME), params).duration_s
        bang = time_optimal(d, params)
        assert t_poly > bang.duration_s
        for acc in EnergyAccounting:
            e_poly = move_energy(Move(0.0, d, t_poly, polynomial_law(law)), params, acc)
            best = least_energy(d, t_poly, params, acc)
            assert best.duration_s == pytest.approx(t_poly, rel=1e-9)
            assert best.energy(acc) <= e_poly


def test_least_energy_at_the_minimum_time_is_the_bang_profile_and_decreases_with_time(params):
    d = 0.4
    bang = time_optimal(d, params)
    at_min = least_energy(d, bang.duration_s, params, "signed")
    assert at_min.energy("signed") == pytest.approx(bang.energy("signed"), rel=1e-9)
    energies = [
        least_energy(d, bang.duration_s * k, params, "signed").energy("signed") for k in (1.0, 1.5, 3.0)
    ]
    assert energies[0] > energies[1] > energies[2]
    with pytest.raises(InfeasibleMoveError, match="shorter than the time-optimal"):
        least_energy(d, 0.5 * bang.duration_s, params)


def test_positive_accounting_coasts(params):
    prof = least_energy(0.4, 2.0, params, "positive")
    assert prof.brake_velocity_m_s < prof.cruise_velocity_m_s
    assert prof.coast_time_s > 0.0
    assert prof.energy("positive") <= least_energy(0.4, 2.0, params, "signed").energy("positive")


def test_plan_reference_and_errors(params):
    bang = plan_reference("bang", 0.6, params, t_min_s=0.1, t_max_s=3.0)
    assert bang.duration_s == pytest.approx(time_optimal(0.6, params).duration_s)
    slow = plan_reference(
        "least-energy", 0.6, params, minimise_time=False, omega=0.9, t_min_s=0.3, t_max_s=20.0
    )
    assert slow.duration_s > bang.duration_s
    with pytest.raises(MoveError, match="the bang law is the minimum-time law"):
        plan_reference("bang", 0.6, params, minimise_time=False)
    with pytest.raises(InfeasibleMoveError, match=r"no duration in \[0.1, 0.2\] s"):
        plan_reference("bang", 0.8, params, t_max_s=0.2)
    with pytest.raises(ParameterError, match=r"F_max = tau_max·i_r/r = 25 N, not above the Coulomb friction"):
        params.replace(tau_max=0.1)
    with pytest.raises(MoveError, match="longer than the stroke"):
        time_optimal(0.9, params)


@pytest.mark.parametrize(("tau_max", "a4"), [(2.5, 12.8), (1.0, 12.8), (2.5, 100.0)])
def test_an_axis_that_cannot_reach_v_max_still_has_its_time_optimal_move(params, tau_max, a4):
    """Friction at v_max above the force limit: full force drives the cart towards the speed where
    friction takes it all, never to it. The profile, integrated as an ODE, covers the stroke and stops."""
    from scipy.integrate import solve_ivp

    p = params.replace(tau_max=tau_max, a4=a4)
    assert float(forward_friction(p.v_max, p)) > p.f_max
    prof = time_optimal(0.8, p)
    assert prof.cruise_velocity_m_s < p.v_max

    def phi(v):
        return forward_friction(v, p)

    up = solve_ivp(lambda _t, y: [y[1], (p.f_max - phi(y[1])) / p.M_eq], [0, prof.accel_time_s], [0, 0],
                   rtol=1e-12, atol=1e-14)  # fmt: skip
    x, v = up.y[:, -1]
    assert v == pytest.approx(prof.cruise_velocity_m_s, rel=1e-9)
    assert x == pytest.approx(prof.accel_distance_m, rel=1e-8)  # the distance of the pole's integral
    x += v * prof.cruise_time_s
    down = solve_ivp(lambda _t, y: [y[1], (-p.f_max - phi(y[1])) / p.M_eq], [0, prof.brake_time_s], [x, v],
                     rtol=1e-12, atol=1e-14)  # fmt: skip
    assert down.y[0, -1] == pytest.approx(0.8, abs=1e-9)
    assert down.y[1, -1] == pytest.approx(0.0, abs=1e-9)


def test_without_viscous_and_low_speed_friction_the_top_speed_is_v_max(params):
    """a2 = a4 = 0: friction is a1 at every speed; below F_max it never limits the speed."""
    from axisflow.planner.reference_laws import friction_limited_speed, top_speed

    p = params.replace(a2=0.0, a4=0.0, tau_max=0.5)  # F_max = 125 N > a1 = 72 N
    assert friction_limited_speed(p) == math.inf
    assert top_speed(p) == p.v_max
    prof = time_optimal(0.8, p)  # constant friction: v² = 2·D / (M/(F − a1) + M/(F + a1))
    expected = math.sqrt(2 * 0.8 / (p.M_eq / (p.f_max - p.a1) + p.M_eq / (p.f_max + p.a1)))
    assert prof.cruise_velocity_m_s == pytest.approx(expected, rel=1e-9)


def test_the_friction_limited_speed_takes_the_asymmetry_in(params):
    """a2 = 0, the Coulomb and atan friction saturating 10 N below F_max, and +20 N of asymmetry
    towards +x: φ₊ crosses F_max at a finite speed, where the model's law says."""
    from axisflow.planner.reference_laws import friction_limited_speed

    saturated = params.a1 + params.a3 * math.pi / 2
    p = params.replace(a2=0.0, da1=20.0, tau_max=(saturated + 10.0) / params.force_per_torque)
    v = friction_limited_speed(p)
    assert math.isfinite(v)
    assert float(forward_friction(v, p)) == pytest.approx(p.f_max, rel=1e-9)


def test_a_move_below_one_encoder_count_is_the_zero_profile(params):
    """Shorter than one count (2π·r/131072 = 1.917 µm): the reference laws plan nothing, in no time."""
    for d in (5e-324, 1e-310, 1e-6):
        assert time_optimal(d, params).duration_s == 0.0
        assert least_energy(d, 0.0, params).duration_s == 0.0
        plan = plan_reference("least-energy", d, params, minimise_time=False)
        assert (plan.duration_s, plan.energy_j, plan.objective) == (0.0, 0.0, 0.0)
    assert time_optimal(2e-6, params).duration_s > 0.0
    with pytest.raises(MoveError, match=r"duration_s = 0\.0 s must be a finite number > 0 s"):
        least_energy(0.1, 0.0, params)
