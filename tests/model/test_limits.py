import numpy as np
import pytest
from axisflow.model import Move, check_limits, default_params, execution_times, polynomial_law


def test_execution_samples_are_1khz_and_include_the_end():
    t = execution_times(0.0105)
    assert t[0] == 0.0
    assert t[1] == pytest.approx(0.001)
    assert t[-1] == pytest.approx(0.0105)
    assert len(t) == 12


def test_velocity_exactly_at_the_limit_is_not_a_violation():
    p = default_params().replace(tau_max=1e3)
    law = polynomial_law("poly5")
    T = 0.5  # the peak sits at T/2 = 250 ms, an execution sample
    d = p.v_max * T / law.peak_velocity_factor  # so the peak velocity is exactly v_max
    report = check_limits(Move(0.1, 0.1 + d, T, law), p)
    assert report.peak_velocity_m_s == pytest.approx(p.v_max, rel=1e-12)
    assert report.velocity_violation <= 1e-12
    faster = check_limits(Move(0.1, 0.1 + d, T * 0.9, law), p)
    assert faster.velocity_violation == pytest.approx(1 / 0.9 - 1, rel=1e-3)
    assert not faster.ok


def test_torque_violation_is_relative_to_tau_max():
    p = default_params()
    report = check_limits(Move(0.0, 0.8, 0.15, polynomial_law("poly3")), p)
    assert report.torque_violation == pytest.approx(report.peak_torque_nm / p.tau_max - 1.0)
    assert report.max_violation >= report.torque_violation


def test_a_long_move_is_checked_in_chunks_with_the_same_result(monkeypatch):
    p = default_params()
    move = Move(0.0, 0.8, 0.4321, polynomial_law("poly7"))
    whole = check_limits(move, p)
    monkeypatch.setattr("axisflow.model.limits._CHUNK_SAMPLES", 7)
    chunked = check_limits(move, p)
    assert chunked == whole
    s = move.sample(execution_times(move.duration_s))
    assert whole.peak_velocity_m_s == np.max(np.abs(s.velocity_m_s))
