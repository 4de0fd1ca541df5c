"""The newest samples of one joint, kept in a ring of numpy arrays of fixed size.

An adaptive node receives the axis's samples in batches (decoded in bulk) and fits the last few tens of
seconds of them every few seconds. :class:`SampleRing` holds the newest ``capacity`` samples as three
columns — stamp [ns] (int64), position and effort (float64, the joint's units) — written in place:
no Python object per sample, no growing lists. :meth:`SampleRing.since` copies out the samples from a
stamp on, oldest first.

Samples must arrive in increasing stamp order (one drive's stream). A batch whose first stamp is not
after the newest held one means the source started again (a bridge restarted): the ring is emptied
and begins with that batch (:attr:`SampleRing.restarts` counts it); stamps that repeat or go back
inside a batch are dropped and counted (:attr:`SampleRing.dropped`).
"""

from __future__ import annotations

import numpy as np


class SampleRing:
    """The newest ``capacity`` samples (see the module docstring)."""

    def __init__(self, capacity: int) -> None:
        if capacity < 2:
            raise ValueError(f"ring capacity = {capacity} samples must be at least 2")
        self.capacity = capacity
        self._stamp = np.zeros(capacity, dtype=np.int64)
        self._position = np.zeros(capacity)
        self._effort = np.zeros(capacity)
        self._next = 0
        """where the next sample goes"""
        self._count = 0
        self.received = 0
        """samples taken in since the ring was made"""
        self.dropped = 0
        """samples dropped because their stamp repeated or went back inside a batch"""
        self.restarts = 0
        """batches that started at or before the newest stamp held: the ring began again with them"""

    def __len__(self) -> int:
        return self._count

    @property
    def newest_ns(self) -> int | None:
        """The stamp of the newest sample [ns], None while empty."""
        return int(self._stamp[(self._next - 1) % self.capacity]) if self._count else None

    @property
    def oldest_ns(self) -> int | None:
        return int(self._stamp[(self._next - self._count) % self.capacity]) if self._count else None

    def extend(self, stamp_ns: np.ndarray, position: np.ndarray, effort: np.ndarray) -> None:
        """Append a batch of samples (1-D arrays of one length, in stamp order)."""
        stamp_ns = np.asarray(stamp_ns, dtype=np.int64)
        position, effort = np.asarray(position, dtype=float), np.asarray(effort, dtype=float)
        if not stamp_ns.shape == position.shape == effort.shape or stamp_ns.ndim != 1:
            raise ValueError(
                f"a batch needs three 1-D columns of one length, got {stamp_ns.shape}, {position.shape}, "
                f"{effort.shape}"
            )
        if not stamp_ns.size:
            return
        self.received += stamp_ns.size
        newest = self.newest_ns
        if newest is not None and stamp_ns[0] <= newest:
            self.restarts += 1
            self._next = self._count = 0
        keep = np.ones(stamp_ns.size, dtype=bool)
        keep[1:] = stamp_ns[1:] > np.maximum.accumulate(stamp_ns)[:-1]
        if not keep.all():
            self.dropped += int(np.count_nonzero(~keep))
            stamp_ns, position, effort = stamp_ns[keep], position[keep], effort[keep]
        n = stamp_ns.size
        if n >= self.capacity:  # only the newest capacity samples stay
            keep_from = n - self.capacity
            stamp_ns, position, effort = stamp_ns[keep_from:], position[keep_from:], effort[keep_from:]
            n = self.capacity
        first = min(n, self.capacity - self._next)
        for column, values in ((self._stamp, stamp_ns), (self._position, position), (self._effort, effort)):
            column[self._next : self._next + first] = values[:first]
            column[: n - first] = values[first:]
        self._next = (self._next + n) % self.capacity
        self._count = min(self._count + n, self.capacity)

    def since(self, start_ns: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Copies of (stamp [ns], position, effort) of the held samples stamped at or after ``start_ns``,
        oldest first."""
        order = (np.arange(self._next - self._count, self._next)) % self.capacity
        stamps = self._stamp[order]
        first = int(np.searchsorted(stamps, start_ns, "left"))
        idx = order[first:]
        return self._stamp[idx], self._position[idx], self._effort[idx]
