"""The measured signals of one joint of a log, in the cart's SI units, checked for what the fit needs.

A ``sensor_msgs/msg/JointState`` joint is read with the fast log reader
(:func:`axisflow.acquisition.logs.reader.read_joint_states`) and converted to the cart's frame with the
axis geometry (r, i_r of the parameter file):

* a **motor** joint (angle [rad], speed [rad/s], torque [N·m]): x = θ·r/i_r, ẋ = ω·r/i_r,
  F = τ·i_r/r; the fit's errors are reported in N·m;
* a **carriage** joint (position [m], velocity [m/s], belt force [N]) is used as it is; errors in N.

Checks, each a one-line :class:`IdentificationError`: the time stamps must increase, by steps within
:data:`GAP_TOLERANCE` of the log's median step (a gap or a jump back names its sample and time);
non-finite values are dropped and counted (an error above :data:`MAX_NONFINITE_FRACTION`); the record
must be long enough and the axis must move.

Holes. A chunk of the log that could not be read (damaged on disk) leaves a hole in the columns
(:attr:`~axisflow.acquisition.logs.reader.JointStateColumns.holes`); its samples are put back as
missing ones (non-finite, at the log's step), so the fit never takes the samples on both sides of a
hole for neighbours: preparation leaves them out with a guard like any non-finite sample. They are
counted apart (``skipped``), not against :data:`MAX_NONFINITE_FRACTION`.

Window. A :class:`TimeWindow` keeps the samples of each log between two times (seconds from an origin:
the log's first sample unless given) and checks only those: a log with a gap or a stretch of no
interest is fitted from the part that matters (``axisflow identify --start S --end S``).

Time base: a drive samples on its own clock, at a fixed period; the stamps a log carries may jitter
around that (a stamp taken when a message was handled, a clock rounded to 256 ns by a float). The
derivatives the fit needs amplify any such jitter (1 µs of stamp noise at 1 kHz is 0.1 % of a step,
and a second difference turns it into acceleration noise), so the samples are placed on the uniform
grid that fits the stamps best (least squares: the drive's period and phase), and the largest
deviation of a stamp from it is reported (``stamp_jitter_s``).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum
from pathlib import Path

import numpy as np

from ..acquisition.logs.reader import Hole, read_joint_states
from ..model import AxisflowError, AxisParams

GAP_TOLERANCE = 0.5
"""a step between stamps may differ from the median step by this fraction"""
MAX_NONFINITE_FRACTION = 0.01
"""more non-finite samples than this fraction of a log is an error, not something to drop"""
MIN_DURATION_S = 2.0
MIN_MOTION_M_S = 1e-3


class IdentificationError(AxisflowError, ValueError):
    """A log or a setting cannot be used for identification (the message names what and why)."""


@dataclass(frozen=True)
class TimeWindow:
    """The samples of a log from ``start_s`` to ``end_s`` (inclusive), in seconds from ``origin_ns``
    (a stamp [ns]; None: each log's first sample). None for a bound: the log's own start or end."""

    start_s: float | None = None
    end_s: float | None = None
    origin_ns: int | None = None

    def __post_init__(self) -> None:
        for name, value in (("start", self.start_s), ("end", self.end_s)):
            if value is not None and not np.isfinite(value):
                raise IdentificationError(f"window {name} = {value} s must be a finite time")
        if self.start_s is not None and self.end_s is not None and not self.end_s > self.start_s:
            raise IdentificationError(
                f"window end = {self.end_s:g} s must be after its start = {self.start_s:g} s"
            )

    @property
    def whole(self) -> bool:
        return self.start_s is None and self.end_s is None

    def mask(self, source: str, stamps: np.ndarray) -> np.ndarray:
        """Which of ``stamps`` [ns] lie in the window; an error naming the log's span if none do."""
        origin = int(stamps[0]) if self.origin_ns is None else self.origin_ns
        t = (stamps - origin) * 1e-9
        keep = np.ones(stamps.size, dtype=bool)
        if self.start_s is not None:
            keep &= t >= self.start_s
        if self.end_s is not None:
            keep &= t <= self.end_s
        if not keep.any():
            raise IdentificationError(
                f"{source}: no sample in the window {self.describe()}: the log spans "
                f"{t[0]:.3f} s to {t[-1]:.3f} s"
            )
        return keep

    def describe(self) -> str:
        start = "its start" if self.start_s is None else f"{self.start_s:g} s"
        end = "its end" if self.end_s is None else f"{self.end_s:g} s"
        origin = "the first sample" if self.origin_ns is None else f"stamp {self.origin_ns} ns"
        return f"from {start} to {end} after {origin}"


class JointKind(StrEnum):
    """Which side of the gearbox a joint measures."""

    MOTOR = "motor"
    """rad, rad/s, N·m"""
    CARRIAGE = "carriage"
    """m, m/s, N"""

    @property
    def effort_unit(self) -> str:
        return "N·m" if self is JointKind.MOTOR else "N"

    @property
    def effort_key(self) -> str:
        """the unit as it appears in report keys (``rms_nm``, ``rms_n``)"""
        return "nm" if self is JointKind.MOTOR else "n"


def joint_kind(name: str, kind: str | None = None) -> JointKind:
    """The kind of a joint: given explicitly, or ``motor``/``carriage`` by name (other names need it)."""
    if kind is not None:
        try:
            return JointKind(kind)
        except ValueError:
            raise IdentificationError(f"joint kind {kind!r} is not one of motor, carriage") from None
    if name in (JointKind.MOTOR.value, JointKind.CARRIAGE.value):
        return JointKind(name)
    raise IdentificationError(
        f"joint {name!r} is neither 'motor' nor 'carriage': say which it measures with --joint-kind "
        "motor (rad, rad/s, N·m) or carriage (m, m/s, N)"
    )


@dataclass(frozen=True, eq=False)
class JointSignals:
    """One log's joint, in the cart frame: times from the log's first stamp, position, velocity and
    the force the joint's effort means, all float64 arrays of the same length."""

    source: str
    topic: str
    joint: str
    kind: JointKind
    start_ns: int
    """stamp of the first sample [ns since the Unix epoch]"""
    t_s: np.ndarray
    position_m: np.ndarray
    velocity_m_s: np.ndarray
    force_n: np.ndarray
    effort_per_force: float
    """the joint's effort per cart force: r/i_r for a motor joint [N·m/N], 1 for a carriage joint"""
    finite: np.ndarray
    """False where a sample had a non-finite value (filled by interpolation; never fitted)"""
    truncated: bool
    stamp_jitter_s: float
    """the largest deviation of a stamp from the uniform grid ``t_s`` [s]"""
    skipped: int = 0
    """samples lost with chunks of the log that could not be read (put back as non-finite ones)"""

    @property
    def rate_hz(self) -> float:
        return (len(self.t_s) - 1) / (self.t_s[-1] - self.t_s[0])

    @property
    def duration_s(self) -> float:
        return float(self.t_s[-1] - self.t_s[0])

    @property
    def dropped(self) -> int:
        """samples with a non-finite value in the log (not counting the ``skipped`` ones)"""
        return int(np.count_nonzero(~self.finite)) - self.skipped


def load_joint(
    path: str | Path,
    topic: str,
    joint: str,
    params: AxisParams,
    kind: str | None = None,
    window: TimeWindow | None = None,
) -> JointSignals:
    """The joint ``joint`` of ``topic`` in the log at ``path`` (within ``window``: default the whole
    log), checked (see the module docstring)."""
    columns = read_joint_states(path, topic)
    data = columns.joint(joint)
    jk = joint_kind(joint, kind)
    scale = params.r / params.i_r if jk is JointKind.MOTOR else 1.0
    stamps = data.stamp_ns
    q = np.asarray(data.position, dtype=float)
    qd = np.asarray(data.velocity, dtype=float)
    effort = np.asarray(data.effort, dtype=float)
    stamps, (q, qd, effort), skipped = _open_holes(stamps, (q, qd, effort), columns.holes)
    origin_ns, first = (int(stamps[0]) if stamps.size else 0), 0
    if window is not None and not window.whole and stamps.size:
        keep = window.mask(str(path), stamps)
        first = int(np.argmax(keep))  # the window is one stretch: its first sample's index
        if window.origin_ns is not None:
            origin_ns = window.origin_ns
        stamps, q, qd, effort, skipped = stamps[keep], q[keep], qd[keep], effort[keep], skipped[keep]
    _check_stamps(str(path), stamps, origin_ns, first)
    finite = np.isfinite(q) & np.isfinite(qd) & np.isfinite(effort)
    n_skipped = int(np.count_nonzero(skipped))
    n_bad = int(np.count_nonzero(~finite)) - n_skipped
    if n_bad > MAX_NONFINITE_FRACTION * finite.size:
        raise IdentificationError(
            f"{path}: {n_bad} of {finite.size} samples of joint {joint!r} have non-finite values "
            f"(more than {MAX_NONFINITE_FRACTION:.0%}): the log cannot be used"
        )
    k = np.arange(stamps.size, dtype=float)
    since_first = (stamps - stamps[0]).astype(float)
    step_ns, offset_ns = np.polyfit(k, since_first, 1)  # the drive's period and phase, by least squares
    grid_ns = offset_ns + k * step_ns
    jitter_s = float(np.max(np.abs(since_first - grid_ns))) * 1e-9
    t = (grid_ns - grid_ns[0]) * 1e-9
    if not finite.all():  # non-finite values and skipped samples
        q, qd, effort = (_fill(t, a, finite) for a in (q, qd, effort))
    signals = JointSignals(
        source=str(path),
        topic=topic,
        joint=joint,
        kind=jk,
        start_ns=int(stamps[0]),
        t_s=t,
        position_m=q * scale,
        velocity_m_s=qd * scale,
        force_n=effort / scale,
        effort_per_force=scale,
        finite=finite,
        truncated=columns.truncated,
        stamp_jitter_s=jitter_s,
        skipped=n_skipped,
    )
    _check_usable(signals)
    return signals


def _check_stamps(source: str, stamps: np.ndarray, origin_ns: int, first: int) -> None:
    """Increasing stamps at a steady step; errors name samples by their index in the whole log
    (``first``: the index of ``stamps[0]``) and times in seconds from ``origin_ns``."""
    if stamps.size < 3:
        raise IdentificationError(f"{source}: {stamps.size} samples are too few to identify anything")
    steps = np.diff(stamps)
    back = np.flatnonzero(steps <= 0)
    t = (stamps - origin_ns) * 1e-9
    if back.size:
        k = int(back[0]) + 1
        raise IdentificationError(
            f"{source}: time stamps do not increase: sample {first + k} at {t[k]:.6f} s is "
            f"{-steps[k - 1] * 1e-9:.6f} s before sample {first + k - 1} ({back.size} such steps in all)"
        )
    median = float(np.median(steps))
    off = np.flatnonzero(np.abs(steps - median) > GAP_TOLERANCE * median)
    if off.size:
        k = int(off[0])
        raise IdentificationError(
            f"{source}: a gap in the time stamps: {steps[k] * 1e-6:.3f} ms between samples {first + k} and "
            f"{first + k + 1} (at {t[k]:.6f} s), the log's step is {median * 1e-6:.3f} ms ({off.size} such "
            "steps in all); "
            "identify needs an unbroken record: fit the part before or after it (--start/--end)"
        )


def _open_holes(
    stamps: np.ndarray, arrays: tuple[np.ndarray, ...], holes: tuple[Hole, ...]
) -> tuple[np.ndarray, tuple[np.ndarray, ...], np.ndarray]:
    """The samples with each hole between two rows filled by missing samples: stamps at the log's
    median step from the sample before the hole, NaN values. Returns the stamps, the arrays and a mask
    of the samples put back. (A hole before the first or after the last row shortens the log.)"""
    inner = [h.row for h in holes if 0 < h.row < stamps.size]
    if not inner:
        return stamps, arrays, np.zeros(stamps.size, dtype=bool)
    step = float(np.median(np.diff(stamps)))
    at: list[int] = []
    put_back: list[int] = []
    for row in inner:
        missing = round((stamps[row] - stamps[row - 1]) / step) - 1 if step > 0 else 0
        at += [row] * max(missing, 0)
        put_back += [int(stamps[row - 1]) + round(k * step) for k in range(1, missing + 1)]
    where = np.array(at, dtype=np.intp)
    filled = tuple(np.insert(a, where, np.nan) for a in arrays)
    mask = np.insert(np.zeros(stamps.size, dtype=bool), where, True)
    return np.insert(stamps, where, np.array(put_back, dtype=np.int64)), filled, mask


def _fill(t: np.ndarray, values: np.ndarray, finite: np.ndarray) -> np.ndarray:
    """Non-finite samples replaced by linear interpolation (so that filters run; never fitted)."""
    return np.interp(t, t[finite], values[finite])


def _check_usable(s: JointSignals) -> None:
    if s.duration_s < MIN_DURATION_S:
        raise IdentificationError(
            f"{s.source}: {s.duration_s:.3f} s of joint {s.joint!r} is too short "
            f"(at least {MIN_DURATION_S:g} s)"
        )
    peak = float(np.max(np.abs(s.velocity_m_s)))
    if peak < MIN_MOTION_M_S:
        raise IdentificationError(
            f"{s.source}: the axis does not move in this log (peak speed {peak:.3g} m/s, below "
            f"{MIN_MOTION_M_S:g} m/s): run `axisflow excite` while recording"
        )
