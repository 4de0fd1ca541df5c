"""``fleet trend``: from the fits table to the series, the detections, ``alarms.json`` and the report."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from .alarms import Alarm, alarm_of, write_alarms
from .fits import read_fits
from .report import TrendInputs, write_report
from .trend import TRENDED, WATCHED, Detection, DetectorSettings, detect, series_of, watched_windows


@dataclass(frozen=True)
class TrendResult:
    alarms: tuple[Alarm, ...]
    detections: dict[tuple[str, str], Detection]
    axes: int
    windows: int
    watched: int
    """windows the detector watched (after the baselines), the N of the false alarm budget"""
    files: tuple[Path, ...]


def trend_fleet(catalog: str | Path, settings: DetectorSettings | None = None) -> TrendResult:
    """Read ``catalog``'s fits, run the detector on the watched parameters of every axis, write
    alarms.json, trend.md, its figures and trend.rrd into the catalog folder."""
    s = settings or DetectorSettings()
    folder = Path(catalog)
    rows = read_fits(folder)
    series = {parameter: series_of(rows, parameter) for parameter in TRENDED}
    watched_series = [x for p in WATCHED for x in series[p]]
    watched = watched_windows(watched_series, s)
    detections: dict[tuple[str, str], Detection] = {}
    for x in watched_series:
        d = detect(x, s, watched)
        if d is not None:
            detections[(x.axis, x.parameter)] = d
    alarms = [a for d in detections.values() if (a := alarm_of(d, s.false_alarm, watched)) is not None]
    alarms.sort(key=lambda a: (a.onset, a.axis, a.parameter))
    line = (
        f"detector: CUSUM against the first {s.baseline_windows} windows of each axis, smallest change "
        f"{s.min_change_pct:g} % (or {s.min_shift_sigma:g} σ), at most {s.false_alarm:g} false alarms "
        f"expected over the {watched} windows watched"
    )
    inputs = TrendInputs(tuple(rows), series, detections, tuple(alarms), line)
    paths = [write_alarms(folder, alarms), *write_report(folder, inputs)]
    axes = len({r.axis for r in rows})
    return TrendResult(tuple(alarms), detections, axes, len(rows), watched, tuple(paths))
