import itertools
import math

import numpy as np
import pytest
from axisflow.model import (
    EnergyAccounting,
    Move,
    cart_force,
    default_params,
    move_energy,
    polynomial_law,
    trace_energy,
    trace_energy_at,
)
from axisflow.model.limits import execution_times

LAWS = ["poly3", "poly5", "poly7"]


def _friction_only(a1=0.0, a2=0.0, a3=0.0, a4=1.0, **kw):
    # a negligible inertia, so only the friction terms act
    return default_params().replace(m=1e-3, J_m=1e-8, J_g=0.0, J_p=1e-8, a1=a1, a2=a2, a3=a3, a4=a4, **kw)


@pytest.mark.parametrize("law", LAWS)
@pytest.mark.parametrize("accounting", list(EnergyAccounting))
def test_coulomb_and_viscous_energy_match_the_closed_form(law, accounting):
    """Friction only: E = a1·|d| + a2·d²/T·∫s'² (friction power is never negative)."""
    p = _friction_only(a1=37.0, a2=81.0)
    move = Move(0.7, 0.15, 0.83, polynomial_law(law))
    d, T = move.distance_m, move.duration_s
    expected = 37.0 * abs(d) + 81.0 * d**2 / T * move.law.integral_of_squared_velocity()
    assert move_energy(move, p, accounting) == pytest.approx(expected, rel=1e-10)


@pytest.mark.parametrize("law", LAWS)
def test_signed_energy_of_inertia_vanishes_and_positive_counts_peak_kinetic_energy(law):
    """No friction: signed E = 0 (kinetic energy returned); positive E = ½·M·v_peak²; absolute = M·v_peak²."""
    p = default_params().replace(a1=0.0, a2=0.0, a3=0.0)
    move = Move(0.05, 0.75, 0.9, polynomial_law(law))
    kinetic = 0.5 * p.M_eq * move.peak_velocity_m_s**2
    assert move_energy(move, p, EnergyAccounting.SIGNED) == pytest.approx(0.0, abs=1e-9 * kinetic)
    assert move_energy(move, p, EnergyAccounting.POSITIVE) == pytest.approx(kinetic, rel=1e-10)
    assert move_energy(move, p, EnergyAccounting.ABSOLUTE) == pytest.approx(2 * kinetic, rel=1e-10)


def test_atan_term_matches_independent_quadrature():
    from scipy.integrate import quad

    p = _friction_only(a3=15.0, a4=40.0)
    move = Move(0.1, 0.5, 1.1, polynomial_law("poly5"))

    def power(t):
        v = float(move.sample(t).velocity_m_s)
        return 15.0 * math.atan(40.0 * v) * v

    ref, _ = quad(power, 0.0, move.duration_s, epsabs=1e-13, epsrel=1e-13, limit=200)
    assert move_energy(move, p, EnergyAccounting.SIGNED) == pytest.approx(ref, rel=1e-9)


@pytest.mark.parametrize("accounting", list(EnergyAccounting))
def test_sampled_trace_energy_converges_to_the_move_energy(accounting):
    p = default_params()
    move = Move(0.6, 0.02, 0.7, polynomial_law("poly7"))
    t = execution_times(move.duration_s, 20_000.0)
    s = move.sample(t)
    f = cart_force(s.velocity_m_s, s.acceleration_m_s2, p)
    sampled = trace_energy(s.velocity_m_s, f, 1 / 20_000.0, accounting)
    assert sampled == pytest.approx(move_energy(move, p, accounting), rel=1e-4)


@pytest.mark.parametrize("accounting", list(EnergyAccounting))
def test_energy_at_uneven_times_is_the_even_one_and_bridges_a_missing_sample(accounting):
    p = default_params()
    move = Move(0.6, 0.02, 0.7, polynomial_law("poly5"))
    t = execution_times(move.duration_s, 1000.0)
    s = move.sample(t)
    f = cart_force(s.velocity_m_s, s.acceleration_m_s2, p)
    even = trace_energy(s.velocity_m_s, f, 1e-3, accounting)
    assert trace_energy_at(t, s.velocity_m_s, f, accounting) == pytest.approx(even, rel=1e-12)
    keep = np.ones(t.size, dtype=bool)
    keep[[100, 350, 600]] = False  # three samples lost: each step of 2 ms spans one
    bridged = trace_energy_at(t[keep], s.velocity_m_s[keep], f[keep], accounting)
    assert bridged == pytest.approx(even, rel=1e-4)
    assert trace_energy_at(t[:1], s.velocity_m_s[:1], f[:1], accounting) == 0.0


def test_positive_energy_lies_between_signed_and_absolute():
    p = default_params()
    rng = np.random.default_rng(3)
    for _ in range(20):
        a, b = rng.uniform(0, 0.8, 2)
        move = Move(a, b, rng.uniform(0.2, 3.0), polynomial_law(str(rng.choice(LAWS))))
        es, ep, ea = (move_energy(move, p, acc) for acc in EnergyAccounting)
        assert es - 1e-9 <= ep <= ea + 1e-9


def test_a_braking_lobe_shorter_than_the_scan_spacing_is_counted():
    """poly3 ends with ẍ ≠ 0 while ẋ → 0: a slow move brakes only in its last ~1e-4 of the time,
    between the last two evenly spaced scan points; its (tiny) negative power still counts."""
    from scipy.integrate import quad

    p = default_params()
    move = Move(0.0, 0.6941531727931924, 2.4268217117951436, polynomial_law("poly3"))

    def power(t):
        s = move.sample(t)
        return float(cart_force(s.velocity_m_s, s.acceleration_m_s2, p) * s.velocity_m_s)

    edges = np.linspace(0.0, move.duration_s, 2001)
    braking = sum(
        quad(lambda t: max(-power(t), 0.0), a, b, epsabs=0.0, epsrel=1e-13, limit=200)[0]
        for a, b in itertools.pairwise(edges)
    )
    assert 1e-6 < braking < 1e-5  # J: a lobe, but a real one
    signed = move_energy(move, p, EnergyAccounting.SIGNED)
    assert move_energy(move, p, EnergyAccounting.POSITIVE) == pytest.approx(signed + braking, rel=1e-12)
    assert move_energy(move, p, EnergyAccounting.ABSOLUTE) == pytest.approx(signed + 2 * braking, rel=1e-12)
