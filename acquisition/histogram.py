"""A fixed-size histogram of durations (1 µs bins) for jitter and latency percentiles.

Its memory does not grow with the number of samples, so a bridge or recorder can run for days.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class DurationStats:
    """Percentiles of a set of durations [µs]."""

    count: int
    p50_us: float
    p99_us: float
    max_us: float

    def to_dict(self) -> dict[str, float]:
        return {"count": self.count, "p50_us": self.p50_us, "p99_us": self.p99_us, "max_us": self.max_us}


class DurationHistogram:
    """Counts durations in 1 µs bins up to ``limit_us``; longer ones land in the last bin."""

    def __init__(self, limit_us: int = 100_000) -> None:
        self._bins = [0] * (limit_us + 1)
        self._limit = limit_us
        self.count = 0
        self.max_ns = 0

    def add_ns(self, duration_ns: int) -> None:
        us = duration_ns // 1000
        if us < 0:
            us = 0
        self._bins[us if us < self._limit else self._limit] += 1
        self.count += 1
        if duration_ns > self.max_ns:
            self.max_ns = duration_ns

    def percentile_us(self, q: float) -> float:
        """The smallest bin value [µs] at or below which a fraction ``q`` of the durations lie."""
        if self.count == 0:
            return float("nan")
        target = q * self.count
        seen = 0
        for us, n in enumerate(self._bins):
            seen += n
            if n and seen >= target:
                return float(us)
        return float(self._limit)

    def stats(self) -> DurationStats:
        return DurationStats(
            count=self.count,
            p50_us=self.percentile_us(0.50),
            p99_us=self.percentile_us(0.99),
            max_us=self.max_ns / 1000.0 if self.count else float("nan"),
        )
