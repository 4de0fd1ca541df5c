"""The tick-jitter benchmark's parts: the floor (a C loop built with this machine's compiler), the
lateness figures, the ratio, and busy loops that end with their block."""

import os
import shutil
from pathlib import Path

import numpy as np
import pytest
from axisflow.benchmarks.tick_jitter import JitterRow, Lateness, busy_loops, compile_floor, run_floor


def test_lateness_figures_from_the_nanoseconds():
    late = Lateness.of_ns(np.array([-5, 1_000, 2_000, 1_500_000, 3_000] + [1_000] * 95, dtype=np.int64))
    assert (late.ticks, late.p50_us, late.max_us, late.late) == (100, 1.0, 1500.0, 1)
    row = JitterRow(
        "as found", "ordinary", Lateness(10, 1.0, 50.0, 60.0, 0), Lateness(10, 2.0, 100.0, 9.0, 0), 1.0
    )
    assert row.ratio == 2.0
    assert np.isnan(JitterRow("as found", "ordinary", None, row.bridge, 1.0).ratio)


@pytest.mark.skipif(not (shutil.which("cc") or shutil.which("gcc")), reason="no C compiler")
def test_the_floor_is_built_here_and_sleeps_to_absolute_deadlines(tmp_path):
    binary = compile_floor(tmp_path)
    assert not isinstance(binary, str), binary
    late = run_floor(binary, 0.05, rt=False)
    assert late.ticks == 50 and 0.0 <= late.p50_us <= late.p99_us <= late.max_us


def _running(pid: int) -> bool:
    try:
        return Path(f"/proc/{pid}/stat").read_text().split(")")[1].split()[0] in "RS"
    except FileNotFoundError:
        return False


def test_busy_loops_run_for_the_block_on_their_cores_and_end_with_it():
    with busy_loops(2) as pids:
        assert len(pids) == 2 and all(_running(pid) for pid in pids)
        cores = sorted(os.sched_getaffinity(0))
        assert [os.sched_getaffinity(pid) for pid in pids] == [{cores[0]}, {cores[1 % len(cores)]}]
    assert not any(_running(pid) for pid in pids)
