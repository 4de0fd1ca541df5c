"""A foreign log's joint in SI units with integer-nanosecond stamps: :func:`joint_samples` applies a
:class:`~.column_map.ColumnMap` to a :class:`~.table.ForeignTable` and checks what a recording needs.

Units go through :func:`axisflow.model.units.signal_unit` (the one table of units). Each refusal is
one line naming the file, the column or row and the value:

* a mapped column the file does not have (the error lists those it has), an unknown unit (the error
  lists the known ones), a column without a unit where the file gives none (time defaults to s);
* columns of different lengths; units of both sides of the transmission in one joint (a position in mm
  and an effort in N·m); an effort in V or A without a scale; a scale variable that is not a scalar;
* **missing values** (NaN, an empty CSV field, inf) in any mapped column: a row with one is dropped,
  and it becomes a lost sample, a hole the refit counts and never fits across — if it is alone. A
  **run** of two or more such rows is refused, naming how many runs there are, where the longest
  starts and how long it is: a stretch of missing data is not something to guess;
* **time** that does not increase (the row and both values, in the file's unit), a stamp before 0 or
  beyond what a ROS 2 time holds (int32 seconds).

Stamps are exact: an integer time column is multiplied by the nanoseconds of its unit, a float column
is rounded to the nanosecond (a float64 holds every nanosecond up to ~10⁶ s from its zero); with a
sample rate instead, row k is at round(k·10⁹/rate) ns. ``time_offset_s`` is added to every stamp.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...model import ParameterError
from ...model.units import SignalUnit, signal_unit
from .column_map import ColumnMap, Signal
from .errors import ForeignLogError
from .table import ForeignTable

NS_PER_S = 1_000_000_000
MAX_STAMP_NS = (2**31) * NS_PER_S - 1
"""the last stamp a ROS 2 ``builtin_interfaces/Time`` holds (int32 seconds)"""


@dataclass(frozen=True, eq=False)
class JointSamples:
    """One joint of a foreign log, ready to record: stamps (int64 ns, increasing) and float64 arrays
    in the SI units of its side (``velocity``/``effort`` None: not in the log)."""

    source: Path
    joint: str
    side: str
    """:data:`~axisflow.model.units.CARRIAGE_SIDE` or :data:`~axisflow.model.units.MOTOR_SIDE`"""
    stamp_ns: np.ndarray
    position: np.ndarray
    velocity: np.ndarray | None
    effort: np.ndarray | None
    dropped: int
    """rows dropped for a missing value (each alone: a hole of one sample)"""
    rows: int
    """rows of the file's data"""
    units: dict[str, str]
    """the unit each signal was read in (time, position, velocity, effort; the effort's with its scale,
    ``V × 35.15``), for the record"""

    def __len__(self) -> int:
        return len(self.stamp_ns)

    @property
    def start_ns(self) -> int:
        return int(self.stamp_ns[0])

    @property
    def end_ns(self) -> int:
        return int(self.stamp_ns[-1])


class _Mapping:
    """The columns and units of one table under one map (the steps of :func:`joint_samples`)."""

    def __init__(self, table: ForeignTable, cmap: ColumnMap) -> None:
        self.table, self.cmap = table, cmap
        self.names: dict[str, str] = {}
        self.values: dict[str, np.ndarray] = {}
        self.units: dict[str, SignalUnit] = {}
        self.scale_note = ""
        """how the effort was scaled, for the record (`` × 35.15``)"""
        signals = {
            "time": cmap.time,
            "position": cmap.position,
            "velocity": cmap.velocity,
            "effort": cmap.effort,
        }
        for what, signal in signals.items():
            if signal is not None:
                self.names[what], self.values[what] = table.column(signal.column, what)
                self.units[what] = self._unit(what, signal)

    def _unit(self, what: str, signal: Signal) -> SignalUnit:
        name = signal.unit or self.table.units.get(self.names[what]) or ("s" if what == "time" else None)
        if name is None:
            raise ForeignLogError(
                f"{self.table.path}: {what} column {self.names[what]!r} has no unit in the file: "
                "give its unit"
            )
        try:
            return signal_unit(what, name, self.cmap.counts_per)
        except ParameterError as exc:
            raise ForeignLogError(f"{self.table.path}: {exc}") from None

    def check_lengths(self) -> int:
        lengths = {what: len(v) for what, v in self.values.items()}
        if len(set(lengths.values())) > 1:
            shown = ", ".join(f"{what} {self.names[what]!r} {n}" for what, n in lengths.items())
            raise ForeignLogError(
                f"{self.table.path}: the mapped columns differ in length ({shown} values): a log needs one "
                "value of each per sample"
            )
        n = lengths["position"]
        if n == 0:
            raise ForeignLogError(f"{self.table.path} holds no samples")
        return n

    def side(self) -> str:
        sides = {what: u.side for what, u in self.units.items() if u.side is not None}
        if len(set(sides.values())) > 1:
            shown = " but ".join(
                f"{what} in {self.units[what].name} is on the {side} side" for what, side in sides.items()
            )
            raise ForeignLogError(
                f"{self.table.path}: {shown}: one joint measures one side of the transmission"
            )
        return sides["position"]

    def effort_si(self, side: str) -> np.ndarray | None:
        if "effort" not in self.values:
            return None
        unit, scale = self.units["effort"], self.cmap.effort_scale
        if isinstance(scale, str):
            scale = self.table.scalar(scale, "effort scale")
            if not (np.isfinite(scale) and scale != 0.0):
                raise ForeignLogError(
                    f"{self.table.path}: effort scale {self.cmap.effort_scale} = {scale} must be "
                    "finite and not 0"
                )
        if unit.needs_scale and scale is None:
            per = "N" if side == "carriage" else "N·m"
            raise ForeignLogError(
                f"{self.table.path}: effort {self.names['effort']!r} in {unit.name} is not a force: give a "
                f"scale ({per} per {unit.name}, a number or a scalar of the file)"
            )
        if scale is not None:
            self.scale_note = f" × {float(scale):g}"
        return self.values["effort"].astype(np.float64) * (
            unit.si_per_unit * (1.0 if scale is None else float(scale))
        )


def joint_samples(table: ForeignTable, cmap: ColumnMap) -> JointSamples:
    """The joint ``cmap`` maps in ``table`` (see the module docstring)."""
    m = _Mapping(table, cmap)
    n = m.check_lengths()
    side = m.side()
    effort = m.effort_si(side)
    position = m.values["position"].astype(np.float64) * m.units["position"].si_per_unit
    velocity = None
    if "velocity" in m.values:
        velocity = m.values["velocity"].astype(np.float64) * m.units["velocity"].si_per_unit
    stamps = _stamps(m, n)
    keep = _holes(m, n)
    stamps = stamps[keep]
    _check_time(m, stamps, np.flatnonzero(keep))
    return JointSamples(
        source=table.path,
        joint=cmap.joint or side,
        side=side,
        stamp_ns=stamps,
        position=position[keep],
        velocity=None if velocity is None else velocity[keep],
        effort=None if effort is None else effort[keep],
        dropped=int(n - np.count_nonzero(keep)),
        rows=n,
        units={what: u.name + (m.scale_note if what == "effort" else "") for what, u in m.units.items()},
    )


def _stamps(m: _Mapping, n: int) -> np.ndarray:
    """Each row's stamp [ns] (rows with a missing time get 0: they are dropped)."""
    offset_ns = round(m.cmap.time_offset_s * NS_PER_S)
    if m.cmap.rate_hz is not None:
        return np.rint(np.arange(n) * (NS_PER_S / m.cmap.rate_hz)).astype(np.int64) + offset_ns
    t = m.values["time"]
    ns_per_unit = m.units["time"].si_per_unit * NS_PER_S
    if t.dtype.kind == "i":
        return t * round(ns_per_unit) + offset_ns
    finite = np.isfinite(t)
    stamps = np.zeros(n, dtype=np.int64)
    scaled = t[finite] * ns_per_unit
    if scaled.size and np.abs(scaled).max() > 2.0**62:
        raise ForeignLogError(
            f"{m.table.path}: time {m.names['time']!r} reaches {t[finite].max():g} "
            f"{m.units['time'].name}: beyond any stamp"
        )
    stamps[finite] = np.rint(scaled).astype(np.int64)
    return stamps + offset_ns


def _holes(m: _Mapping, n: int) -> np.ndarray:
    """Which rows to keep: those without a missing value; an error for a run of two or more."""
    missing = np.zeros(n, dtype=bool)
    for values in m.values.values():
        if values.dtype.kind == "f":
            missing |= ~np.isfinite(values)
    if not missing.any():
        return ~missing
    edges = np.diff(np.concatenate(([0], missing.astype(np.int8), [0])))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    lengths = ends - starts
    long = lengths >= 2
    if long.any():
        k = int(np.argmax(lengths))
        first, size = int(starts[k]), int(lengths[k])
        empty = [
            m.names[what] for what, v in m.values.items() if v.dtype.kind == "f" and not np.isfinite(v[first])
        ]
        raise ForeignLogError(
            f"{m.table.path}: {int(long.sum())} run(s) of 2 or more rows with missing values (NaN or empty), "
            f"the longest {size} rows from {m.table.row_name(first)} (in {', '.join(empty)}): a missing "
            "value alone is dropped as a lost sample, a run is not guessed: cut the log or fill it"
        )
    return ~missing


def _check_time(m: _Mapping, stamps: np.ndarray, rows: np.ndarray) -> None:
    """Stamps increase, start at 0 or later and fit a ROS 2 time; else an error naming the row."""
    path = m.table.path
    time = m.values.get("time")

    def shown(i: int) -> str:  # the file's own value (a stamp [s] for a log without time)
        if time is None:
            return f"{stamps[i] / NS_PER_S:.9g} s"
        return f"{time[rows[i]]:.12g} {m.units['time'].name}"

    steps = np.diff(stamps)
    if steps.size and (steps <= 0).any():
        i = int(np.argmax(steps <= 0)) + 1
        what = "goes back" if steps[i - 1] < 0 else "repeats"
        raise ForeignLogError(
            f"{path}: time {what} at {m.table.row_name(int(rows[i]))}: {shown(i)} after {shown(i - 1)} at "
            f"{m.table.row_name(int(rows[i - 1]))}; time must increase"
        )
    if stamps[0] < 0:
        raise ForeignLogError(
            f"{path}: time starts at {shown(0)} ({m.table.row_name(int(rows[0]))}), before 0: a recording's "
            "stamps start at 0 or later; give a time offset"
        )
    if stamps[-1] > MAX_STAMP_NS:
        raise ForeignLogError(
            f"{path}: time reaches {shown(len(stamps) - 1)}, beyond 2^31 s (the last ROS 2 time stamp)"
        )
