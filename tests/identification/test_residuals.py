"""What the model leaves unexplained, against closed forms: the noise floor of white noise through the
filter, a line in time found at its frequency, a ripple of the motor angle found at its order."""

import math

import numpy as np
import pytest
from axisflow.identification.residuals import analyse_residuals
from scipy.signal import butter, sosfiltfilt

RATE, CUTOFF, ORDER = 1000.0, 15.0, 4


def _analyse(residual, angle=None, moving=None):
    n = residual.size
    moving = np.ones(n, bool) if moving is None else moving
    angle = np.linspace(0.0, 1e3, n) if angle is None else angle
    return analyse_residuals([residual], [moving], [angle], RATE, CUTOFF, ORDER)


def test_the_noise_floor_of_white_noise_is_its_filtered_rms():
    """σ = 0.01 white: density 2σ²/f_s, and through the zero-phase filter exactly the RMS of the
    filtered noise."""
    rng = np.random.default_rng(0)
    noise = rng.normal(0.0, 0.01, 600_000)
    r = _analyse(noise)
    assert r.noise_density == pytest.approx(2 * 0.01**2 / RATE, rel=0.05)
    filtered = sosfiltfilt(butter(ORDER, CUTOFF, fs=RATE, output="sos"), noise)
    assert r.noise_floor == pytest.approx(float(np.std(filtered)), rel=0.05)
    assert r.floor_band_hz == (3.0, 9.0) and r.segments > 500
    assert r.peaks_hz == ()  # nothing stands out of white noise


def test_a_line_in_time_is_found_at_its_frequency_with_its_rms():
    rng = np.random.default_rng(1)
    t = np.arange(300_000) / RATE
    residual = rng.normal(0.0, 0.01, t.size) + 0.005 * np.sin(2 * np.pi * 57.0 * t)
    r = _analyse(residual)
    top = r.peaks_hz[0]
    assert top.frequency == pytest.approx(57.0, abs=1.0)
    assert top.rms == pytest.approx(0.005 / math.sqrt(2), rel=0.15)
    assert top.ratio > 10


def test_a_ripple_of_the_motor_angle_is_found_at_its_order_whatever_the_speed():
    """A 24-per-revolution ripple while the motor turns at a speed that changes: smeared in Hz, one
    line in cycles per revolution."""
    rng = np.random.default_rng(2)
    t = np.arange(200_000) / RATE
    speed = 10.0 + 8.0 * np.sin(2 * np.pi * 0.05 * t)  # rad/s, always forward
    theta = np.cumsum(speed) / RATE
    residual = rng.normal(0.0, 0.005, t.size) + 0.004 * np.sin(24 * theta + 0.3)
    r = _analyse(residual, angle=theta)
    assert r.order_segments > 100
    top = r.peaks_order[0]
    assert top.frequency == pytest.approx(24.0, abs=0.5)
    assert top.rms == pytest.approx(0.004 / math.sqrt(2), rel=0.15)


def test_stretches_too_short_for_a_spectrum_give_no_floor():
    residual = np.random.default_rng(3).normal(0.0, 0.01, 50_000)
    moving = np.zeros(residual.size, bool)
    for start in range(0, residual.size, 300):  # 0.2 s stretches: shorter than any segment
        moving[start : start + 200] = True
    r = _analyse(residual, moving=moving)
    assert r.segments == 0 and math.isnan(r.noise_floor) and r.peaks_hz == ()
