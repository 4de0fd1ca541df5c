"""The drive time of a CANopen bus: 1 ms ticks, a SYNC every n of them.

Tick k is drive time ``t0 + k·1 ms`` (the bridge's tick). The SYNC of tick k (k a multiple of
``ticks_per_cycle``) carries the setpoint of tick k to every drive, and each drive's measurement at
that SYNC comes back stamped with the drive time of tick k: so a sample is always stamped with the
instant it was measured, one bus cycle before the master can read it.
"""

from __future__ import annotations

import threading
import time

from ....model import EXECUTION_PERIOD_NS


class BusClock:
    """The bus's drive time and the wake-up of a master waiting for process data (shared by the cycle
    owner, which advances it, and the drive adapters, which read it)."""

    def __init__(self, ticks_per_cycle: int, start_stamp_ns: int | None = None) -> None:
        """``start_stamp_ns``: the drive time of tick 0 [ns since the epoch]; None: the next whole
        millisecond of the wall clock."""
        self.ticks_per_cycle = ticks_per_cycle
        self.tick = 0
        """the tick the bridge commands next"""
        self.sync_tick = -1
        """the tick of the latest SYNC sent (−1: none yet)"""
        self.sync_sent_s = 0.0
        """when it was sent [s, monotonic clock]"""
        if start_stamp_ns is None:
            start_stamp_ns = -(-time.time_ns() // EXECUTION_PERIOD_NS) * EXECUTION_PERIOD_NS
        self.start_stamp_ns = start_stamp_ns
        self.arrived = threading.Condition()
        """notified by the adapters' receive callbacks when process data arrives"""

    def stamp_ns(self, tick: int) -> int:
        return self.start_stamp_ns + tick * EXECUTION_PERIOD_NS

    @property
    def is_sync_tick(self) -> bool:
        """Whether the current tick's setpoint goes out with a SYNC."""
        return self.tick % self.ticks_per_cycle == 0

    def notify_arrival(self) -> None:
        with self.arrived:
            self.arrived.notify_all()
