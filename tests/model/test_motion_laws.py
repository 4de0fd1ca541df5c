import numpy as np
import pytest
from axisflow.model import POLYNOMIAL_LAWS, Move, MoveError, polynomial_law

CASES = [(0.1, 0.7, 1.3), (0.75, 0.05, 0.42), (0.0, 0.8, 3.0), (0.4, 0.41, 0.1)]


@pytest.mark.parametrize("name", ["poly3", "poly5", "poly7"])
@pytest.mark.parametrize(("x0", "x1", "T"), CASES)
def test_rest_to_rest_boundary_conditions(name, x0, x1, T):
    law = polynomial_law(name)
    move = Move(x0, x1, T, law)
    s = move.sample(np.array([0.0, T]))
    assert s.position_m == pytest.approx([x0, x1], abs=1e-12)
    assert s.velocity_m_s == pytest.approx([0.0, 0.0], abs=1e-12)
    # derivatives that the law fixes at the ends (from the normalised shape: no sign tricks)
    if law.degree >= 5:
        assert law.shape(np.array([0.0, 1.0]), 2) == pytest.approx([0.0, 0.0], abs=1e-9)
    else:
        assert abs(law.shape(0.0, 2)) > 1.0  # poly3 starts with a step in acceleration
    if law.degree >= 7:
        assert law.shape(np.array([0.0, 1.0]), 3) == pytest.approx([0.0, 0.0], abs=1e-9)


@pytest.mark.parametrize("name", ["poly3", "poly5", "poly7"])
def test_derivatives_are_consistent_with_position(name):
    move = Move(0.2, 0.65, 0.9, polynomial_law(name))
    t = np.linspace(0.05, 0.85, 81)
    h = 1e-6
    s = move.sample(t)
    plus, minus = move.sample(t + h), move.sample(t - h)
    assert s.velocity_m_s == pytest.approx((plus.position_m - minus.position_m) / (2 * h), rel=1e-6, abs=1e-8)
    assert s.acceleration_m_s2 == pytest.approx(
        (plus.velocity_m_s - minus.velocity_m_s) / (2 * h), rel=1e-5, abs=1e-6
    )
    assert s.jerk_m_s3 == pytest.approx(
        (plus.acceleration_m_s2 - minus.acceleration_m_s2) / (2 * h), rel=1e-5, abs=1e-4
    )


@pytest.mark.parametrize(
    ("name", "c_v", "c_a", "int_v2"),
    [
        ("poly3", 1.5, 6.0, 6 / 5),
        ("poly5", 1.875, 10 / np.sqrt(3), 10 / 7),
        ("poly7", 2.1875, None, 700 / 429),
    ],
)
def test_peak_factors_and_closed_form_integrals(name, c_v, c_a, int_v2):
    law = polynomial_law(name)
    u = np.linspace(0, 1, 200001)
    assert law.peak_velocity_factor == pytest.approx(c_v, rel=1e-12)
    assert law.peak_velocity_factor == pytest.approx(np.max(np.abs(law.shape(u, 1))), rel=1e-9)
    assert law.peak_acceleration_factor == pytest.approx(np.max(np.abs(law.shape(u, 2))), rel=1e-8)
    if c_a is not None:
        assert law.peak_acceleration_factor == pytest.approx(c_a, rel=1e-12)
    assert law.integral_of_squared_velocity() == pytest.approx(int_v2, rel=1e-10)


def test_outside_the_move_the_cart_rests():
    move = Move(0.3, 0.1, 0.5, POLYNOMIAL_LAWS["poly5"])
    s = move.sample(np.array([-1.0, 0.7]))
    assert s.position_m.tolist() == [0.3, pytest.approx(0.1)]
    assert s.velocity_m_s.tolist() == [0.0, 0.0]
    assert s.acceleration_m_s2.tolist() == [0.0, 0.0]


@pytest.mark.parametrize("name", ["poly3", "poly5", "poly7"])
def test_laws_are_monotone_so_they_never_overshoot(name):
    law = polynomial_law(name)
    s = law.shape(np.linspace(0, 1, 10001))
    assert np.all(np.diff(s) >= -1e-15)


def test_bad_moves():
    with pytest.raises(MoveError, match=r"duration_s = 0.0 s must be > 0 s"):
        Move(0.0, 0.1, 0.0, POLYNOMIAL_LAWS["poly3"])
    with pytest.raises(MoveError, match=r"x1_m = nan m is not finite"):
        Move(0.0, float("nan"), 1.0, POLYNOMIAL_LAWS["poly3"])
    with pytest.raises(MoveError, match=r"duration_s = 3601.0 s exceeds the longest move, 3600 s"):
        Move(0.0, 0.1, 3601.0, POLYNOMIAL_LAWS["poly3"])
    with pytest.raises(MoveError, match="unknown motion law 'poly4'"):
        polynomial_law("poly4")
