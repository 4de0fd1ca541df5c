"""The cycle owner: one SYNC per bus cycle for every drive of a bus.

Each cycle (every ``ticks_per_cycle`` bridge ticks, after every bridge stepped): each drive's RPDO 1
and 2 (controlword and setpoint, :meth:`~.adapter.CanopenDrive.rpdo_frames`), then the SYNC (COB-ID
0x080, no data). The drives latch their RPDOs at the SYNC, sample their actual values, answer with
TPDO 1 and 2 and run their position loop towards the new target until the next SYNC.

Pacing (``pacing`` in the configuration):

* ``wall`` — the caller (the bridge's loop, at ``--speed 1``) calls :meth:`SyncCycle.after_tick` on
  absolute deadlines of the monotonic clock and counts late ticks; the cycle does not wait: a drive's
  answer is read at the next tick (one cycle of latency, as on any field bus);
* ``lockstep`` — after the SYNC the cycle waits until every drive's TPDOs of it arrived (at most
  ``pdo_timeout_ms``; a drive known lost is not waited for): deterministic, for simulated drives and
  ``--speed 0``.

:meth:`SyncCycle.enable` runs cycles of its own before the bridge starts (the state machine walk of
every drive to operation enabled); :meth:`SyncCycle.shutdown` after it (the drives' own quick stop,
then switched off). A drive that was told the SYNC period (0x1006) watches for SYNC and faults when it
stops: at wall pacing :meth:`SyncCycle.idle` keeps the SYNC going (holding every drive where it is)
while the bridges are being set up.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass

import canopen

from ...errors import DriveError
from ...histogram import DurationHistogram, DurationStats
from ..drive import STOPPING_EVENTS
from .adapter import CanopenDrive
from .clock import BusClock
from .config import DriveConfig, Pacing
from .faults import RESET_TIMEOUT_S
from .objects import SYNC_COB_ID

log = logging.getLogger(__name__)

SHUTDOWN_TIMEOUT_S = 3.0
"""how long the drives' own quick stop may take at shutdown before they are switched off anyway"""
LATE_FACTOR = 1.5
"""a SYNC that follows the previous one by more than this many periods is late"""
MISSED_FACTOR = 2.0
"""… and by more than this many, a drive's SYNC watch counts a SYNC as missing"""


@dataclass(frozen=True)
class CycleReport:
    """What the SYNC of a bus did while the bridges ran."""

    cycle_hz: int
    pacing: str
    syncs: int
    interval_jitter: DurationStats | None
    """|SYNC interval − period| [µs] (wall pacing)"""
    late_cycles: int
    """SYNC intervals longer than :data:`LATE_FACTOR` periods"""
    missed_cycles: int
    """SYNC intervals longer than :data:`MISSED_FACTOR` periods: a drive's SYNC watch would count them"""
    waits_timed_out: int
    """lock-step cycles in which a drive's TPDOs did not come within its timeout"""

    def to_dict(self) -> dict[str, object]:
        return {
            "cycle_hz": self.cycle_hz,
            "pacing": self.pacing,
            "syncs": self.syncs,
            "interval_jitter": self.interval_jitter.to_dict() if self.interval_jitter else None,
            "late_cycles": self.late_cycles,
            "missed_cycles": self.missed_cycles,
            "waits_timed_out": self.waits_timed_out,
        }

    def summary(self) -> str:
        line = f"  CAN bus: {self.syncs} SYNCs at {self.cycle_hz} Hz ({self.pacing})"
        j = self.interval_jitter
        if j is not None and j.count:
            line += (
                f"; interval jitter p50 {j.p50_us:.0f} µs, p99 {j.p99_us:.0f} µs, max {j.max_us:.0f} µs; "
                f"{self.late_cycles} late (> {LATE_FACTOR:g} periods), {self.missed_cycles} missed "
                f"(> {MISSED_FACTOR:g})"
            )
        if self.waits_timed_out:
            line += f"; {self.waits_timed_out} lock-step waits timed out"
        return line


class SyncCycle:
    """The SYNC of one bus and the drives it serves (see the module docstring)."""

    def __init__(
        self, network: canopen.Network, config: DriveConfig, drives: list[CanopenDrive], clock: BusClock
    ) -> None:
        self.network, self.config, self.drives, self.clock = network, config, drives, clock
        self.lockstep = config.pacing is Pacing.LOCKSTEP
        self._wait_s = max(d.settings.pdo_timeout_ms for d in drives) / 1000.0
        self.syncs = 0
        self.waits_timed_out = 0
        """lock-step cycles in which some drive's TPDOs did not come within its timeout"""
        self._period_ns = self.clock.ticks_per_cycle * 1_000_000
        self._intervals = DurationHistogram()
        self._late = self._missed = 0
        self._last_sync_ns: int | None = None

    def start_measuring(self) -> None:
        """From now on (the bridges' loop) keep the SYNC intervals (:meth:`report`)."""
        self._intervals = DurationHistogram()
        self.syncs = self.waits_timed_out = self._late = self._missed = 0
        self._last_sync_ns = None

    def report(self) -> CycleReport:
        wall = not self.lockstep
        return CycleReport(
            self.config.cycle_hz, self.config.pacing.value, self.syncs,
            self._intervals.stats() if wall else None, self._late if wall else 0, self._missed if wall else 0,
            self.waits_timed_out,
        )  # fmt: skip

    def after_tick(self) -> None:
        """The bridge stepped every drive's tick: send the cycle if this tick has one; next tick."""
        if self.clock.is_sync_tick:
            self.sync()
        self.clock.tick += 1

    def sync(self) -> None:
        """RPDOs of every drive, the SYNC, and (lock-step) the wait for every drive's answer."""
        tick = self.clock.tick
        send = self.network.send_message
        for drive in self.drives:
            for cob_id, data in drive.rpdo_frames():
                send(cob_id, data)
        # the tick is set before the SYNC goes out: a drive's answer can come before send() returns
        now_ns = time.monotonic_ns()
        now = now_ns * 1e-9
        self.clock.sync_tick, self.clock.sync_sent_s = tick, now
        send(SYNC_COB_ID, b"")
        if self._last_sync_ns is not None:
            interval = now_ns - self._last_sync_ns
            self._intervals.add_ns(abs(interval - self._period_ns))
            self._late += interval > LATE_FACTOR * self._period_ns
            self._missed += interval > MISSED_FACTOR * self._period_ns
        self._last_sync_ns = now_ns
        for drive in self.drives:
            drive.on_sync(tick, now)
        self.syncs += 1
        if self.lockstep:
            with self.clock.arrived:
                answered = self.clock.arrived.wait_for(
                    lambda: all(d.answered(tick) for d in self.drives), self._wait_s
                )
            if not answered:
                self.waits_timed_out += 1

    @contextmanager
    def idle(self) -> Iterator[None]:
        """At wall pacing, SYNC cycles from a thread of their own while the block runs (the drives hold
        their last target; drive time stands still until the bridges' loop starts); nothing at lock-step,
        where nobody watches the SYNC's period."""
        if self.lockstep:
            yield
            return
        done = threading.Event()
        thread = threading.Thread(
            target=self._idle_cycles, args=(done,), name="canopen-idle-sync", daemon=True
        )
        thread.start()
        try:
            yield
        finally:
            done.set()
            thread.join()

    def _idle_cycles(self, done: threading.Event) -> None:
        period_s = self.clock.ticks_per_cycle * 1e-3
        deadline = time.monotonic()
        while not done.is_set():
            self.sync()
            deadline += period_s
            done.wait(max(0.0, deadline - time.monotonic()))

    # ---- before and after the bridge ----------------------------------------------------------------
    def _own_cycle(self, deadline: float) -> None:
        """One cycle outside the bridge's loop (at wall pacing: on the cycle's period)."""
        self.sync()
        self.clock.tick += self.clock.ticks_per_cycle
        if not self.lockstep:
            time.sleep(max(0.0, min(deadline - time.monotonic(), self.clock.ticks_per_cycle * 1e-3)))

    def enable(self) -> None:
        """Walk every drive to operation enabled (a fault is reset where start-up allowed it); raises
        :class:`DriveError` naming the drive that did not get there."""
        for drive in self.drives:
            drive.reset_fault()
        deadline = time.monotonic() + RESET_TIMEOUT_S + 1.0
        while True:
            for drive in self.drives:
                drive.collect()
                for event in drive.events():
                    if event.kind in STOPPING_EVENTS:
                        raise DriveError(f"enabling failed: {event.text}")
            if all(d.status().following for d in self.drives):
                return
            if time.monotonic() > deadline:
                raise DriveError("enabling failed: the drives did not reach operation enabled in time")
            self._own_cycle(deadline)

    def shutdown(self) -> None:
        """The drives' own quick stop until every reachable drive is at rest (at most
        :data:`SHUTDOWN_TIMEOUT_S`), then switched off (disable voltage) and NMT pre-operational."""
        live = [d for d in self.drives if d.health.comm_ok]
        for drive in live:
            drive.stop_for_shutdown()
        deadline = time.monotonic() + SHUTDOWN_TIMEOUT_S
        while live and not all(d.at_rest() for d in live):
            if time.monotonic() > deadline:
                moving = ", ".join(d.settings.name for d in live if not d.at_rest())
                log.warning("drive(s) %s not at rest %.0f s after their quick stop: switching off", moving,
                            SHUTDOWN_TIMEOUT_S)  # fmt: skip
                break
            self._own_cycle(deadline)
            for drive in live:
                drive.collect()
        for drive in live:
            drive.switch_off()
        if live:
            self._own_cycle(time.monotonic())
        for drive in self.drives:
            try:
                drive.node.nmt.state = "PRE-OPERATIONAL"
            except Exception as exc:  # a bus gone at shutdown: nothing more to tell the drive
                log.warning("NMT pre-operational for drive %s not sent: %s", drive.settings.name, exc)
