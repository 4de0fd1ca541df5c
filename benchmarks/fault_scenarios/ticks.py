"""The 1 kHz samples of a recording, tick by tick: every tick there, once, in order, and how late each
ran (from the file alone)."""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...acquisition import AxisKeys, read_joint_states
from ...model import EXECUTION_PERIOD_NS

KEYS = AxisKeys()
"""the axis of every scenario"""
STATE_TOPIC = "/" + KEYS.state
SETPOINT_TOPIC = "/" + KEYS.setpoint
TICK_NS = EXECUTION_PERIOD_NS


@dataclass(frozen=True)
class Stalls:
    """How late the ticks of a stretch of drive time started."""

    ticks: int
    late: int
    """ticks that started more than a period (1 ms) after their deadline"""
    max_ms: float
    """the latest tick start [ms after its deadline]"""

    def __str__(self) -> str:
        return f"{self.late} of {self.ticks} ticks late, longest stall {self.max_ms:.1f} ms"


@dataclass(frozen=True, eq=False)
class TickRecord:
    """The 1 kHz samples of one topic in a recording, split by publisher (a restarted bridge numbers
    its samples from 1 again).

    A sample's ``publish_time`` is the wall time at which the bridge published it and its header stamp
    the tick's drive time, which at 1× real time advances with the wall clock: publish − stamp, less
    its median, is how late that tick ran (:attr:`late_ns`) — a tick-by-tick record of the loop's
    timing, from the file alone."""

    runs: tuple[tuple[int, int, int, int], ...]
    """per publisher, in file order: (messages, first sequence, last sequence, first stamp [ns])"""
    bad_steps: int
    """consecutive samples of one publisher whose stamps are not exactly 1 ms apart"""
    sequence_gaps: int
    """sequence numbers skipped within one publisher"""
    misplaced: int
    """consecutive samples of one publisher whose stamp step is not their sequence step × 1 ms (a
    sample out of order, doubled or mislabelled; a lost one is a sequence gap, not this)"""
    last_stamp_ns: tuple[int, ...]
    """per publisher, its last stamp [ns]"""
    stamp_ns: np.ndarray
    late_ns: np.ndarray
    """per sample, how late its tick ran [ns] (see the class docstring)"""
    position_m: np.ndarray
    velocity_m_s: np.ndarray
    """the carriage joint of each sample"""

    @property
    def messages(self) -> int:
        return sum(r[0] for r in self.runs)

    @property
    def contiguous(self) -> bool:
        """No tick missing between the first and the last of each publisher: no sequence gap, stamps
        exactly 1 ms apart."""
        return bool(self.runs) and self.bad_steps == 0 and self.sequence_gaps == 0

    @property
    def consistent(self) -> bool:
        """Every sample where its sequence number puts it (lost samples allowed: see ``sequence_gaps``)."""
        return bool(self.runs) and self.misplaced == 0

    @property
    def every_tick(self) -> bool:
        """Every tick there, once, in order, from each publisher's first: :attr:`contiguous` and the
        sequences start at 1."""
        return self.contiguous and all(r[1] == 1 for r in self.runs)

    def stalls(self, t0_ns: int | None = None, t1_ns: int | None = None) -> Stalls:
        """Late ticks between drive times ``t0_ns`` and ``t1_ns`` (default: all)."""
        keep = np.ones(len(self.stamp_ns), bool)
        if t0_ns is not None:
            keep &= self.stamp_ns >= t0_ns
        if t1_ns is not None:
            keep &= self.stamp_ns < t1_ns
        late = self.late_ns[keep]
        return Stalls(int(late.size), int(np.count_nonzero(late > TICK_NS)), float(late.max(initial=0)) / 1e6)


def tick_record(path: Path, topic: str = STATE_TOPIC) -> TickRecord:
    """:class:`TickRecord` of ``topic`` in ``path`` (complete or cut off by a crash)."""
    cols = read_joint_states(path, topic)
    seq = cols.sequence.astype(np.int64)
    stamps = cols.stamp_ns.astype(np.int64)
    delay = cols.publish_time_ns.astype(np.int64) - stamps
    late = np.empty_like(delay)
    starts = [0, *(np.flatnonzero(np.diff(seq) < 0) + 1).tolist(), len(seq)]
    runs, last, bad, gaps, misplaced = [], [], 0, 0, 0
    for a, b in itertools.pairwise(starts):
        if a == b:
            continue
        s, t = seq[a:b], stamps[a:b]
        runs.append((b - a, int(s[0]), int(s[-1]), int(t[0])))
        last.append(int(t[-1]))
        bad += int(np.count_nonzero(np.diff(t) != TICK_NS))
        gaps += int(np.sum(np.maximum(np.diff(s) - 1, 0)))
        misplaced += int(np.count_nonzero(np.diff(t) != np.diff(s) * TICK_NS))
        late[a:b] = delay[a:b] - np.median(delay[a:b])
    carriage = cols.joint("carriage")
    return TickRecord(
        tuple(runs), bad, gaps, misplaced, tuple(last), stamps, late, carriage.position, carriage.velocity
    )


def phase_stalls(state: TickRecord, marks: dict[str, int]) -> dict[str, Stalls]:
    """:meth:`TickRecord.stalls` between consecutive ``marks`` (name → wall time [ns] its phase began;
    the last mark ends the last phase)."""
    edges = list(marks.values())
    return {name: state.stalls(t0, t1) for name, t0, t1 in zip(marks, edges, edges[1:], strict=False)}
