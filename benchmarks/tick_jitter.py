"""Tick jitter: how late the bridge's 1 kHz ticks start, beside the floor of this machine, quiet and with
two busy loops beside it.

**The floor** is a minimal C loop that sleeps to absolute 1 ms deadlines (``clock_nanosleep`` with
``TIMER_ABSTIME`` on ``CLOCK_MONOTONIC``) and notes how late it woke: what any program gets from this
kernel and this (virtual) machine at that moment. It is compiled with the machine's C compiler at
bench time into a temporary folder; without a compiler the floor is skipped, and the table says why.

**The bridge** is ``axisflow bridge --sim --speed 1`` alone (no subscriber): its report's tick
lateness (tick start − its deadline) and its ticks late by more than a period.

Each is run as an ordinary process and, where this system allows ``SCHED_FIFO``, at real-time
priority (the floor: the whole process; the bridge: ``--rt-priority``, its ticking thread alone);
every pair (floor, bridge) runs on the machine as found (quiet, unless other work loads it: the load
average is in the table) and then beside two ``python3 -c "while True: pass"`` loops of its own, one
pinned to each core, started for the pair and stopped after it. The ratio is the bridge's p99
lateness over the floor's, in the same scheduling class and the same condition.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

CLI = [sys.executable, "-c", "import sys; from axisflow.cli import main; sys.exit(main())"]
RT_PRIORITY = 50
"""the SCHED_FIFO priority of the real-time rows (below the kernel's threaded interrupts at 50…)"""
PERIOD_NS = 1_000_000
BUSY_LOOP = "while True: pass"
_HISTOGRAM_END_US = 100_000.0
"""the bridge's lateness histogram's last bin (acquisition/histogram.py)"""

FLOOR_SOURCE = r"""
#define _GNU_SOURCE
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

/* floor TICKS: sleep to absolute 1 ms deadlines, print how late each wake-up was [ns] */
int main(int argc, char **argv) {
    long ticks = argc > 1 ? atol(argv[1]) : 1000;
    const long long period = 1000000LL;
    long long *late = malloc(sizeof(long long) * (size_t)ticks);
    struct timespec now;
    if (late == NULL) return 1;
    clock_gettime(CLOCK_MONOTONIC, &now);
    long long start = now.tv_sec * 1000000000LL + now.tv_nsec + period;
    for (long k = 0; k < ticks; k++) {
        long long deadline = start + k * period;
        struct timespec due = {deadline / 1000000000LL, deadline % 1000000000LL};
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &due, NULL) != 0) {}
        clock_gettime(CLOCK_MONOTONIC, &now);
        late[k] = now.tv_sec * 1000000000LL + now.tv_nsec - deadline;
    }
    for (long k = 0; k < ticks; k++) printf("%lld\n", late[k]);
    free(late);
    return 0;
}
"""


@dataclass(frozen=True)
class Lateness:
    """How late the ticks of one run started [µs]; ``late``: by more than a period."""

    ticks: int
    p50_us: float
    p99_us: float
    max_us: float
    late: int

    @classmethod
    def of_ns(cls, late_ns: np.ndarray) -> Lateness:
        us = np.maximum(late_ns, 0) / 1e3
        return cls(int(us.size), *(float(np.percentile(us, q)) for q in (50, 99)), float(us.max()),
                   int(np.sum(late_ns > PERIOD_NS)))  # fmt: skip


def compile_floor(folder: Path) -> Path | str:
    """The floor's executable, built in ``folder``; or why it could not be (no compiler, a failed build)."""
    compiler = shutil.which("cc") or shutil.which("gcc") or shutil.which("clang")
    if compiler is None:
        return "no C compiler (cc, gcc, clang) on this machine"
    source, binary = folder / "floor.c", folder / "floor"
    source.write_text(FLOOR_SOURCE)
    built = subprocess.run([compiler, "-O2", "-o", str(binary), str(source)], capture_output=True, text=True)
    if built.returncode != 0:
        return f"{compiler} could not build the floor: {built.stderr.strip()[-300:]}"
    return binary


def rt_allowed() -> bool:
    """Whether a process may run as SCHED_FIFO at :data:`RT_PRIORITY` here."""
    from axisflow.acquisition.bridge.tick_clock import fifo_allowed

    return fifo_allowed(RT_PRIORITY)


def _fifo() -> None:  # preexec_fn of a real-time floor
    os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(RT_PRIORITY))


def run_floor(binary: Path, seconds: float, rt: bool) -> Lateness:
    ticks = round(seconds * 1e9 / PERIOD_NS)
    done = subprocess.run([str(binary), str(ticks)], capture_output=True, text=True, check=True,
                          preexec_fn=_fifo if rt else None, timeout=seconds * 10 + 30)  # fmt: skip
    return Lateness.of_ns(np.array(done.stdout.split(), dtype=np.int64))


def run_bridge(seconds: float, rt: bool) -> Lateness:
    args = [*CLI, "bridge", "--sim", "--speed", "1", "--duration", f"{seconds:g}", "--listen",
            "tcp/127.0.0.1:0", "--json"] + (["--rt-priority", str(RT_PRIORITY)] if rt else [])  # fmt: skip
    done = subprocess.run(args, capture_output=True, text=True, timeout=seconds * 10 + 60,
                          env={**os.environ, "RUST_LOG": "error"})  # fmt: skip
    if done.returncode != 0:
        raise RuntimeError(f"bridge failed: {done.stderr.strip()[-500:]}")
    report = json.loads(done.stdout)
    t = report["tick_lateness"]
    return Lateness(t["count"], t["p50_us"], t["p99_us"], t["max_us"], report["late_ticks"])


@contextmanager
def busy_loops(n: int) -> Iterator[list[int]]:
    """``n`` Python busy loops, loop i pinned to core i mod the cores there are, for the block (it gets
    their process ids)."""
    cores = sorted(os.sched_getaffinity(0))
    loops = []
    try:
        for i in range(n):
            core = cores[i % len(cores)]
            pin = lambda c=core: os.sched_setaffinity(0, {c})  # noqa: E731
            loops.append(subprocess.Popen([sys.executable, "-c", BUSY_LOOP], preexec_fn=pin))
        yield [loop.pid for loop in loops]
    finally:
        for loop in loops:
            loop.kill()
            loop.wait()


@dataclass(frozen=True)
class JitterRow:
    condition: str
    """``as found`` or ``+ two busy loops``"""
    scheduling: str
    """``ordinary`` or ``SCHED_FIFO 50``"""
    floor: Lateness | None
    bridge: Lateness
    load_average: float
    """the 1-minute load average after the pair"""

    @property
    def ratio(self) -> float:
        """the bridge's p99 lateness over the floor's (nan without a floor)"""
        if self.floor is None or self.floor.p99_us <= 0:
            return float("nan")
        return self.bridge.p99_us / self.floor.p99_us


def measure(seconds: float, progress: Callable[[str], None]) -> dict[str, object]:
    """Every pair (floor, bridge), ordinary and real-time where allowed, as found and with two busy loops."""
    rows: list[JitterRow] = []
    with tempfile.TemporaryDirectory(prefix="axisflow-tick-floor-") as tmp:
        floor = compile_floor(Path(tmp))
        schedulings = [False, True] if rt_allowed() else [False]
        for condition, loops in (("as found", 0), ("+ two busy loops", 2)):
            with busy_loops(loops):
                for rt in schedulings:
                    name = f"SCHED_FIFO {RT_PRIORITY}" if rt else "ordinary"
                    progress(f"tick jitter, {condition}, {name}: the floor, then the bridge ({seconds:g} s)")
                    floor_lateness = run_floor(floor, seconds, rt) if isinstance(floor, Path) else None
                    bridge = run_bridge(seconds, rt)
                    rows.append(JitterRow(condition, name, floor_lateness, bridge, os.getloadavg()[0]))
    return {
        "seconds": seconds,
        "floor_skipped": None if isinstance(floor, Path) else floor,
        "real_time_skipped": (
            None if len(schedulings) == 2 else f"SCHED_FIFO {RT_PRIORITY} is not allowed here"
        ),
        "rows": [{**asdict(r), "ratio": r.ratio} for r in rows],
    }


def table(result: dict[str, object]) -> str:
    """The jitter table: per condition and scheduling, the floor's and the bridge's lateness."""
    lines = [
        f"tick jitter, {result['seconds']:g} s of 1 kHz ticks each: lateness = tick start − its deadline",
        f"{'condition':<18}{'scheduling':<15}{'':<8}{'p50 µs':>9}{'p99 µs':>9}{'max µs':>10}{'late>1ms':>10}"
        f"{'p99 ratio':>11}{'load':>7}",
    ]
    for row in result["rows"]:  # type: ignore[attr-defined]
        for what in ("floor", "bridge"):
            t = row[what]
            if t is None:
                cells = f"{'-':>9}{'-':>9}{'-':>10}{'-':>10}"
            else:  # (the bridge's histogram ends at 100 ms: a p99 there is "at least")
                capped = what == "bridge" and t["p99_us"] >= _HISTOGRAM_END_US
                p99 = f"≥{_HISTOGRAM_END_US:.0f}" if capped else f"{t['p99_us']:.0f}"
                cells = f"{t['p50_us']:>9.0f}{p99:>9}{t['max_us']:>10.0f}{t['late']:>10}"
            ratio = f"{row['ratio']:>11.2f}" if what == "bridge" else f"{'':>11}"
            lines.append(f"{row['condition']:<18}{row['scheduling']:<15}{what:<8}{cells}{ratio}"
                         f"{row['load_average']:>7.1f}")  # fmt: skip
    for key in ("floor_skipped", "real_time_skipped"):
        if result.get(key):
            lines.append(f"  ({key.replace('_', ' ')}: {result[key]})")
    return "\n".join(lines)
