"""Wear alarms: what the change detector found, as ``DIR/alarms.json``.

``alarms.json`` is a JSON list of :class:`Alarm` objects: ``axis``, ``parameter``, ``onset`` (ISO 8601,
UTC: the start of the first window of the change), ``change_pct`` (the latest level against the
axis's baseline), ``sigma_pct`` (the σ of that change) and ``evidence`` (the detector's figures: the
method, the baseline and its windows, the reference value k and decision interval h in σ units, when
the CUSUM crossed h, its peak, and the z of the windows from the onset on). An empty list is a fleet
with no alarm.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

from ..model.files import write_atomic
from .errors import FleetError
from .trend import Detection

ALARMS_FILE = "alarms.json"
METHOD = "two-sided CUSUM in units of σ against the axis's first windows"


def iso_utc(stamp_ns: int) -> str:
    """``2026-01-14T00:00:00Z`` (whole seconds; the stamp's sub-second part is dropped)."""
    return datetime.fromtimestamp(stamp_ns // 1_000_000_000, UTC).strftime("%Y-%m-%dT%H:%M:%SZ")


@dataclass(frozen=True)
class Alarm:
    axis: str
    parameter: str
    onset: str
    change_pct: float
    sigma_pct: float
    evidence: dict[str, Any]

    def to_json(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> Alarm:
        return cls(**data)


def alarm_of(d: Detection, false_alarm: float, watched: int) -> Alarm | None:
    """The alarm of a detection (None: it raised none)."""
    if d.alarm is None or d.onset is None:
        return None
    s = d.series
    after = range(d.onset, len(s))
    peak = d.cusum_up if d.direction > 0 else d.cusum_down
    return Alarm(
        axis=s.axis,
        parameter=s.parameter,
        onset=iso_utc(int(s.start_ns[d.onset])),
        change_pct=round(d.change_pct, 4),
        sigma_pct=round(d.sigma_pct, 4),
        evidence={
            "method": METHOD,
            "direction": "up" if d.direction > 0 else "down",
            "baseline": d.baseline,
            "baseline_windows": d.baseline_windows,
            "baseline_from": iso_utc(int(s.start_ns[0])),
            "baseline_to": iso_utc(int(s.end_ns[d.baseline_windows - 1])),
            "extra_scatter": d.extra_scatter,
            "k_sigma": d.k,
            "h_sigma": d.h,
            "alarm_window": iso_utc(int(s.start_ns[d.alarm])),
            "cusum_peak_sigma": float(np.max(peak)),
            "windows_since_onset": len(after),
            "z_since_onset": [round(float(d.z[i]), 2) for i in after],
            "false_alarm_budget": false_alarm,
            "watched_windows": watched,
        },
    )


def write_alarms(folder: Path, alarms: list[Alarm]) -> Path:
    path = folder / ALARMS_FILE
    write_atomic(path, json.dumps([a.to_json() for a in alarms], indent=1) + "\n")
    return path


def read_alarms(path: str | Path) -> list[Alarm]:
    try:
        data = json.loads(Path(path).read_text("utf-8"))
    except (OSError, ValueError) as exc:
        raise FleetError(f"{path} cannot be read as alarms: {exc}") from None
    if not isinstance(data, list):
        raise FleetError(f"{path} is not a list of alarms")
    return [Alarm.from_json(a) for a in data]
