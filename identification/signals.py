"""The measured signals of one joint of a log, in the cart's SI units, checked for what the fit needs.

A ``sensor_msgs/msg/JointState`` joint is read with the fast log reader
(:func:`axisflow.acquisition.logs.reader.read_joint_states`) and converted to the cart's frame with the
axis geometry (r, i_r of the parameter file):

* a **motor** joint (angle [rad], speed [rad/s], torque [N·m]): x = θ·r/i_r, ẋ = ω·r/i_r,
  F = τ·i_r/r; the fit's errors are reported in N·m;
* a **carriage** joint (position [m], velocity [m/s], belt force [N]) is used as it is; errors in N.

Checks, each a one-line :class:`IdentificationError`: the time stamps must increase (a jump back names
its sample and time); non-finite positions and efforts are dropped and counted (an error above
:data:`MAX_NONFINITE_FRACTION`); the record must be long enough and the axis must move.

Lost samples are normal (a frame lost on a fieldbus, a message dropped on a busy network, a damaged
chunk a reader skipped): the samples are placed on the drive's sampling grid
(:mod:`.sample_grid`), the holes are filled by interpolation so that filters can run, counted and
marked (``observed``), and preparation keeps every filtered or differentiated value that a hole
touches out of the fit. Only a log missing more than
:data:`~.sample_grid.MAX_LOST_FRACTION` of its grid is refused.

Velocity: the fit never uses a logged velocity (a drive's velocity is its own filtered estimate, with
its own lag); it differentiates the filtered position. A log without velocities (many drivers send
none: an empty array in every message) is read as well; ``velocity_logged`` says whether it had them.

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
from typing import TYPE_CHECKING

import numpy as np

from ..acquisition.wire.keys import AxisKeys, topic_for_key
from ..model import AxisflowError
from .errors import IdentificationError
from .sample_grid import SampleGrid, place_on_grid

if TYPE_CHECKING:
    from ..model import AxisParams

DEFAULT_TOPIC = topic_for_key(AxisKeys().state)
"""the JointState topic a refit reads unless told: the state of our default axis"""
DEFAULT_JOINT = "motor"
"""the joint a refit reads unless told (a :class:`JointKind` by its name)"""
MAX_NONFINITE_FRACTION = 0.01
"""more non-finite samples than this fraction of a log is an error, not something to drop"""
MIN_DURATION_S = 2.0
MIN_MOTION_M_S = 1e-3


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
    """One log's joint, in the cart frame, on the drive's sampling grid: times from the first sample,
    position, velocity and the force the joint's effort means, all float64 arrays of the grid's length
    (values at missing samples interpolated; ``observed`` marks the real ones)."""

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
    """False where a sample had a non-finite position or effort (filled by interpolation; never fitted)"""
    truncated: bool
    stamp_jitter_s: float
    """the largest deviation of a stamp from the uniform grid ``t_s`` [s]"""
    grid: SampleGrid
    """where the samples sit on the drive's grid; its holes"""
    velocity_logged: bool
    """whether the log carries velocities (NaN at grid points without one; never fitted)"""
    skipped: int = 0
    """of the :attr:`lost` samples, those lost with chunks of the log that the reader could not read
    and skipped (each named in a warning)"""

    @property
    def observed(self) -> np.ndarray:
        """True at the grid points that have a sample."""
        return self.grid.observed()

    @property
    def rate_hz(self) -> float:
        return 1e9 / self.grid.period_ns

    @property
    def duration_s(self) -> float:
        return float(self.t_s[-1] - self.t_s[0])

    @property
    def dropped(self) -> int:
        """Samples with non-finite values (not counting missing ones)."""
        return int(np.count_nonzero(~self.finite & self.observed))

    @property
    def lost(self) -> int:
        """Samples missing from the log (holes in the grid)."""
        return self.grid.lost


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
    from ..acquisition.logs.reader import read_joint_states  # the log reader (mcap) loads when used

    columns = read_joint_states(path, topic)
    data = columns.joint(joint)
    jk = joint_kind(joint, kind)
    scale = params.transmission.metres_per_radian if jk is JointKind.MOTOR else 1.0
    stamps = data.stamp_ns
    q = np.asarray(data.position, dtype=float)
    qd = np.asarray(data.velocity, dtype=float)
    effort = np.asarray(data.effort, dtype=float)
    origin_ns, first, end = (int(stamps[0]) if stamps.size else 0), 0, stamps.size
    if window is not None and not window.whole and stamps.size:
        keep = window.mask(str(path), stamps)
        first = int(np.argmax(keep))  # the window is one stretch: its first sample's index
        end = first + int(np.count_nonzero(keep))
        if window.origin_ns is not None:
            origin_ns = window.origin_ns
        stamps, q, qd, effort = stamps[keep], q[keep], qd[keep], effort[keep]
    # a skipped chunk inside the kept rows leaves a gap in the stamps: the grid makes it a hole
    skipped = sum(h.messages or 0 for h in columns.holes if first < h.row < end)
    grid = place_on_grid(stamps, str(path), first, origin_ns)
    finite = np.isfinite(q) & np.isfinite(effort)
    n_bad = int(np.count_nonzero(~finite))
    if n_bad > MAX_NONFINITE_FRACTION * finite.size:
        raise IdentificationError(
            f"{path}: {n_bad} of {finite.size} samples of joint {joint!r} have non-finite values "
            f"(more than {MAX_NONFINITE_FRACTION:.0%}): the log cannot be used"
        )
    velocity_logged = bool(np.isfinite(qd).any())
    if n_bad:
        q, effort = (_fill(a, finite) for a in (q, effort))
    on_grid = np.zeros(grid.size, dtype=bool)
    on_grid[grid.index] = finite
    velocity = np.full(grid.size, np.nan)
    velocity[grid.index] = qd
    signals = JointSignals(
        source=str(path),
        topic=topic,
        joint=joint,
        kind=jk,
        start_ns=int(stamps[0]),
        t_s=grid.times_s(),
        position_m=grid.spread(q) * scale,
        velocity_m_s=velocity * scale,
        force_n=grid.spread(effort) / scale,
        effort_per_force=scale,
        finite=on_grid | ~grid.observed(),
        truncated=columns.truncated,
        stamp_jitter_s=grid.jitter_s,
        grid=grid,
        velocity_logged=velocity_logged,
        skipped=skipped,
    )
    _check_usable(signals)
    return signals


def _fill(values: np.ndarray, finite: np.ndarray) -> np.ndarray:
    """Non-finite samples replaced by linear interpolation between their finite neighbours (so that
    filters run; never fitted)."""
    k = np.arange(values.size, dtype=float)
    return np.interp(k, k[finite], values[finite])


def _check_usable(s: JointSignals) -> None:
    if s.duration_s < MIN_DURATION_S:
        raise IdentificationError(
            f"{s.source}: {s.duration_s:.3f} s of joint {s.joint!r} is too short "
            f"(at least {MIN_DURATION_S:g} s)"
        )
    speed = np.abs(np.diff(s.position_m)) * s.rate_hz  # from the position: the log may have no velocity
    peak = float(np.percentile(speed, 99.9)) if speed.size else 0.0
    if peak < MIN_MOTION_M_S:
        raise IdentificationError(
            f"{s.source}: the axis does not move in this log (peak speed {peak:.3g} m/s, below "
            f"{MIN_MOTION_M_S:g} m/s): run `axisflow excite` while recording"
        )


def recorded_drive(path: str | Path, topic: str) -> str | None:
    """What drove the axis whose samples are on ``topic`` (``/<prefix>/<axis>/state``), as its bridge
    recorded it on ``/<prefix>/<axis>/drive`` (:class:`~axisflow.acquisition.wire.drive_info.DriveInfo`);
    None for a log without it (another tool's, or a bridge that did not say)."""
    from ..acquisition.logs.reader import read_messages
    from ..acquisition.wire.drive_info import DRIVE_INFO_TYPE, DriveInfo

    drive_topic = topic.rsplit("/", 1)[0] + "/drive"
    try:
        messages = read_messages(path, drive_topic, DRIVE_INFO_TYPE)
    except AxisflowError:
        return None
    return DriveInfo.decode(messages[-1].data).describe() if messages else None
