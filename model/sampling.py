"""The drive's execution rate and its sampling rule: the one home of "1 kHz".

A drive executes a move at a fixed period Δt = :data:`EXECUTION_PERIOD_NS` (1 ms): a move of duration
T that starts at tick k₀ is sampled at t = (k − k₀)·Δt for the :func:`move_ticks` ticks with
0 ≤ t < T, and from tick k₀ + :func:`move_ticks` on the axis rests at the end point (the sample at
t = T). The bridge executes moves by this rule and validates them at the same samples
(:func:`axisflow.model.limits.check_limits`), so the two cannot drift apart.
"""

from __future__ import annotations

import math

EXECUTION_PERIOD_NS = 1_000_000
"""one drive tick [ns]: 1 ms; sample stamps advance by exactly this much"""
EXECUTION_PERIOD_S = EXECUTION_PERIOD_NS * 1e-9
"""one drive tick [s]"""
EXECUTION_RATE_HZ = 1e9 / EXECUTION_PERIOD_NS
"""ticks per second [Hz]: 1000"""
_TICK_ROUNDING = 1e-9
"""a duration within this many ticks of a whole number of ticks counts as that number (a duration
computed as n·Δt in floating point must not gain a tick)"""


def move_ticks(duration_s: float, rate_hz: float = EXECUTION_RATE_HZ) -> int:
    """Ticks a move of ``duration_s`` spans: ⌈T·rate⌉ (the ticks with 0 ≤ k/rate < T)."""
    return math.ceil(duration_s * rate_hz - _TICK_ROUNDING)


def sample_count(duration_s: float, rate_hz: float = EXECUTION_RATE_HZ) -> int:
    """Execution samples k/rate with 0 ≤ k/rate ≤ T: ⌊T·rate⌋ + 1 (the end T is added when it falls
    between two ticks)."""
    return math.floor(duration_s * rate_hz + _TICK_ROUNDING) + 1


def ticks_to_seconds(ticks: int) -> float:
    """Drive time [s] of a number of ticks."""
    return ticks * EXECUTION_PERIOD_S
