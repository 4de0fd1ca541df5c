"""The scenarios' memory sampler: a reading after a moment is a sample taken after it."""

import os
import subprocess
import sys
import time

import pytest
from axisflow.benchmarks.fault_scenarios.rig import RssSampler


def test_the_rss_after_a_moment_comes_from_a_sample_taken_after_it():
    with RssSampler(os.getpid(), 0.02) as rss:
        t = time.monotonic()
        mb = rss.after(t)
        first = next((when, value) for when, value in rss.samples if when >= t)
    assert first[1] == mb > 0.0


def test_a_process_that_is_gone_gives_no_reading():
    gone = subprocess.Popen([sys.executable, "-c", "pass"])
    gone.wait()
    with (
        RssSampler(gone.pid, 0.02) as rss,
        pytest.raises(RuntimeError, match=f"no RSS sample of process {gone.pid}"),
    ):
        rss.after(time.monotonic(), timeout_s=0.2)
