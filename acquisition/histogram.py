"""A fixed-size histogram of durations (1 µs bins) for jitter and latency percentiles.

Its memory does not grow with the number of samples, so a bridge or recorder can run for days.
:meth:`DurationHistogram.add_ns` is on hot paths (the recorder calls it per message): it only appends
to a short list, which is sorted into the bins a few thousand at a time (numpy, for all at once).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

_FOLD_EVERY = 4096
"""durations kept in the list before they go into the bins"""


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
    """Counts durations in 1 µs bins up to ``limit_us``; longer ones land in the last bin, negative ones
    in the first."""

    def __init__(self, limit_us: int = 100_000) -> None:
        self._bins = np.zeros(limit_us + 1, dtype=np.int64)
        self._limit = limit_us
        self._pending: list[int] = []
        self._binned = 0
        self._max_ns = 0

    def add_ns(self, duration_ns: int) -> None:
        pending = self._pending
        pending.append(duration_ns)
        if len(pending) >= _FOLD_EVERY:
            self._fold()

    def _fold(self) -> None:
        if not self._pending:
            return
        durations = np.array(self._pending, dtype=np.int64)
        self._pending.clear()
        np.add.at(self._bins, np.clip(durations // 1000, 0, self._limit), 1)
        self._binned += len(durations)
        self._max_ns = max(self._max_ns, int(durations.max()))

    @property
    def count(self) -> int:
        """durations added"""
        return self._binned + len(self._pending)

    @property
    def max_ns(self) -> int:
        """the longest duration added [ns] (0 before any)"""
        self._fold()
        return self._max_ns

    def percentile_us(self, q: float) -> float:
        """The smallest bin value [µs] at or below which a fraction ``q`` of the durations lie."""
        self._fold()
        if self._binned == 0:
            return float("nan")
        cumulative = np.cumsum(self._bins)
        target = q * self._binned
        # the first bin that reaches the target (for q = 0: the first bin holding anything)
        first = (
            np.searchsorted(cumulative, target, side="left")
            if target > 0
            else np.searchsorted(cumulative, 0, "right")
        )
        return float(min(int(first), self._limit))

    def stats(self) -> DurationStats:
        count = self.count
        return DurationStats(
            count=count,
            p50_us=self.percentile_us(0.50),
            p99_us=self.percentile_us(0.99),
            max_us=self.max_ns / 1000.0 if count else float("nan"),
        )
