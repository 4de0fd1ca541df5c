"""The tracking error of an axis: setpoint minus measured carriage position at the same tick.

The bridge stamps the sample and the setpoint of a tick with the same drive time, so the error of
tick k is x_set(t_k) − x(t_k), paired by equal stamps. The two topics arrive separately (live: in
batches, in any order between them), so :class:`TrackingJoin` keeps the samples that have no partner
yet and pairs them when it comes; a sample still unpaired once the other topic is
:data:`UNPAIRED_HORIZON_NS` past it never gets one (a lost message) and is dropped.
"""

from __future__ import annotations

import numpy as np

UNPAIRED_HORIZON_NS = 2_000_000_000
"""how far [ns] the other topic may run ahead before an unpaired sample is given up"""


def _pairs(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Indices (ia, ib) with a[ia] == b[ib], each stamp paired at most once."""
    if len(a) == len(b) and np.array_equal(a, b) and (len(a) < 2 or bool(np.all(a[1:] > a[:-1]))):
        every = np.arange(len(a))  # the usual case: both topics hold the same ticks
        return every, every
    if len(a) and len(b) and bool(np.all(a[1:] > a[:-1])) and bool(np.all(b[1:] > b[:-1])):
        ib = np.minimum(np.searchsorted(b, a), len(b) - 1)
        ia = np.flatnonzero(b[ib] == a)
        return ia, ib[ia]
    _common, ia, ib = np.intersect1d(a, b, assume_unique=False, return_indices=True)
    return ia, ib


class TrackingJoin:
    """Pairs measured and setpoint positions by stamp, batch by batch."""

    def __init__(self) -> None:
        self._state = (np.empty(0, np.int64), np.empty(0))
        self._setpoint = (np.empty(0, np.int64), np.empty(0))
        self._newest_state = self._newest_setpoint = int(np.iinfo(np.int64).min)

    def push(
        self,
        state: tuple[np.ndarray, np.ndarray] | None = None,
        setpoint: tuple[np.ndarray, np.ndarray] | None = None,
    ) -> tuple[np.ndarray, np.ndarray]:
        """Add (stamp_ns, position_m) of either topic; returns (stamp_ns, setpoint − measured [m]) of
        the ticks paired by this call, in increasing stamp order."""
        st = _joined(self._state, state)
        sp = _joined(self._setpoint, setpoint)
        ia, ib = _pairs(st[0], sp[0])
        stamps = st[0][ia]
        error = sp[1][ib] - st[1][ia]
        keep_st = np.ones(len(st[0]), bool)
        keep_st[ia] = False
        keep_sp = np.ones(len(sp[0]), bool)
        keep_sp[ib] = False
        # a sample is given up once the other topic has run UNPAIRED_HORIZON_NS past it
        lowest = np.iinfo(np.int64).min
        self._newest_state = max(self._newest_state, int(st[0].max(initial=lowest)))
        self._newest_setpoint = max(self._newest_setpoint, int(sp[0].max(initial=lowest)))
        if self._newest_setpoint != lowest:
            keep_st &= st[0] >= self._newest_setpoint - UNPAIRED_HORIZON_NS
        if self._newest_state != lowest:
            keep_sp &= sp[0] >= self._newest_state - UNPAIRED_HORIZON_NS
        self._state = (st[0][keep_st], st[1][keep_st])
        self._setpoint = (sp[0][keep_sp], sp[1][keep_sp])
        if len(stamps) > 1 and not bool(np.all(stamps[1:] > stamps[:-1])):
            order = np.argsort(stamps, kind="stable")
            stamps, error = stamps[order], error[order]
        return stamps, error

    @property
    def unpaired(self) -> int:
        """samples waiting for their partner"""
        return len(self._state[0]) + len(self._setpoint[0])


def _joined(
    kept: tuple[np.ndarray, np.ndarray], new: tuple[np.ndarray, np.ndarray] | None
) -> tuple[np.ndarray, np.ndarray]:
    if new is None:
        return kept
    if not len(kept[0]):
        return np.asarray(new[0], np.int64), np.asarray(new[1], float)
    return np.concatenate([kept[0], new[0]]), np.concatenate([kept[1], new[1]])
