"""The bridge's tick clock: absolute deadlines on the monotonic clock, and a ticking thread shielded
from what delays it.

**Absolute deadlines.** Tick k is due at ``start + k·period``. The thread sleeps in libc's
``clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, deadline)`` (through ctypes, which lets go of the
GIL for the call): the kernel wakes it at the deadline itself, so neither the time taken to compute a
relative delay nor a signal that interrupts the sleep moves it, and a late tick runs at once without
the schedule drifting. No spin: on a machine of two cores with other work on both, a spinning thread
takes the core from what it waits for. Where libc has no ``clock_nanosleep`` the clock sleeps the
relative rest instead (``threading.Event.wait``). A deadline more than :data:`_COARSE_NS` away (a
slowed-down bridge) is slept in an interruptible wait first, so a stop ends it at once.

**What else delays a tick, and what the clock does about it** (:class:`TickTiming`):

* the garbage collector: everything allocated before the loop is frozen out of its way
  (``gc.freeze``), the automatic collection is off while the loop runs, and the clock collects the
  young generation itself every :data:`_YOUNG_EVERY` ticks, right after a tick's work, when the next
  deadline is farthest, and the whole heap every :data:`_FULL_EVERY` ticks the same way;
* the GIL: a thread woken for its tick waits until the thread holding the GIL lets go, which it is
  asked to do after the switch interval (5 ms by default): the loop runs with
  :data:`_SWITCH_INTERVAL_S`;
* the scheduler: with ``rt_priority`` the ticking thread runs as ``SCHED_FIFO`` at that priority, so
  it preempts every ordinary process the moment its deadline comes (needs ``CAP_SYS_NICE``, or an
  ``RLIMIT_RTPRIO`` of at least that priority: ``ulimit -r``, ``/etc/security/limits.conf``'s
  ``rtprio``; ``chrt -f P axisflow bridge …`` does the same for a whole process). Only this thread:
  Zenoh's threads and the move intake stay ordinary. With ``cpus`` it is also held to those cores
  (``os.sched_setaffinity``; ``taskset -c`` for a whole process). An ordinary thread's timer slack
  (50 µs by default) is set to 1 µs, and its time slice to :data:`_SLICE_NS` where the kernel's
  scheduler (EEVDF, Linux 6.12 on) takes one from ``sched_setattr``: a woken thread with a short
  slice may preempt the one running instead of waiting for the end of its slice (1.4 ms here).

The clock measures what it did: per tick the lateness (wake-up − deadline) and the period jitter
(|period − nominal|), the ticks late by more than a period, and how often it collected garbage.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import errno
import gc
import logging
import os
import sys
import threading
import time
from dataclasses import dataclass, field

from ..errors import AcquisitionError
from ..histogram import DurationHistogram

log = logging.getLogger(__name__)

_COARSE_NS = 20_000_000
"""a deadline farther than this is first waited for in an interruptible wait (a stop ends it)"""
_YOUNG_EVERY = 100
"""ticks between two collections of the youngest generation (automatic collection being off)"""
_FULL_EVERY = 60_000
"""ticks between two collections of every generation (a minute at 1 kHz)"""
_SWITCH_INTERVAL_S = 0.0002
"""the GIL's switch interval while the loop runs: how long a woken tick waits for a busy thread"""
_SLICE_NS = 100_000
"""the time slice an ordinary ticking thread asks for (the shortest the kernel takes) [ns]"""
_SYS_SCHED_SETATTR = {"x86_64": 314, "aarch64": 274}
_CLOCK_MONOTONIC = 1
_TIMER_ABSTIME = 1
_PR_SET_TIMERSLACK = 29


class TickTimingError(AcquisitionError):
    """The real-time priority or the CPU affinity asked for cannot be had."""


@dataclass(frozen=True)
class TickTiming:
    """How the ticking thread runs (see the module docstring)."""

    rt_priority: int | None = None
    """SCHED_FIFO priority of the ticking thread (1…99); None: an ordinary thread"""
    cpus: tuple[int, ...] | None = None
    """the cores the ticking thread may run on; None: any"""

    def __post_init__(self) -> None:
        if self.rt_priority is not None:
            if not 1 <= self.rt_priority <= 99:
                raise TickTimingError(f"real-time priority {self.rt_priority} is outside 1…99 (SCHED_FIFO)")
            if not fifo_allowed(self.rt_priority):
                raise TickTimingError(_not_allowed(self.rt_priority))
        if self.cpus is not None:
            available = sorted(os.sched_getaffinity(0))
            missing = sorted(set(self.cpus) - set(available))
            if not self.cpus or missing:
                raise TickTimingError(
                    f"CPUs {','.join(map(str, self.cpus)) or '(none)'} are not all available to this "
                    f"process (it may run on {','.join(map(str, available))})"
                )


class _Timespec(ctypes.Structure):
    _fields_ = [("tv_sec", ctypes.c_long), ("tv_nsec", ctypes.c_long)]


class _SchedAttr(ctypes.Structure):
    """The kernel's ``struct sched_attr`` (sched_setattr(2))."""

    _fields_ = [
        ("size", ctypes.c_uint32),
        ("sched_policy", ctypes.c_uint32),
        ("sched_flags", ctypes.c_uint64),
        ("sched_nice", ctypes.c_int32),
        ("sched_priority", ctypes.c_uint32),
        ("sched_runtime", ctypes.c_uint64),
        ("sched_deadline", ctypes.c_uint64),
        ("sched_period", ctypes.c_uint64),
    ]


def _set_slice(libc: ctypes.CDLL, slice_ns: int) -> bool:
    """Ask for a time slice of ``slice_ns`` for the calling (ordinary) thread; 0 asks for the default.
    False where the kernel or the architecture does not take one."""
    import platform

    number = _SYS_SCHED_SETATTR.get(platform.machine())
    if number is None:
        return False
    nice = os.getpriority(os.PRIO_PROCESS, 0)
    attr = _SchedAttr(ctypes.sizeof(_SchedAttr), os.SCHED_OTHER, 0, nice, 0, slice_ns, 0, 0)
    return libc.syscall(number, 0, ctypes.byref(attr), 0) == 0


def _libc() -> ctypes.CDLL | None:
    name = ctypes.util.find_library("c")
    try:
        return ctypes.CDLL(name, use_errno=True) if name else None
    except OSError:
        return None


@dataclass
class _Counts:
    lateness: DurationHistogram = field(default_factory=DurationHistogram)
    jitter: DurationHistogram = field(default_factory=DurationHistogram)
    late: int = 0
    collections: int = 0


class TickClock:
    """The deadlines of a loop of ticks ``period_ns`` apart, from the first :meth:`wait` on; use as a
    context manager on the ticking thread (entering applies :class:`TickTiming` and the garbage
    collector's shield, leaving undoes them)."""

    def __init__(self, period_ns: float, stop: threading.Event, timing: TickTiming | None = None) -> None:
        self.period_ns = period_ns
        self.timing = timing or TickTiming()
        self._stop = stop
        self._counts = _Counts()
        self._start_ns: int | None = None
        self._prev_ns = 0
        self._ticks = 0
        self._restore: list[object] = []
        libc = _libc()
        self._sleep = getattr(libc, "clock_nanosleep", None) if libc is not None else None
        if self._sleep is not None:
            self._sleep.argtypes = [ctypes.c_int, ctypes.c_int, ctypes.POINTER(_Timespec), ctypes.c_void_p]
            self._sleep.restype = ctypes.c_int
        self._libc = libc
        self._ts = _Timespec()
        self._ts_ref = ctypes.byref(self._ts)

    @property
    def absolute(self) -> bool:
        """True when the clock sleeps to absolute deadlines (libc's clock_nanosleep)."""
        return self._sleep is not None

    # ---- entering and leaving --------------------------------------------------------------------------
    def __enter__(self) -> TickClock:
        t = self.timing
        if t.cpus is not None:
            before = os.sched_getaffinity(0)
            os.sched_setaffinity(0, t.cpus)
            self._restore.append(lambda: os.sched_setaffinity(0, before))
        if t.rt_priority is not None:
            policy, param = os.sched_getscheduler(0), os.sched_getparam(0)
            try:
                os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(t.rt_priority))
            except PermissionError:
                self._undo()
                raise TickTimingError(_not_allowed(t.rt_priority)) from None
            self._restore.append(lambda: os.sched_setscheduler(0, policy, param))
        elif self._libc is not None and os.sched_getscheduler(0) == os.SCHED_OTHER:
            libc = self._libc
            libc.prctl(_PR_SET_TIMERSLACK, 1, 0, 0, 0)  # (a real-time thread has no slack)
            self._restore.append(lambda: libc.prctl(_PR_SET_TIMERSLACK, 0, 0, 0, 0))  # 0: the default
            if _set_slice(libc, _SLICE_NS):
                self._restore.append(lambda: _set_slice(libc, 0))
        interval = sys.getswitchinterval()
        sys.setswitchinterval(_SWITCH_INTERVAL_S)
        self._restore.append(lambda: sys.setswitchinterval(interval))
        was_enabled = gc.isenabled()
        gc.collect()
        gc.freeze()  # what is allocated by now lives as long as the loop: out of the collector's way
        gc.disable()
        self._restore.append(lambda: gc.enable() if was_enabled else None)
        self._restore.append(gc.unfreeze)
        return self

    def _undo(self) -> None:
        while self._restore:
            undo = self._restore.pop()
            try:
                undo()  # type: ignore[operator]
            except OSError as exc:  # e.g. a priority that cannot be lowered back: the thread ends anyway
                log.debug("tick clock: could not undo a setting: %s", exc)

    def __exit__(self, *_exc: object) -> None:
        self._undo()

    # ---- the loop ------------------------------------------------------------------------------------
    def wait(self) -> bool:
        """Sleep until the next tick's deadline (the first tick: now); True when it is time, False
        when ``stop`` was set meanwhile. Counts how late it woke."""
        if self._start_ns is None:
            self._start_ns = time.monotonic_ns()
        deadline = self._start_ns + int(self._ticks * self.period_ns)
        now = time.monotonic_ns()
        if deadline - now > _COARSE_NS and self._stop.wait((deadline - now - _COARSE_NS // 2) * 1e-9):
            return False
        if deadline > now:
            self._sleep_until(deadline)
            now = time.monotonic_ns()
        if self._stop.is_set():
            return False
        counts = self._counts
        counts.lateness.add_ns(max(now - deadline, 0))
        if self._ticks:
            counts.jitter.add_ns(abs(now - self._prev_ns - int(self.period_ns)))
        if now - deadline > self.period_ns:
            counts.late += 1
        self._prev_ns = now
        self._ticks += 1
        return True

    def _sleep_until(self, deadline_ns: int) -> None:
        if self._sleep is None:
            self._stop.wait((deadline_ns - time.monotonic_ns()) * 1e-9)
            return
        self._ts.tv_sec, self._ts.tv_nsec = divmod(deadline_ns, 1_000_000_000)
        while self._sleep(_CLOCK_MONOTONIC, _TIMER_ABSTIME, self._ts_ref, None) == errno.EINTR:
            if self._stop.is_set():  # a signal: the handler's stop may already be set
                return

    def after_tick(self) -> None:
        """Right after a tick's work, when the next deadline is farthest: collect garbage on schedule."""
        ticks = self._ticks
        if ticks % _FULL_EVERY == 0:
            gc.collect()
        elif ticks % _YOUNG_EVERY == 0:
            gc.collect(0)
        else:
            return
        self._counts.collections += 1

    # ---- what it measured ----------------------------------------------------------------------------
    @property
    def ticks(self) -> int:
        return self._ticks

    @property
    def start_ns(self) -> int | None:
        """the first tick's deadline (monotonic clock [ns]); tick k is due ``k`` periods after it"""
        return self._start_ns

    @property
    def late_ticks(self) -> int:
        """ticks that woke more than a period after their deadline"""
        return self._counts.late

    @property
    def lateness(self) -> DurationHistogram:
        """wake-up − deadline per tick [ns]"""
        return self._counts.lateness

    @property
    def period_jitter(self) -> DurationHistogram:
        """|wake-up − previous wake-up − period| per tick after the first [ns]"""
        return self._counts.jitter

    @property
    def collections(self) -> int:
        """garbage collections the clock ran between ticks"""
        return self._counts.collections


def fifo_allowed(priority: int) -> bool:
    """Whether a thread of this process may run as SCHED_FIFO at ``priority`` (tried on a thread of
    its own, which ends right after)."""
    allowed: list[bool] = []

    def attempt() -> None:
        try:
            os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(priority))
            allowed.append(True)
        except PermissionError:
            allowed.append(False)

    thread = threading.Thread(target=attempt, name="rt-priority-check")
    thread.start()
    thread.join()
    return allowed == [True]


def _not_allowed(priority: int) -> str:
    import resource

    soft, _hard = resource.getrlimit(resource.RLIMIT_RTPRIO)
    limit = "unlimited" if soft == resource.RLIM_INFINITY else str(soft)
    return (
        f"real-time priority {priority} (SCHED_FIFO) is not allowed here: it needs CAP_SYS_NICE or an "
        f"RLIMIT_RTPRIO of at least {priority} (ulimit -r is {limit}; docs/acquisition.md says how)"
    )
