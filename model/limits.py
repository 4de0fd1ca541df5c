"""Limit check of a move at the drive's execution samples.

The drive executes a move at a fixed rate (1 kHz, :mod:`axisflow.model.sampling`): the samples are
t_k = k·Δt for k = 0 … ⌊T/Δt⌋, plus the end t = T. At each sample the cart velocity and the motor
torque required by eq. (1) must stay within ±v_max and ±tau_max. The worst violation is reported
relative to the limit: max(|ẋ|/v_max − 1, |τ_m|/tau_max − 1, 0), so 0.01 means "1 % above a limit".
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from .dynamics import cart_force, motor_torque
from .motion_laws import Motion
from .params import AxisParams
from .sampling import EXECUTION_RATE_HZ, sample_count


@dataclass(frozen=True)
class LimitReport:
    """Peaks of a move at the execution samples and its worst relative limit violation."""

    peak_velocity_m_s: float
    peak_torque_nm: float
    velocity_violation: float
    """max(|ẋ|/v_max − 1, 0) at the samples"""
    torque_violation: float
    """max(|τ_m|/tau_max − 1, 0) at the samples"""
    samples: int
    min_position_m: float
    max_position_m: float
    """the range of positions at the samples (a polynomial law stays between its end points; a sampled
    trajectory need not)"""

    @property
    def max_violation(self) -> float:
        return max(self.velocity_violation, self.torque_violation)

    @property
    def ok(self) -> bool:
        return self.max_violation <= 0.0


def execution_times(duration_s: float, rate_hz: float = EXECUTION_RATE_HZ) -> np.ndarray:
    """Sample times [s] of a move executed at ``rate_hz``: k/rate for k = 0…⌊T·rate⌋, and T."""
    return np.concatenate(list(_sample_chunks(duration_s, rate_hz, 0)))


_CHUNK_SAMPLES = 1 << 13
"""samples evaluated at once: the check of a long move needs bounded memory, and each numpy call is
short (a validating thread hands the interpreter back to a 1 kHz loop quickly)"""


def _sample_chunks(duration_s: float, rate_hz: float, min_points: int) -> Iterator[np.ndarray]:
    """The check's sample times in chunks, never all at once: k/rate for k = 0…⌊T·rate⌋, T, and
    ``min_points`` evenly spaced times (the order does not matter for peaks)."""
    n = sample_count(duration_s, rate_hz)
    for start in range(0, n, _CHUNK_SAMPLES):
        yield np.arange(start, min(start + _CHUNK_SAMPLES, n)) / rate_hz
    if (n - 1) / rate_hz < duration_s:
        yield np.array([duration_s])
    for start in range(0, min_points, _CHUNK_SAMPLES):
        yield np.arange(start, min(start + _CHUNK_SAMPLES, min_points)) * (
            duration_s / max(min_points - 1, 1)
        )


def check_limits(
    move: Motion,
    params: AxisParams,
    rate_hz: float = EXECUTION_RATE_HZ,
    min_points: int = 0,
    extra_times_s: np.ndarray | None = None,
) -> LimitReport:
    """Peaks and worst violation of velocity and motor torque at the execution samples.

    ``min_points`` > 0 adds that many evenly spaced times over the move to the samples, so a move
    spanning few (or no) execution periods is checked along its course, not only at its two ends
    (where a rest-to-rest law is at rest). ``extra_times_s`` are checked too (a sampled trajectory's
    knots).
    """
    v_peak = tau_peak = 0.0
    x_lo, x_hi = math.inf, -math.inf
    samples = 0
    chunks = _sample_chunks(move.duration_s, rate_hz, min_points)
    if extra_times_s is not None:
        extra = np.asarray(extra_times_s, dtype=float)
        chunks = itertools.chain(
            chunks, (extra[i : i + _CHUNK_SAMPLES] for i in range(0, extra.size, _CHUNK_SAMPLES))
        )
    for t in chunks:
        s = move.sample(t)
        tau = motor_torque(cart_force(s.velocity_m_s, s.acceleration_m_s2, params), params)
        v_peak = max(v_peak, float(np.max(np.abs(s.velocity_m_s))))
        tau_peak = max(tau_peak, float(np.max(np.abs(tau))))
        x_lo = min(x_lo, float(np.min(s.position_m)))
        x_hi = max(x_hi, float(np.max(s.position_m)))
        samples += t.size
    return LimitReport(
        peak_velocity_m_s=v_peak,
        peak_torque_nm=tau_peak,
        velocity_violation=max(v_peak / params.v_max - 1.0, 0.0),
        torque_violation=max(tau_peak / params.tau_max - 1.0, 0.0),
        samples=samples,
        min_position_m=x_lo,
        max_position_m=x_hi,
    )
