"""The duration histogram against a plain reading of its definition, across its folding into bins."""

from __future__ import annotations

import math

import numpy as np
import pytest
from axisflow.acquisition.histogram import _FOLD_EVERY, DurationHistogram


def reference(durations_ns: list[int], limit_us: int, q: float) -> float:
    """The smallest bin [µs] at or below which a fraction q of the durations lie, bin by bin."""
    bins = [0] * (limit_us + 1)
    for d in durations_ns:
        bins[min(max(d // 1000, 0), limit_us)] += 1
    seen = 0
    for us, n in enumerate(bins):
        seen += n
        if n and seen >= q * len(durations_ns):
            return float(us)
    return float(limit_us)


@pytest.mark.parametrize("n", [1, 7, _FOLD_EVERY - 1, _FOLD_EVERY, 3 * _FOLD_EVERY + 5])
def test_percentiles_count_and_max_match_the_definition(n):
    rng = np.random.default_rng(n)
    durations = [int(d) for d in rng.integers(-5_000, 2_500_000, n)]  # some negative, some past the limit
    h = DurationHistogram(limit_us=2_000)
    for d in durations:
        h.add_ns(d)
    for q in (0.0, 0.01, 0.5, 0.99, 1.0):
        assert h.percentile_us(q) == reference(durations, 2_000, q), q
    stats = h.stats()
    assert stats.count == n
    assert stats.max_us == max(max(durations), 0) / 1000.0
    h.add_ns(10**12)  # added after a read: still counted
    assert h.stats().count == n + 1 and h.stats().max_us == 10**9


def test_an_empty_histogram_says_nan():
    stats = DurationHistogram().stats()
    assert stats.count == 0 and math.isnan(stats.p50_us) and math.isnan(stats.max_us)
