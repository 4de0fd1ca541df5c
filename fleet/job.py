"""The Dask job: windows identified on Dask distributed, a task per window, results into the fits table.

The job runs on a client of :func:`~.cluster.fleet_client` (a LocalCluster of worker processes on
127.0.0.1, or a running scheduler). :func:`identify_windows` plans each axis's calibration
(:mod:`.axis_calibration`: its first windows pooled) and keys every window with it, then submits one
task per window not yet in the fits table: the task carries the window's description (paths and
hashes, a few hundred bytes) and its axis's calibration — the record from
``DIR/calibrations.parquet``, or the future of a calibration task submitted first, on which Dask
makes the window wait — the worker reads the logs and returns a row
(:func:`~.window_fit.fit_window_row`). Rows are gathered
as they complete, the progress is reported, and the table is written (atomically) every
:data:`SAVE_EVERY_S` and at the end, so an interrupted run keeps what it finished. A task whose worker
died is a ``failed`` row. With nothing new to do, :func:`identify_fleet` starts no cluster.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .axis_calibration import (
    CALIBRATIONS_FILE,
    AxisCalibration,
    calibrate_axis,
    calibrated_windows,
    read_calibrations,
    write_calibrations,
)
from .catalog import read_catalog
from .cluster import CONNECT_TIMEOUT_S, DEFAULT_WORKERS, fleet_client
from .fits import FAILED, FITS_FILE, FitRow, read_fits, write_fits
from .window_fit import FitSettings, WindowResult, empty_row, fit_window_row
from .windows import Window, WindowSpec, plan_windows

SAVE_EVERY_S = 30.0
"""how often a running job writes the rows it has [s]"""


@dataclass(frozen=True)
class Progress:
    """How far a job is: windows done of all to do, by status, the time since it started, and the
    axes whose calibration is still running (their windows wait for it)."""

    done: int
    total: int
    by_status: dict[str, int]
    elapsed_s: float
    calibrating: int = 0

    def line(self) -> str:
        counts = ", ".join(f"{n} {s.replace('_', ' ')}" for s, n in sorted(self.by_status.items()))
        left = ""
        if self.calibrating:  # the windows done so far do not tell the rate yet
            left = f", {self.calibrating} axes still calibrating"
        elif 0 < self.done < self.total:
            left = f", ~{self.elapsed_s / self.done * (self.total - self.done):.0f} s left"
        return f"{self.done}/{self.total} windows ({counts}) in {self.elapsed_s:.0f} s{left}"


@dataclass(frozen=True)
class JobResult:
    """What :func:`identify_windows` did: the new rows, the rows kept from before, the timing."""

    new: tuple[FitRow, ...]
    kept: int
    """windows already in the fits table (same key), not done again"""
    windows: int
    wall_s: float
    peak_rss_mb: dict[str, float]
    """the largest peak RSS each worker reported [MB]"""
    path: Path

    @property
    def rows(self) -> int:
        return self.kept + len(self.new)


def pending(windows: Sequence[Window], folder: Path, redo: bool = False) -> tuple[list[FitRow], list[Window]]:
    """(the rows of ``folder``'s fits table that belong to ``windows``, the windows without a row);
    the windows keyed with their calibrations (:func:`~.axis_calibration.calibrated_windows`)."""
    previous = [] if redo else read_fits(folder, missing_ok=True)
    keys = {w.key for w in windows}
    done_keys = {r.key for r in previous}
    return [r for r in previous if r.key in keys], [w for w in windows if w.key not in done_keys]


def identify_windows(
    client: Any,
    windows: Sequence[Window],
    settings: FitSettings,
    folder: Path,
    progress: Callable[[Progress], None] | None = None,
    redo: bool = False,
) -> JobResult:
    """Identify the ``windows`` (of :func:`~.windows.plan_windows`) not yet in ``folder/fits.parquet``
    on ``client``'s cluster (see the module docstring); ``redo`` identifies all of them again, and
    calibrates every axis again."""
    from distributed import as_completed

    t0 = time.perf_counter()
    windows, plans = calibrated_windows(windows, settings)
    kept, todo = pending(windows, folder, redo)
    known = {} if redo else {c.key: c for c in read_calibrations(folder, missing_ok=True)}
    calibrations: dict[str, Any] = {}
    for axis in sorted({w.axis for w in todo} & plans.keys()):
        plan = plans[axis]
        calibrations[axis] = known.get(plan.key) or client.submit(
            calibrate_axis, plan, settings, key=f"fleet-calibration-{plan.key}", pure=False
        )
    new: list[FitRow] = []
    rss: dict[str, float] = {}
    by_status: dict[str, int] = {}
    futures = {
        client.submit(
            fit_window_row, w, settings, calibrations.get(w.axis), key=f"fleet-window-{w.key}", pure=False
        ): w
        for w in todo
    }
    saved = time.perf_counter()
    for future in as_completed(futures):
        window = futures[future]
        try:
            result: WindowResult = future.result()
            row = result.row
            rss[row.worker] = max(rss.get(row.worker, 0.0), result.peak_rss_mb)
        except Exception as exc:
            row = empty_row(window, FAILED, f"the task failed: {type(exc).__name__}: {exc}", 0.0)
        new.append(row)
        by_status[row.status] = by_status.get(row.status, 0) + 1
        if progress is not None:
            running = sum(not isinstance(c, AxisCalibration) and not c.done() for c in calibrations.values())
            progress(Progress(len(new), len(todo), dict(by_status), time.perf_counter() - t0, running))
        if time.perf_counter() - saved > SAVE_EVERY_S:
            write_fits(folder, [*kept, *new])
            saved = time.perf_counter()
    path = write_fits(folder, [*kept, *new])
    _keep_calibrations(folder, plans, known, calibrations)
    return JobResult(tuple(new), len(kept), len(windows), time.perf_counter() - t0, rss, path)


def _keep_calibrations(
    folder: Path, plans: dict[str, Any], known: dict[str, AxisCalibration], used: dict[str, Any]
) -> None:
    """``folder/calibrations.parquet`` with the calibrations the windows are keyed with: those this
    run made (a calibration task that died is left out: the next run makes it again) and those kept."""
    current = {plan.key for plan in plans.values()}
    records = {c.key: c for c in known.values() if c.key in current}
    for value in used.values():
        if isinstance(value, AxisCalibration):
            continue
        try:
            record = value.result()
        except Exception:
            continue
        records[record.key] = record
    if records or (folder / CALIBRATIONS_FILE).exists():
        write_calibrations(folder, list(records.values()))


def identify_fleet(
    catalog: str | Path,
    windows: WindowSpec,
    settings: FitSettings,
    workers: int = DEFAULT_WORKERS,
    scheduler: str | None = None,
    progress: Callable[[Progress], None] | None = None,
    redo: bool = False,
    timeout_s: float = CONNECT_TIMEOUT_S,
) -> JobResult:
    """``fleet identify``: the catalog's windows (:func:`~.windows.plan_windows`) identified on a
    LocalCluster of ``workers`` or on ``scheduler``, into ``catalog/fits.parquet``."""
    t0 = time.perf_counter()
    folder = Path(catalog)
    entries = read_catalog(folder)
    planned = plan_windows(entries, windows, settings.method())
    kept, todo = pending(calibrated_windows(planned, settings)[0], folder, redo)
    if not todo:  # nothing new: no cluster to start, and the table is only rewritten if it shrinks
        path = folder / FITS_FILE
        if len(kept) != len(read_fits(folder, missing_ok=True)):
            write_fits(folder, kept)
        return JobResult((), len(kept), len(planned), time.perf_counter() - t0, {}, path)
    with fleet_client(workers, scheduler, timeout_s) as client:
        return identify_windows(client, planned, settings, folder, progress, redo)
