"""Sampled trajectories: quintic Hermite pieces through the knots, C² at the knots, rest outside."""

import numpy as np
import pytest
from axisflow.model import MoveError, SampledTrajectory, check_limits, default_params


def _random(seed=1, n=21):
    rng = np.random.default_rng(seed)
    t = np.cumsum(np.r_[0.0, rng.uniform(0.001, 0.01, n - 1)])
    x = rng.uniform(0.0, 0.8, n)
    v = rng.normal(size=n)
    v[0] = v[-1] = 0.0
    return t, x, v, rng.normal(size=n)


def test_pieces_match_position_velocity_and_acceleration_at_both_knots():
    t, x, v, a = _random()
    traj = SampledTrajectory(t, x, v, a)
    at = traj.sample(t)
    assert at.position_m == pytest.approx(x, abs=1e-14)
    assert at.velocity_m_s == pytest.approx(v, abs=1e-11)
    assert at.acceleration_m_s2 == pytest.approx(a, abs=1e-8)
    # each piece's own end (s = 1) meets the next knot: C² across knots
    before = traj.sample(np.nextafter(t[1:-1], 0.0))
    assert before.position_m == pytest.approx(x[1:-1], abs=1e-12)
    assert before.velocity_m_s == pytest.approx(v[1:-1], abs=1e-6)


def test_the_end_sample_is_the_last_knot_exactly():
    """A path that ends on the stroke's end stays on it: its last piece's sum at s = 1 missed 0.0 by
    -6e-28 m (a 1 µs piece near the end), and the bridge refused the move as leaving the stroke."""
    t = np.array([0.0, 1.02674964, 1.02675064])
    x = np.array([0.8, 5.06428233e-13, 0.0])
    v = np.array([0.0, -1.52000878e-06, 0.0])
    a = np.array([0.0, -3.04002927, 0.0])
    traj = SampledTrajectory(t, x, v, a)
    end = traj.sample(np.array([traj.duration_s, traj.duration_s + 1.0]))
    assert list(end.position_m) == [0.0, 0.0]


def test_derivatives_are_those_of_the_position():
    traj = SampledTrajectory(*_random(seed=2))
    t = np.linspace(0.001, traj.duration_s - 0.001, 997)
    h = 1e-7
    s, up, down = traj.sample(t), traj.sample(t + h), traj.sample(t - h)
    assert (up.position_m - down.position_m) / (2 * h) == pytest.approx(s.velocity_m_s, rel=1e-5, abs=1e-5)
    assert (up.velocity_m_s - down.velocity_m_s) / (2 * h) == pytest.approx(
        s.acceleration_m_s2, rel=1e-4, abs=1e-3
    )


def test_a_sinusoid_through_knots_10_ms_apart_is_reproduced_between_them():
    w = 2 * np.pi * 2.0
    t = np.arange(0.0, 1.0 + 1e-12, 0.01)
    x = 0.4 - 0.1 * np.cos(w * t)  # at rest at t = 0 and t = 1 s
    traj = SampledTrajectory(
        t, x, 0.1 * w * np.sin(w * t) * (np.abs(np.sin(w * t)) > 1e-12), 0.1 * w * w * np.cos(w * t)
    )
    tq = np.linspace(0.0, 1.0, 4001)
    s = traj.sample(tq)
    assert s.position_m == pytest.approx(0.4 - 0.1 * np.cos(w * tq), abs=1e-8)
    assert s.velocity_m_s == pytest.approx(0.1 * w * np.sin(w * tq), abs=1e-5)
    assert s.acceleration_m_s2 == pytest.approx(0.1 * w * w * np.cos(w * tq), abs=2e-3)
    outside = traj.sample(np.array([-1.0, 2.0]))
    assert list(outside.position_m) == pytest.approx([x[0], x[-1]]) and list(outside.velocity_m_s) == [
        0.0,
        0.0,
    ]


def test_limit_check_reports_the_position_range_of_a_trajectory():
    t = np.linspace(0.0, 2.0, 201)
    w = np.pi
    x = 0.5 - 0.3 * np.cos(w * t)  # from 0.2 m up to 0.8 m and back
    v = 0.3 * w * np.sin(w * t)
    v[0] = v[-1] = 0.0
    traj = SampledTrajectory(t, x, v, 0.3 * w * w * np.cos(w * t))
    report = check_limits(traj, default_params(), extra_times_s=t)
    assert report.min_position_m == pytest.approx(0.2) and report.max_position_m == pytest.approx(0.8)
    assert report.peak_velocity_m_s == pytest.approx(0.3 * w, rel=1e-6)


@pytest.mark.parametrize(
    ("change", "match"),
    [
        (lambda k: k.__setitem__("t", np.r_[0.0, 0.1, 0.1, 0.3]), r"times must increase: t_s\[2\] = 0.1 s"),
        (lambda k: k.__setitem__("t", np.r_[0.5, 0.6, 0.7, 0.8]), r"t_s\[0\] = 0.5 s must be 0 s"),
        (lambda k: k["v"].__setitem__(-1, 0.2), r"velocity_m_s\[-1\] = 0.2 m/s"),
        (lambda k: k["x"].__setitem__(1, np.nan), r"position_m\[1\] = nan is not finite"),
        (lambda k: k.__setitem__("a", np.zeros(3)), "differ in length"),
    ],
)
def test_bad_knots_are_move_errors_naming_the_value(change, match):
    knots = {"t": np.r_[0.0, 0.1, 0.2, 0.3], "x": np.r_[0.1, 0.2, 0.3, 0.4], "v": np.r_[0.0, 1.0, 1.0, 0.0]}
    knots["a"] = np.zeros(4)
    change(knots)
    with pytest.raises(MoveError, match=match):
        SampledTrajectory(knots["t"], knots["x"], knots["v"], knots["a"])
