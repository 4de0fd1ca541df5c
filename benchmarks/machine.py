"""The machine reference: a short fixed workload measured in every benchmark's run, so that a time can be
read as a multiple of it and compared across machines (machines of one kind differ several-fold).

The workload is fixed code on fixed data, about half a second in all: pure Python (integer arithmetic,
a dict and a list of tuples, string formatting: what an interpreter spends its time on) and numpy
(matrix products, a sort and an FFT on a seeded array: memory and vectorised floating point), each run
:data:`ROUNDS` times; the reference is the sum of the fastest round of each part (the least disturbed
by whatever else runs on the machine). ``bench NAME`` measures it before the benchmark, prints it on
stderr and adds it to ``--json`` output as ``machine_reference``; ``bench all`` prints it at the top
of its table and every time beside it as a multiple of it (docs/performance.md).
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

ROUNDS = 3
_PY_N = 180_000
_NP_SIZE = 96
"""small matrices: a product this size runs on one thread (BLAS's threads would measure the load)"""
_NP_N = 400_000


@dataclass(frozen=True)
class MachineReference:
    """The reference workload's time on this machine, now [s]."""

    python_s: float
    """the pure-Python part, its fastest round"""
    numpy_s: float
    """the numpy part, its fastest round"""

    @property
    def seconds(self) -> float:
        """the reference: both parts"""
        return self.python_s + self.numpy_s

    def multiple(self, seconds: float) -> float:
        """``seconds`` as a multiple of the reference"""
        return seconds / self.seconds

    def describe(self) -> str:
        return (
            f"machine reference {self.seconds * 1e3:.0f} ms (Python {self.python_s * 1e3:.0f} ms + numpy "
            f"{self.numpy_s * 1e3:.0f} ms, fastest of {ROUNDS} rounds)"
        )

    def to_dict(self) -> dict[str, float]:
        return {"seconds": self.seconds, "python_s": self.python_s, "numpy_s": self.numpy_s}


def _python_work() -> int:
    table: dict[int, int] = {}
    rows = []
    total = 0
    for i in range(_PY_N):
        total = (total * 31 + i * i) % 1_000_003
        table[i % 977] = table.get(i % 977, 0) + total
        if i % 8 == 0:
            rows.append((f"{i:05d}", total))
    rows.sort(key=lambda row: row[1])
    return total + len(table) + len(rows[0][0])


def _numpy_work(rng: np.random.Generator) -> float:
    a = rng.standard_normal((_NP_SIZE, _NP_SIZE))
    b = a
    for _ in range(20):
        b = np.tanh(b @ a / _NP_SIZE)
    x = rng.standard_normal(_NP_N)
    spectrum = np.abs(np.fft.rfft(x))
    smooth = np.cumsum(np.exp(-np.abs(x)) * np.sin(x))
    return float(b.sum() + np.sort(x)[_NP_N // 2] + spectrum.max() + smooth[-1])


def machine_reference() -> MachineReference:
    """Measure the reference now (about half a second)."""
    python_s = numpy_s = float("inf")
    for _ in range(ROUNDS):
        t0 = time.perf_counter()
        _python_work()
        t1 = time.perf_counter()
        _numpy_work(np.random.default_rng(20240613))
        t2 = time.perf_counter()
        python_s, numpy_s = min(python_s, t1 - t0), min(numpy_s, t2 - t1)
    return MachineReference(python_s, numpy_s)


def run_with_reference(run: Callable[[argparse.Namespace], int], args: argparse.Namespace) -> int:
    """Run a benchmark's ``run(args)`` with the machine reference measured first, in the same process:
    with ``--json`` its object gains ``machine_reference``; otherwise the reference follows its table,
    so that each time in it can be read as a multiple of it."""
    reference = machine_reference()
    if not getattr(args, "json", False):
        code = run(args)
        print(f"{reference.describe()}: a time above divided by {reference.seconds:.3f} s compares across "
              "machines")  # fmt: skip
        return code
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = run(args)
    text = out.getvalue()
    try:
        result = json.loads(text)
    except json.JSONDecodeError:  # not one object (a failed run's message): as it was
        sys.stdout.write(text)
        return code
    if isinstance(result, dict):
        result.setdefault("machine_reference", reference.to_dict())
    print(json.dumps(result, indent=1))
    return code
