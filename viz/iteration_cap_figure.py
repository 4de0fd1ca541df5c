"""The paper's Fig. 4b: what IPOPT's iteration cap does to the optimal time and to the solve time.

One move, d = 0.4 m (0.2 → 0.6 m) along poly5, in both cases (minimum time; minimum time-energy with
ω = 0.9), solved by the IPOPT back-end (:class:`~axisflow.planner.ipopt_backend.IpoptSettings`
``max_iter`` = 1 … 15, the paper used 10) and by the exact back-end (the certified optimum T*, drawn as
a line). Per cap: the duration IPOPT returns, its deviation from T* [%], and its solve time (the
median of :data:`REPEATS` solves of the CasADi call, the NLP built beforehand; the bars span their
minimum and maximum). A filled marker: IPOPT converged; an open one: it stopped at the cap. A converged
IPOPT sits a little above T* in case 1: its limits are tightened by 0.1 % (``limit_margin``).
"""

from __future__ import annotations

import statistics
import time
from dataclasses import dataclass

import numpy as np

from ..model import AxisParams
from ..planner import DEFAULT_OMEGA, Case, MoveProblem, SolveStatus, make_backend, solve_exact
from .png import png_bytes, pyplot

LAW = "poly5"
MOVE_M = (0.2, 0.6)
"""start and end of the move [m]: d = 0.4 m"""
CAPS = tuple(range(1, 16))
REPEATS = 5


@dataclass(frozen=True)
class CapRun:
    """IPOPT at one iteration cap: duration [s], status, iterations used, solve times [s]."""

    cap: int
    duration_s: float
    converged: bool
    iterations: int
    solve_times_s: tuple[float, ...]

    @property
    def solve_time_s(self) -> float:
        return statistics.median(self.solve_times_s)


@dataclass(frozen=True)
class CapStudy:
    """One case: the exact optimum T* [s], its solve time [s], and IPOPT per cap."""

    case: Case
    exact_duration_s: float
    exact_solve_time_s: float
    runs: tuple[CapRun, ...]


def cap_study(params: AxisParams, case: Case, omega: float = DEFAULT_OMEGA) -> CapStudy:
    """The data of one row of the figure."""
    problem = MoveProblem(*MOVE_M, LAW, case, omega)
    exact_times = []
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        exact = solve_exact(problem, params)
        exact_times.append(time.perf_counter() - t0)
    runs = []
    for cap in CAPS:
        backend = make_backend("ipopt", max_iter=cap)
        backend.prepare(problem, params)
        results = [backend.solve(problem, params) for _ in range(REPEATS)]
        last = results[-1]
        runs.append(
            CapRun(
                cap,
                last.duration_s,
                last.status is SolveStatus.CONVERGED,
                last.iterations,
                tuple(r.solve_time_s for r in results),
            )
        )
    return CapStudy(Case(case), exact.duration_s, statistics.median(exact_times), tuple(runs))


def iteration_cap_png(studies: list[CapStudy]) -> bytes:
    """The figure as PNG bytes: one row per case, columns T, deviation from T*, solve time."""
    plt = pyplot()
    fig, axes = plt.subplots(len(studies), 3, figsize=(12, 3.4 * len(studies)), squeeze=False)
    for row, study in zip(axes, studies, strict=True):
        caps = np.array([r.cap for r in study.runs])
        T = np.array([r.duration_s for r in study.runs])
        done = np.array([r.converged for r in study.runs])
        deviation = (T - study.exact_duration_s) / study.exact_duration_s * 100.0
        solve_ms = np.array([r.solve_time_s for r in study.runs]) * 1e3
        lo = solve_ms - np.array([min(r.solve_times_s) for r in study.runs]) * 1e3
        hi = np.array([max(r.solve_times_s) for r in study.runs]) * 1e3 - solve_ms
        name = (
            "minimum time" if study.case is Case.MIN_TIME else f"minimum time-energy, ω = {DEFAULT_OMEGA:g}"
        )
        for ax, values, label in ((row[0], T, "optimal time T [s]"), (row[1], deviation, "(T − T*)/T* [%]")):
            ax.plot(caps, values, color="tab:blue", lw=1)
            ax.plot(caps[done], values[done], "o", color="tab:blue", label="IPOPT, converged")
            ax.plot(
                caps[~done], values[~done], "o", mfc="white", color="tab:blue", label="IPOPT, stopped at cap"
            )
            ax.set_ylabel(label)
        row[0].axhline(
            study.exact_duration_s,
            color="tab:red",
            lw=1.2,
            label=f"exact optimum T* = {study.exact_duration_s:.4f} s",
        )
        row[1].axhline(0.0, color="tab:red", lw=1.2, label="exact optimum")
        row[1].set_yscale("symlog", linthresh=0.01)
        row[2].errorbar(
            caps,
            solve_ms,
            yerr=[lo, hi],
            fmt="o-",
            color="tab:blue",
            ms=4,
            lw=1,
            capsize=2,
            label=f"IPOPT (median of {REPEATS})",
        )
        row[2].axhline(
            study.exact_solve_time_s * 1e3,
            color="tab:red",
            lw=1.2,
            label=f"exact: {study.exact_solve_time_s * 1e3:.3f} ms",
        )
        row[2].set_ylabel("solve time [ms]")
        row[2].set_ylim(bottom=0.0)
        for ax in row:
            ax.set_xlabel("IPOPT iteration cap (max_iter)")
            ax.set_xticks(caps)
            ax.axvline(10, color="0.6", lw=0.8, ls=":")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=7, loc="best")
        row[1].set_title(
            f"{name}: {LAW}, d = {MOVE_M[1] - MOVE_M[0]:g} m ({MOVE_M[0]:g} → {MOVE_M[1]:g} m)", fontsize=10
        )
    fig.suptitle(
        "Fig. 4b — IPOPT's iteration cap against the exact optimum (dotted: the paper's cap, 10)", fontsize=11
    )
    note = (
        "An iterate with T < T* breaks a limit (in case 1, T* is the shortest feasible time); a converged "
        "IPOPT stays above T* in case 1: it tightens the limits by its margin (0.1 %)."
    )
    fig.text(0.01, 0.005, note, fontsize=8)
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    return png_bytes(fig)
