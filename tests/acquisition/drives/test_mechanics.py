"""The simulated axis's mechanics against closed forms: the inlined friction law is the model's, the
belt mode rings at √(k/m_red), momentum grows by F·t, a stuck cart holds until the belt pulls a1."""

import math

import numpy as np
import pytest
from axisflow.acquisition.drives.mechanics import BeltAxis, RigidAxis
from axisflow.acquisition.drives.plant import BeltConfig
from axisflow.model import EXECUTION_PERIOD_S, default_params, friction_force

P = default_params().replace(a1=61.0, a2=190.0, a3=150.0, a4=9.0)
BELT = BeltConfig(spring_rate_n=1.0e6, end_span_m=0.1, damping_ratio=0.05)
FRICTION = (P.a1, P.a2, P.a3, P.a4)
SPEEDS = [-1.3, -0.2, -1e-3, -1e-6, 1e-6, 1e-3, 0.2, 1.3]


# the paper's law, and one with an offset and an asymmetry (the cart's Karnopp band and each
# direction's friction differ)
LAWS = {"paper": P, "terms": P.replace(f0=12.0, da1=-9.0, da2=25.0)}


def _friction(params):
    return (params.a1, params.a2, params.a3, params.a4, params.f0, params.da1, params.da2)


@pytest.mark.parametrize("law", LAWS)
@pytest.mark.parametrize("v0", SPEEDS)
def test_the_rigid_integrators_friction_is_the_models_law(v0, law):
    params = LAWS[law]
    axis = RigidAxis(params, substeps=1, position_m=0.4)
    axis.set_state(0.4, v0)
    axis.advance(0.0, *_friction(params))  # one step of dt with no motor force: M·Δv = −F_c(v0)·dt
    _check_step(v0, axis.v, params.M_eq, params)


@pytest.mark.parametrize("law", LAWS)
@pytest.mark.parametrize("v0", SPEEDS)
def test_the_belt_integrators_friction_is_the_models_law(v0, law):
    params = LAWS[law]
    axis = BeltAxis(params, BELT, substeps=1, position_m=0.4)
    axis.set_state(0.4, v0)  # unstretched, both masses at v0: the belt pulls nothing in the first step
    axis.advance(0.0, *_friction(params))
    _check_step(v0, axis.v, params.m, params)
    assert axis.motor_v == v0  # no force on the motor side yet


def _check_step(v0, v1, mass, params):
    """v1 = v0 − F_c(v0)·dt/mass, or rest where that would reverse the motion."""
    friction = float(friction_force(v0, params))
    expected = v0 - friction * EXECUTION_PERIOD_S / mass
    if expected * v0 < 0:
        assert v1 == 0.0
    else:
        assert (v0 - v1) * mass / EXECUTION_PERIOD_S == pytest.approx(friction, rel=1e-9)


@pytest.mark.parametrize("mechanics", ["rigid", "belt"])
def test_a_cart_at_rest_breaks_away_where_the_law_says(mechanics):
    """Karnopp with the terms: at rest the cart holds while −(a1 − da1) ≤ F − f0 ≤ a1 + da1, and a
    force past either edge moves it that way by the excess (M·v = (F − F_c(0±))·dt)."""
    params = LAWS["terms"]
    up, down = params.a1 + params.da1, params.a1 - params.da1
    for force, moves in [
        (params.f0 + up - 1e-6, 0),
        (params.f0 - down + 1e-6, 0),
        (params.f0 + up + 1.0, 1),
        (params.f0 - down - 1.0, -1),
    ]:
        if mechanics == "rigid":
            axis, mass, drive = RigidAxis(params, substeps=1, position_m=0.4), params.M_eq, force
        else:  # the belt stretched so that it pulls ``force`` on the cart in the first step
            axis, mass, drive = BeltAxis(params, BELT, substeps=1, position_m=0.4), params.m, 0.0
            axis.motor_x = 0.4 + force / BELT.stiffness_n_m(0.4, params.L)
        axis.advance(drive, *_friction(params))
        assert math.copysign(1.0, axis.v) * (axis.v != 0.0) == moves, force
        if moves:
            excess = force - params.f0 - moves * (up if moves > 0 else down)
            assert axis.v * mass / EXECUTION_PERIOD_S == pytest.approx(excess, rel=1e-6)


def test_the_belt_mode_rings_at_the_springs_frequency():
    """No friction, no damping, the belt stretched by 10 µm: the stretch oscillates at
    ω = √(k/m_red), k the stiffness at the cart's position (two spans in parallel)."""
    belt = BeltConfig(spring_rate_n=1.0e6, end_span_m=0.1, damping_ratio=0.0)
    axis = BeltAxis(P, belt, substeps=16, position_m=0.4)
    axis.motor_x = 0.4 + 1e-5
    stretch = []
    for _ in range(400):
        axis.advance(0.0, 0.0, 0.0, 0.0, 0.0)
        stretch.append(axis.stretch_m())
    s = np.array(stretch)
    up = np.flatnonzero((s[:-1] < 0) & (s[1:] >= 0))
    # zero crossings, interpolated within the tick
    t = up + s[up] / (s[up] - s[up + 1])
    period_s = float(np.mean(np.diff(t))) * EXECUTION_PERIOD_S
    m_r = P.M_eq - P.m
    k = belt.stiffness_n_m(0.4, P.L)
    assert k == pytest.approx(1.0e6 * (1 / 0.5 + 1 / 1.5))
    expected = 2 * math.pi / math.sqrt(k / (P.m * m_r / (P.m + m_r)))
    assert period_s == pytest.approx(expected, rel=0.01)
    assert np.max(np.abs(s)) == pytest.approx(1e-5, rel=0.02)  # undamped: the amplitude stays


def test_the_two_masses_gain_the_momentum_the_motor_gives():
    """With no friction the belt's forces cancel: M_r·v_m + m·v_c = F·t exactly, at any stiffness."""
    axis = BeltAxis(P, BELT, substeps=4, position_m=0.3)
    force = 200.0
    for _ in range(100):
        axis.advance(force, 0.0, 0.0, 0.0, 0.0)
    momentum = (P.M_eq - P.m) * axis.motor_v + P.m * axis.v
    assert momentum == pytest.approx(force * 100 * EXECUTION_PERIOD_S, rel=1e-12)
    assert axis.v == pytest.approx(force * 0.1 / P.M_eq, rel=0.05)  # low frequency: eq. (1)'s M_eq


def test_a_stuck_cart_holds_until_the_belt_pulls_more_than_a1():
    axis = BeltAxis(P, BELT, substeps=4, position_m=0.4)
    axis.advance(0.5 * P.a1, *FRICTION)  # the motor side moves, the belt pulls less than a1
    assert axis.v == 0.0 and axis.x == 0.4 and axis.motor_x > 0.4
    for _ in range(50):
        axis.advance(3.0 * P.a1, *FRICTION)
    assert axis.v > 0.0 and axis.x > 0.4


def test_the_cart_stops_at_the_ends_of_the_stroke():
    axis = BeltAxis(P, BELT, substeps=4, position_m=P.L - 1e-4)
    for _ in range(200):
        axis.advance(900.0, *FRICTION)
    assert axis.x == P.L and axis.v == 0.0
