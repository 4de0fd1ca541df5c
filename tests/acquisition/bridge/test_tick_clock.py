"""The bridge's tick clock: absolute deadlines that do not drift, a stop that ends a long wait at once,
the garbage collector kept out of the loop and given back after it, and the ticking thread's priority
and cores (where this system allows them)."""

import gc
import os
import platform
import threading
import time
from pathlib import Path

import pytest
from axisflow.acquisition.bridge.tick_clock import TickClock, TickTiming, TickTimingError, fifo_allowed

PERIOD_NS = 1_000_000


def test_ticks_keep_to_absolute_deadlines_and_the_schedule_does_not_drift():
    stop, woke = threading.Event(), []
    with TickClock(PERIOD_NS, stop) as clock:
        assert clock.absolute  # libc's clock_nanosleep on this system
        for k in range(200):
            assert clock.wait()
            woke.append(time.monotonic_ns())
            if k == 50:  # a tick whose work overruns by five periods
                time.sleep(5 * PERIOD_NS * 1e-9)
            clock.after_tick()
    assert clock.ticks == 200 and clock.lateness.count == 200 and clock.period_jitter.count == 199
    # never early: tick k starts at or after its deadline, k periods after the first one's
    assert all(t >= clock.start_ns + k * PERIOD_NS for k, t in enumerate(woke)), "a tick came early"
    # the ticks after the overrun are measured against the schedule, not against the overrun tick: the
    # next one starts at least four periods after its deadline (a relative sleep would call it on time)
    assert clock.lateness.max_ns >= 4 * PERIOD_NS
    assert clock.late_ticks >= 1


def test_a_stop_ends_a_long_wait_at_once():
    stop = threading.Event()
    result = []
    with TickClock(10 * 1e9, stop) as clock:  # ten seconds a tick
        assert clock.wait()  # the first tick: now
        waiter = threading.Thread(target=lambda: result.append(clock.wait()))
        waiter.start()
        stop.set()
        waiter.join(5.0)
    assert result == [False]


def test_the_collector_stays_out_of_the_loop_and_comes_back_after_it():
    assert gc.isenabled() and gc.get_freeze_count() == 0
    with TickClock(PERIOD_NS / 100, threading.Event()) as clock:  # 10 µs ticks: quick
        assert not gc.isenabled() and gc.get_freeze_count() > 0
        for _ in range(250):
            assert clock.wait()
            clock.after_tick()
    assert clock.collections == 2  # after ticks 100 and 200
    assert gc.isenabled() and gc.get_freeze_count() == 0


def test_bad_timings_are_refused_naming_the_value():
    with pytest.raises(TickTimingError, match="real-time priority 0 is outside 1…99"):
        TickTiming(rt_priority=0)
    with pytest.raises(TickTimingError, match="real-time priority 100 is outside 1…99"):
        TickTiming(rt_priority=100)
    missing = max(os.sched_getaffinity(0)) + 1
    with pytest.raises(TickTimingError, match=f"CPUs 0,{missing} are not all available"):
        TickTiming(cpus=(0, missing))


@pytest.mark.skipif(not fifo_allowed(1), reason="SCHED_FIFO is not allowed to this process")
def test_the_ticking_thread_alone_runs_at_real_time_priority_on_its_core():
    core = min(os.sched_getaffinity(0))
    seen = {}

    def ticking() -> None:
        with TickClock(PERIOD_NS, threading.Event(), TickTiming(rt_priority=1, cpus=(core,))) as clock:
            clock.wait()
            seen["inside"] = (os.sched_getscheduler(0), os.sched_getaffinity(0))
        seen["after"] = (os.sched_getscheduler(0), os.sched_getaffinity(0))

    thread = threading.Thread(target=ticking)
    thread.start()
    thread.join(5.0)
    assert seen["inside"] == (os.SCHED_FIFO, {core})
    assert seen["after"] == (os.SCHED_OTHER, os.sched_getaffinity(0))
    assert os.sched_getscheduler(0) == os.SCHED_OTHER  # this thread was never touched


def test_an_rt_priority_this_system_refuses_is_one_line_naming_the_limit():
    if fifo_allowed(1):
        pytest.skip("SCHED_FIFO is allowed to this process: nothing to refuse")
    with pytest.raises(TickTimingError, match=r"real-time priority 1 \(SCHED_FIFO\) is not allowed here"):
        TickTiming(rt_priority=1)


def _slice_ns() -> int | None:
    """The calling thread's time slice, as the kernel's scheduler reports it (None: it does not)."""
    for line in Path("/proc/thread-self/sched").read_text().splitlines():
        if line.startswith("se.slice"):
            return int(line.split(":")[1])
    return None


@pytest.mark.skipif(_slice_ns() is None, reason="the kernel reports no time slice")
def test_an_ordinary_ticking_thread_asks_for_a_short_slice_and_gives_it_back():
    before = _slice_ns()
    with TickClock(PERIOD_NS, threading.Event()):
        inside = _slice_ns()
    # the scheduler takes a custom slice from Linux 6.12 on (EEVDF); before, the slice is unchanged
    release = tuple(int(part) for part in platform.release().split(".")[:2])
    assert inside == (100_000 if release >= (6, 12) else before)
    assert _slice_ns() == before
