"""What a process costs, read from /proc: counted against work this test does itself."""

import os
import threading

import pytest
from axisflow.benchmarks.toolkit.proc_stats import (
    cpu_seconds,
    cpu_seconds_or_zero,
    rss_kb,
    status_kb,
    thread_cpu_seconds,
)


def test_thread_cpu_seconds_names_each_thread_and_counts_its_own_work():
    me = threading.get_native_id()
    before = thread_cpu_seconds(os.getpid())
    deadline = cpu_seconds(os.getpid()) + 0.2
    while cpu_seconds(os.getpid()) < deadline:  # 0.2 s of CPU, on this thread
        sum(range(10_000))
    after = thread_cpu_seconds(os.getpid())
    assert after[me][1] - before[me][1] >= 0.15
    assert sum(seconds for _name, seconds in after.values()) <= cpu_seconds(os.getpid()) + 0.02


def test_a_process_that_is_gone_costs_nothing_more():
    gone = 2**22 + 1  # above the largest pid_max Linux allows: no such process
    assert cpu_seconds_or_zero(gone) == 0.0 and rss_kb(gone) == 0
    with pytest.raises(OSError):
        status_kb(gone)
    assert rss_kb(os.getpid()) > 1000 and rss_kb(os.getpid(), "VmHWM") >= rss_kb(os.getpid())
