"""The drive's sampling grid behind a log's stamps: its period and phase, where samples are missing.

A drive samples on its own clock at a fixed period; a log's stamps scatter around that grid (a stamp
taken when a message was handled: tens of µs) and some samples never arrive (a lost frame, a dropped
message, a chunk a reader had to skip). :func:`place_on_grid` recovers the grid from the stamps alone:

1. each step between consecutive stamps is a whole number of periods, n_i = round(step_i / P₀), P₀ the
   median step (a step of n_i > 1 periods is a hole of n_i − 1 missing samples);
2. the grid index of each sample is the running sum of those, and the period and phase are then fitted
   to (index, stamp) by least squares;
3. the largest deviation of a stamp from its grid point is the stamp jitter. It must stay below half a
   period, or the stamps do not sit on a grid at all (an error naming the sample).

The result says how many samples are missing, in how many holes, and the longest; the caller decides
what a usable log is (:data:`MAX_LOST_FRACTION`). Stamps that go back or repeat are errors here: a
log that does that has a problem no grid can mend.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import IdentificationError

MAX_LOST_FRACTION = 0.2
"""more missing samples than this fraction of the grid, and a fit would be mostly made of the
neighbourhoods of holes (which are left out): an error"""


@dataclass(frozen=True, eq=False)
class SampleGrid:
    """Where the samples of a log sit on the drive's grid (see the module docstring)."""

    period_ns: float
    """the drive's sampling period [ns] (least squares over the log)"""
    index: np.ndarray
    """grid index of each sample (int64, strictly increasing, first 0)"""
    jitter_s: float
    """the largest |stamp − grid time| [s]"""
    holes: np.ndarray
    """(n, 2) int64: grid index of the first missing sample of each hole, and its length in samples"""

    @property
    def size(self) -> int:
        """Grid points from the first sample to the last."""
        return int(self.index[-1]) + 1

    @property
    def lost(self) -> int:
        """Samples missing between the first and the last."""
        return int(self.holes[:, 1].sum()) if self.holes.size else 0

    @property
    def longest_hole(self) -> int:
        return int(self.holes[:, 1].max()) if self.holes.size else 0

    def observed(self) -> np.ndarray:
        """True at the grid points that have a sample."""
        mask = np.zeros(self.size, dtype=bool)
        mask[self.index] = True
        return mask

    def times_s(self) -> np.ndarray:
        """Grid times from the first sample's grid point [s]."""
        return np.arange(self.size, dtype=float) * (self.period_ns * 1e-9)

    def spread(self, values: np.ndarray) -> np.ndarray:
        """``values`` (one per sample) on the grid, the holes filled by linear interpolation (so that
        filters can run over them; the caller keeps what they touch out of any fit)."""
        if not self.holes.size:
            return np.asarray(values, dtype=float)
        return np.interp(np.arange(self.size, dtype=float), self.index.astype(float), values)

    def describe(self) -> str:
        if not self.holes.size:
            return "no sample missing"
        return (
            f"{self.lost} of {self.size} samples missing ({self.lost / self.size:.2%}) in "
            f"{len(self.holes)} holes, the longest {self.longest_hole * self.period_ns * 1e-6:.0f} ms"
        )


def place_on_grid(
    stamps_ns: np.ndarray, source: str, first: int = 0, origin_ns: int | None = None
) -> SampleGrid:
    """The grid of increasing ``stamps_ns`` (see the module docstring). Errors name samples by their
    index in the whole log (``first``: the index of ``stamps_ns[0]``) and times in seconds from
    ``origin_ns`` (default the first stamp)."""
    stamps = np.asarray(stamps_ns, dtype=np.int64)
    origin = int(stamps[0]) if origin_ns is None else origin_ns
    if stamps.size < 3:
        raise IdentificationError(f"{source}: {stamps.size} samples are too few to identify anything")
    steps = np.diff(stamps)
    back = np.flatnonzero(steps <= 0)
    if back.size:
        k = int(back[0]) + 1
        t = (int(stamps[k]) - origin) * 1e-9
        raise IdentificationError(
            f"{source}: time stamps do not increase: sample {first + k} at {t:.6f} s is "
            f"{-int(steps[k - 1]) * 1e-9:.6f} s before sample {first + k - 1} ({back.size} such steps in all)"
        )
    period0 = float(np.median(steps))
    periods = np.rint(steps / period0).astype(np.int64)
    short = np.flatnonzero(periods < 1)
    if short.size:
        k = int(short[0])
        raise IdentificationError(
            f"{source}: samples {first + k} and {first + k + 1} are {steps[k] * 1e-6:.3f} ms apart, "
            f"less than half the log's step of {period0 * 1e-6:.3f} ms: duplicated or irregular samples"
        )
    index = np.concatenate([[0], np.cumsum(periods)])
    since = (stamps - stamps[0]).astype(float)
    period, offset = _line(index, since)
    deviation = since - (offset + index * period)
    worst = int(np.argmax(np.abs(deviation)))
    jitter_s = float(abs(deviation[worst])) * 1e-9
    if jitter_s >= 0.5 * period * 1e-9:
        t = (int(stamps[worst]) - origin) * 1e-9
        raise IdentificationError(
            f"{source}: the stamps do not sit on a sampling grid: sample {first + worst} at {t:.6f} s is "
            f"{jitter_s * 1e3:.3f} ms from it, more than half the period {period * 1e-6:.3f} ms"
        )
    gaps = np.flatnonzero(periods > 1)
    holes = np.column_stack([index[gaps] + 1, periods[gaps] - 1]) if gaps.size else np.empty((0, 2), np.int64)
    grid = SampleGrid(float(period), index, jitter_s, holes.astype(np.int64))
    if grid.lost > MAX_LOST_FRACTION * grid.size:
        raise IdentificationError(
            f"{source}: {grid.describe()}: more than {MAX_LOST_FRACTION:.0%} of the log is missing, a fit "
            "would be made of little but the edges of holes; fit the unbroken parts (--start/--end)"
        )
    return grid


def _line(x: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """Slope and intercept of the least-squares line through (x, y) (closed form, O(n) memory)."""
    xm, ym = float(np.mean(x)), float(np.mean(y))
    dx = x - xm
    slope = float(np.dot(dx, y - ym) / np.dot(dx, dx))
    return slope, ym - slope * xm
