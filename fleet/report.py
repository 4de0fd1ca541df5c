"""The fleet's report: ``trend.md`` with a figure per trended parameter (PNG), and a rerun recording
of every axis's trends on one timeline (``trend.rrd``).

Each figure has a panel per axis: the parameter's value per window with its ±σ band, the baseline
level of the watched parameters, and the onset of an alarm (a vertical line). The rerun recording
holds, per axis and parameter, ``fleet/<axis>/<parameter>/value`` and its ``upper`` and ``lower``
(±σ) as scalar series on the timeline ``window`` (each window's start, integer nanoseconds), and the
alarms as text entries at their onsets; written headless (``rr.save``) and renamed into place.
"""

from __future__ import annotations

import io
import math
import uuid
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path

import numpy as np

from ..model.files import atomic_path, write_atomic_files
from .alarms import Alarm, iso_utc
from .fits import FitRow
from .trend import TRENDED, Detection, Series

TREND_FILE = "trend.md"
RRD_FILE = "trend.rrd"
FIGURE_NAME = "trend_{parameter}.png"
APPLICATION_ID = "axisflow_fleet"
TIMELINE = "window"
PANELS_PER_ROW = 4


@dataclass(frozen=True)
class TrendInputs:
    """What the report shows: the fits, the series per parameter and the detections and alarms."""

    rows: tuple[FitRow, ...]
    series: dict[str, list[Series]]
    detections: dict[tuple[str, str], Detection]
    alarms: tuple[Alarm, ...]
    settings_line: str


def figure_png(
    parameter: str, series: Sequence[Series], detections: dict[tuple[str, str], Detection]
) -> bytes:
    """One parameter over time, a panel per axis (see the module docstring)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    title, unit = TRENDED[parameter]
    n = max(len(series), 1)
    cols = min(PANELS_PER_ROW, n)
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 2.4 * rows), squeeze=False, sharex=True)
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    for ax, s in zip(axes.flat, series, strict=False):
        t = np.array([datetime.fromtimestamp(x / 1e9, UTC) for x in s.start_ns])
        ax.plot(t, s.value, ".-", color="C0", lw=1.0, ms=3)
        if np.isfinite(s.std).any():
            ax.fill_between(t, s.value - s.std, s.value + s.std, color="C0", alpha=0.3, lw=0)
        d = detections.get((s.axis, parameter))
        if d is not None:
            ax.axhline(d.baseline, color="0.4", lw=0.8, ls="--")
            if d.onset is not None:
                ax.axvline(t[d.onset], color="C3", lw=1.2)
        ax.set_title(s.axis + (" — alarm" if d is not None and d.onset is not None else ""), fontsize=9)
        ax.tick_params(labelsize=7)
        ax.set_ylabel(unit, fontsize=8)
        for label in ax.get_xticklabels():
            label.set_rotation(30)
    fig.suptitle(f"{title} per window (±σ band; dashed: baseline; red: alarm onset)", fontsize=10)
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=90)
    plt.close(fig)
    return buffer.getvalue()


def write_rrd(path: Path, series: dict[str, list[Series]], alarms: Sequence[Alarm]) -> Path:
    """The trends as a rerun recording (see the module docstring)."""
    import rerun as rr

    rec = rr.RecordingStream(APPLICATION_ID, recording_id=uuid.uuid4())
    with atomic_path(path) as part:
        rec.save(str(part))
        for parameter, per_axis in series.items():
            title, unit = TRENDED[parameter]
            for s in per_axis:
                if not len(s):
                    continue
                base = f"fleet/{s.axis}/{parameter}"
                stamps = np.ascontiguousarray(s.start_ns, dtype=np.int64).view("datetime64[ns]")
                std = np.where(np.isfinite(s.std), s.std, 0.0)
                for leaf, values, name in (
                    ("value", s.value, f"{title} [{unit}]"),
                    ("upper", s.value + std, "+σ"),
                    ("lower", s.value - std, "−σ"),
                ):
                    rec.log(f"{base}/{leaf}", rr.SeriesLines(names=name), static=True)
                    rec.send_columns(
                        f"{base}/{leaf}",
                        indexes=[rr.TimeColumn(TIMELINE, timestamp=stamps)],
                        columns=rr.Scalars.columns(scalars=np.asarray(values, dtype=np.float64)),
                    )
        for alarm in alarms:
            onset = np.datetime64(alarm.onset.rstrip("Z"), "ns")
            rec.set_time(TIMELINE, timestamp=onset)
            text = f"{alarm.parameter} {alarm.change_pct:+.2f} % ± {alarm.sigma_pct:.2f} % from {alarm.onset}"
            rec.log(f"fleet/{alarm.axis}/alarms", rr.TextLog(text, level=rr.TextLogLevel.WARN))
        rec.flush()
        rec.disconnect()
    return path


def trend_markdown(inputs: TrendInputs, figures: Sequence[str]) -> str:
    """trend.md: the alarms, a table per axis (first and last level, change, status counts), the
    figures."""
    rows = inputs.rows
    axes = sorted({r.axis for r in rows})
    lines = ["# Fleet trend", ""]
    if rows:
        first, last = min(r.window_start_ns for r in rows), max(r.window_end_ns for r in rows)
        lines.append(
            f"{len(axes)} axes, {len(rows)} windows from {iso_utc(first)} to {iso_utc(last)}; "
            f"{inputs.settings_line}."
        )
    lines += ["", "## Alarms", ""]
    if not inputs.alarms:
        lines.append("None: no axis's friction changed beyond the detector's thresholds.")
    else:
        lines += [
            "| axis | parameter | onset (UTC) | change | σ | CUSUM crossed h at |",
            "|---|---|---|---:|---:|---|",
        ]
        for a in inputs.alarms:
            lines.append(
                f"| {a.axis} | {TRENDED[a.parameter][0]} | {a.onset} | {a.change_pct:+.2f} % | "
                f"{a.sigma_pct:.2f} % | {a.evidence['alarm_window']} |"
            )
    lines += ["", "## Axes", ""]
    lines += [
        "| axis | windows ok | too little motion | failed | Coulomb at 0.2 m/s: baseline [N] "
        "| latest [N] | change |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    for axis in axes:
        mine = [r for r in rows if r.axis == axis]
        counts = {s: sum(r.status == s for r in mine) for s in ("ok", "too_little_motion", "failed")}
        d = inputs.detections.get((axis, "coulomb_n"))
        ok = sorted((r for r in mine if r.ok), key=lambda r: r.window_start_ns)
        latest = f"{ok[-1].coulomb_n:.2f} ± {ok[-1].coulomb_std_n:.2f}" if ok else "–"
        base = f"{d.baseline:.2f}" if d is not None else "–"
        change = (
            f"{100.0 * (ok[-1].coulomb_n - d.baseline) / d.baseline:+.2f} %" if d is not None and ok else "–"
        )
        lines.append(
            f"| {axis} | {counts['ok']} | {counts['too_little_motion']} | {counts['failed']} | {base} | "
            f"{latest} | {change} |"
        )
    failed = [r for r in rows if not r.ok]
    if failed:
        lines += ["", "## Windows without a fit", ""]
        for r in sorted(failed, key=lambda r: (r.axis, r.window_start_ns)):
            lines.append(
                f"- {r.axis} {iso_utc(r.window_start_ns)}: {r.status.replace('_', ' ')} — {r.reason}"
            )
    lines += ["", "## Figures", ""]
    for name in figures:
        lines += [f"![{name}]({name})", ""]
    lines.append(f"All axes' trends on one timeline: `rerun {RRD_FILE}`.")
    return "\n".join(lines) + "\n"


def write_report(folder: Path, inputs: TrendInputs) -> list[Path]:
    """trend.md and its figures (together, atomically) and trend.rrd."""
    files: dict[str, str | bytes] = {}
    for parameter, per_axis in inputs.series.items():
        name = FIGURE_NAME.format(parameter=parameter)
        files[name] = figure_png(parameter, per_axis, inputs.detections)
    files[TREND_FILE] = trend_markdown(inputs, list(files))
    write_atomic_files(folder, files)
    rrd = write_rrd(folder / RRD_FILE, inputs.series, inputs.alarms)
    return [folder / name for name in files] + [rrd]
