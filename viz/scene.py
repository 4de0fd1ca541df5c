"""What the view draws, one ``log_<thing>()`` per part of the scene, and :class:`AxisScene`, which feeds
them from the records of one axis (a log at once, or the network batch by batch).

Every function sends whole columns with ``rerun.send_columns`` (never one ``log`` call per sample) on
the one timeline of :mod:`.entities`: the samples' header stamps as integer nanoseconds (a numpy
``datetime64[ns]`` view of the int64 stamps, so rerun stores them bit for bit). Values are sent as
they are in the messages (float64), so a recording read back equals its log.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import rerun as rr

from ..acquisition.wire.move_status import MoveState, MoveStatus
from ..acquisition.wire.params_estimate import PARAMETER_NAMES, ParamsEstimate
from ..acquisition.wire.plan_record import PlanRecord
from ..model import AxisParams
from .entities import TIMELINE, AxisEntities
from .moves import MoveLedger, MovePoint, MovePoints
from .samples import AxisSamples
from .tracking import TrackingJoin

LIMIT_STEP_NS = 1_000_000_000
"""a live view extends the limit lines when the samples have run this far [ns] past them"""
_SCALARS = rr.Scalars.descriptor_scalars()
CHUNK_ROWS = 100_000
"""rows per ``send_columns`` call: bounded chunks for the viewer and the memory"""

MEASURED = (31, 119, 180)
SETPOINT = (255, 127, 14)
LIMIT = (214, 39, 40)
WAYPOINT = (44, 160, 44)
PLANNED = (255, 127, 14)
ERROR = (148, 103, 189)
START = (127, 127, 127)
PARAMETER_COLOURS = {
    "M_eq": (140, 86, 75),
    "a1": (31, 119, 180),
    "a2": (214, 39, 40),
    "a3": (44, 160, 44),
    "a4": (148, 103, 189),
    "f0": (127, 127, 127),
    "da1": (23, 190, 207),
    "da2": (188, 189, 34),
}
FRICTION_POINTS = 101
"""points of each direction's branch of a friction curve F_c(ẋ), from rest to v_max"""
_LEVELS = {
    MoveState.ACCEPTED: rr.TextLogLevel.INFO,
    MoveState.STARTED: rr.TextLogLevel.DEBUG,
    MoveState.COMPLETED: rr.TextLogLevel.INFO,
    MoveState.REJECTED: rr.TextLogLevel.ERROR,
    MoveState.DROPPED: rr.TextLogLevel.WARN,
    MoveState.STOPPED: rr.TextLogLevel.WARN,
    MoveState.FAULT: rr.TextLogLevel.ERROR,
    MoveState.COMM_LOST: rr.TextLogLevel.ERROR,
    MoveState.DRIVE_STOPPED: rr.TextLogLevel.ERROR,
    MoveState.WARNING: rr.TextLogLevel.WARN,
    MoveState.ENABLED: rr.TextLogLevel.INFO,
}


def send_scalars(rec: rr.RecordingStream, path: str, stamp_ns: np.ndarray, values: np.ndarray) -> None:
    """``values`` (float64, shape (n,) or (n, k) for k series) at ``stamp_ns`` (int64 ns) on ``path``."""
    stamps = np.ascontiguousarray(stamp_ns, dtype=np.int64).view("datetime64[ns]")
    values = np.asarray(values, dtype=np.float64)
    for a in range(0, len(stamps), CHUNK_ROWS):
        part = values[a : a + CHUNK_ROWS]
        if part.ndim == 1:  # one scalar per row: the column built directly (a live view sends thousands)
            columns = [rr.ComponentColumn(_SCALARS, rr.components.ScalarBatch(part))]
        else:
            columns = rr.Scalars.columns(scalars=part)
        rec.send_columns(
            path, indexes=[rr.TimeColumn(TIMELINE, timestamp=stamps[a : a + CHUNK_ROWS])], columns=columns
        )


def _send_points(rec: rr.RecordingStream, path: str, points: Sequence[MovePoint]) -> None:
    if points:
        send_scalars(
            rec, path, np.array([p.stamp_ns for p in points], np.int64), np.array([p.value for p in points])
        )


def log_styles(rec: rr.RecordingStream, e: AxisEntities) -> None:
    """Names and colours of every series (static: they hold on every timeline)."""
    lines = {
        e.position_measured: ("measured", MEASURED),
        e.position_setpoint: ("setpoint", SETPOINT),
        e.velocity_measured: ("measured", MEASURED),
        e.velocity_setpoint: ("setpoint", SETPOINT),
        e.torque_measured: ("measured", MEASURED),
        e.torque_feedforward: ("feed-forward (model)", SETPOINT),
        e.tracking_error: ("setpoint − measured", ERROR),
        e.power: ("τ_m·ω_m, measured", MEASURED),
    }
    for path, (name, colour) in lines.items():
        rec.log(path, rr.SeriesLines(names=name, colors=[colour], widths=1.0), static=True)
    for path, names in (
        (e.stroke, ["L", "0"]),
        (e.velocity_limits, ["+v_max", "−v_max"]),
        (e.torque_limits, ["+tau_max", "−tau_max"]),
    ):
        rec.log(path, rr.SeriesLines(names=names, colors=[LIMIT, LIMIT], widths=[1.0, 1.0]), static=True)
    points = {
        e.waypoints: ("way point (plan end)", WAYPOINT, "Diamond"),
        e.energy_measured: ("measured ∫g(τ_m·ω_m)dt", MEASURED, "Circle"),
        e.energy_planned: ("planned E_th", PLANNED, "Cross"),
        e.energy_error: ("E% = (E_th − E_exp)/E_th", ERROR, "Circle"),
    }
    for path, (name, colour, marker) in points.items():
        rec.log(
            path, rr.SeriesPoints(names=name, colors=[colour], markers=marker, marker_sizes=4.0), static=True
        )


def log_limits(rec: rr.RecordingStream, e: AxisEntities, params: AxisParams, stamp_ns: Sequence[int]) -> None:
    """The stroke [0, L], ±v_max and ±tau_max as lines through the times ``stamp_ns`` (e.g. the first
    and the last stamp of the samples)."""
    stamps = np.array(stamp_ns, np.int64)
    for path, (low, high) in (
        (e.stroke, (0.0, params.L)),
        (e.velocity_limits, (-params.v_max, params.v_max)),
        (e.torque_limits, (-params.tau_max, params.tau_max)),
    ):
        send_scalars(rec, path, stamps, np.array([[high, low]] * len(stamps)))


def log_signals(
    rec: rr.RecordingStream, samples: AxisSamples, position: str, velocity: str, torque: str
) -> None:
    """Carriage position x [m], cart velocity ẋ [m/s] and motor torque [N·m] of ``samples`` on the three
    entity paths (the measured ones, or the setpoint's with its model feed-forward τ_ff of eq. 1)."""
    send_scalars(rec, position, samples.stamp_ns, samples.position_m)
    send_scalars(rec, velocity, samples.stamp_ns, samples.velocity_m_s)
    send_scalars(rec, torque, samples.stamp_ns, samples.torque_nm)


def log_tracking_error(
    rec: rr.RecordingStream, e: AxisEntities, stamp_ns: np.ndarray, error_m: np.ndarray
) -> None:
    """Setpoint − measured position [m] of the ticks that have both."""
    if len(stamp_ns):
        send_scalars(rec, e.tracking_error, stamp_ns, error_m)


def log_power(rec: rr.RecordingStream, e: AxisEntities, measured: AxisSamples) -> None:
    """Mechanical power at the motor shaft, P = τ_m·ω_m [W] (= F·ẋ, eq. 1), of the measured samples."""
    send_scalars(rec, e.power, measured.stamp_ns, measured.torque_nm * measured.motor_speed_rad_s)


def log_move_points(rec: rr.RecordingStream, e: AxisEntities, points: MovePoints) -> None:
    """Way points (the plans' end positions [m]), per-move energy [J], measured and planned, and each
    move's E% [%], at the move's end tick."""
    _send_points(rec, e.waypoints, points.waypoints)
    _send_points(rec, e.energy_planned, points.planned_energy)
    _send_points(rec, e.energy_measured, points.measured_energy)
    _send_points(rec, e.energy_error, points.energy_error)


def drawn_parameters(start: ParamsEstimate) -> tuple[str, ...]:
    """The parameters an adaptive node's estimates are drawn for: those not zero in its version 0
    ``start`` (each is drawn in % of it; a term that is off, an axis without an offset say, has none)."""
    return tuple(name for name in PARAMETER_NAMES if start.value_of[name])


def log_parameter_styles(rec: rr.RecordingStream, e: AxisEntities, start: ParamsEstimate) -> None:
    """Names and colours of the adapted parameters' series (static), those of :func:`drawn_parameters`."""
    for name in drawn_parameters(start):
        colour = PARAMETER_COLOURS[name]
        names = [name, f"{name} + σ", f"{name} − σ"]
        rec.log(
            e.parameter(name),
            rr.SeriesLines(names=names, colors=[colour] * 3, widths=[1.5, 0.5, 0.5]),
            static=True,
        )
        rec.log(
            e.rejected_parameter(name),
            rr.SeriesPoints(names=f"{name}, turned down", colors=[colour], markers="Cross", marker_sizes=3.0),
            static=True,
        )


def log_parameters(
    rec: rr.RecordingStream, e: AxisEntities, records: Sequence[ParamsEstimate], start: ParamsEstimate
) -> None:
    """An adaptive node's estimates over time, each parameter in % of version 0 (``start``): the accepted
    ones with their ±σ band (three series), the turned-down ones as points (at the window's end); the
    parameters of :func:`drawn_parameters`."""
    base = start.value_of
    for name in drawn_parameters(start):
        accepted = [r for r in records if r.accepted and np.isfinite(r.value_of[name])]
        if accepted:
            stamps = np.array([r.stamp_ns for r in accepted], np.int64)
            value = np.array([r.value_of[name] for r in accepted])
            sigma = np.nan_to_num(np.array([r.std_of[name] for r in accepted]))
            columns = np.column_stack([value, value + sigma, value - sigma]) / base[name] * 100.0 - 100.0
            send_scalars(rec, e.parameter(name), stamps, columns)
        turned = [r for r in records if not r.accepted and np.isfinite(r.value_of[name])]
        if turned:
            stamps = np.array([r.stamp_ns for r in turned], np.int64)
            value = np.array([r.value_of[name] for r in turned]) / base[name] * 100.0 - 100.0
            send_scalars(rec, e.rejected_parameter(name), stamps, value)


def friction_curve(record: ParamsEstimate, v_max: float) -> np.ndarray:
    """(2n + 1, 2): F_c(ẋ) [N] over ẋ in [−v_max, v_max] [m/s] of a record's whole friction law
    (:mod:`axisflow.model.friction`, the offset and asymmetry included), one strip through both
    directions: moving towards −x, −φ₋(|ẋ|) up to rest; at rest, f0; moving towards +x, φ₊(ẋ)
    from rest. The Coulomb step at ẋ = 0 is drawn as the vertical segment through f0 that joins
    the two directions' limits."""
    law = record.friction
    v = np.linspace(0.0, v_max, FRICTION_POINTS)
    backward = -law.forward(-1.0).value(v)[::-1]
    forward = law.forward(1.0).value(v)
    speeds = np.concatenate([-v[::-1], [0.0], v])
    return np.column_stack([speeds, np.concatenate([backward, law.force(0.0)[None], forward])])


def log_friction(
    rec: rr.RecordingStream, e: AxisEntities, record: ParamsEstimate, start: ParamsEstimate, v_max: float
) -> None:
    """The friction curve of the accepted set ``record`` (at its time) beside version 0's (static)."""
    rec.log(
        e.friction_start,
        rr.LineStrips2D([friction_curve(start, v_max)], colors=[START], labels=["version 0"]),
        static=True,
    )
    rec.set_time(TIMELINE, timestamp=np.datetime64(record.stamp_ns, "ns"))
    rec.log(
        e.friction_now,
        rr.LineStrips2D(
            [friction_curve(record, v_max)], colors=[MEASURED], labels=[f"version {record.version}"]
        ),
    )


def log_move_statuses(rec: rr.RecordingStream, e: AxisEntities, statuses: Sequence[MoveStatus]) -> None:
    """The bridge's move statuses as a text log at their drive time, the level by their state."""
    if not statuses:
        return
    stamps = np.array([s.stamp_ns for s in statuses], np.int64).view("datetime64[ns]")
    texts = [s.text or f"{s.state.name.lower()} move {s.move_id}" for s in statuses]
    levels = [_LEVELS[s.state] for s in statuses]
    rec.send_columns(
        e.events,
        indexes=[rr.TimeColumn(TIMELINE, timestamp=stamps)],
        columns=rr.TextLog.columns(text=texts, level=levels),
    )


class AxisScene:
    """The scene of one axis, fed by its records in batches (see the module docstring).

    The limits are drawn over the span of the samples seen so far (extended by each batch); the
    tracking error pairs state and setpoint ticks as both arrive; the way points and energies appear
    once a move's records (and, for the measured energy, its samples) are in.
    """

    def __init__(self, rec: rr.RecordingStream, entities: AxisEntities, params: AxisParams) -> None:
        self.rec, self.entities, self.params = rec, entities, params
        self._tracking = TrackingJoin()
        self._moves = MoveLedger(params.energy_accounting)
        self._span: tuple[int, int] | None = None
        """the times the limit lines reach"""
        self._start: ParamsEstimate | None = None
        """an adaptive node's version 0 (its parameters are drawn relative to it)"""
        self._early: list[ParamsEstimate] = []
        """estimates that came before version 0"""
        self._seen: tuple[int, int] | None = None
        """the first and last stamp of the samples"""
        log_styles(rec, entities)

    def add_state(self, samples: AxisSamples) -> None:
        """Measured samples: position, velocity, torque, power, tracking error, measured energy."""
        if not len(samples):
            return
        e = self.entities
        log_signals(self.rec, samples, e.position_measured, e.velocity_measured, e.torque_measured)
        log_power(self.rec, e, samples)
        log_tracking_error(self.rec, e, *self._tracking.push(state=(samples.stamp_ns, samples.position_m)))
        log_move_points(self.rec, e, self._moves.add_samples(samples))
        self._extend_limits(samples.stamp_ns)

    def add_setpoint(self, samples: AxisSamples) -> None:
        """Setpoints: commanded position and velocity, feed-forward torque, tracking error."""
        if not len(samples):
            return
        e = self.entities
        log_signals(self.rec, samples, e.position_setpoint, e.velocity_setpoint, e.torque_feedforward)
        log_tracking_error(self.rec, e, *self._tracking.push(setpoint=(samples.stamp_ns, samples.position_m)))
        self._extend_limits(samples.stamp_ns)

    def add_statuses(self, statuses: Sequence[MoveStatus]) -> None:
        log_move_statuses(self.rec, self.entities, statuses)
        points = MovePoints()
        for status in statuses:
            points.extend(self._moves.add_status(status))
        log_move_points(self.rec, self.entities, points)

    def add_plans(self, plans: Sequence[PlanRecord]) -> None:
        points = MovePoints()
        for plan in plans:
            points.extend(self._moves.add_plan(plan))
        log_move_points(self.rec, self.entities, points)

    def add_params(self, records: Sequence[ParamsEstimate]) -> None:
        """An adaptive node's estimates: the parameters over time and the friction curve now and at the
        start (nothing until its version 0 has come: the parameters are drawn relative to it)."""
        e = self.entities
        if self._start is None:
            initial = [r for r in records if r.decision == "initial"]
            if not initial:
                self._early += records
                return
            self._start = initial[0]
            log_parameter_styles(self.rec, e, self._start)
            records, self._early = [*self._early, *records], []
        log_parameters(self.rec, e, records, self._start)
        for record in records:
            if record.accepted:
                log_friction(self.rec, e, record, self._start, self.params.v_max)

    def finish(self) -> None:
        """Draw the limits to the last sample seen (a live view extends them in steps)."""
        if self._seen is not None:
            self._extend_limits(np.array(self._seen, np.int64), step_ns=0)

    def _extend_limits(self, stamp_ns: np.ndarray, step_ns: int = LIMIT_STEP_NS) -> None:
        """Extend the limit lines to ``stamp_ns`` where the samples run more than ``step_ns`` past them."""
        lo, hi = int(stamp_ns.min()), int(stamp_ns.max())
        if self._seen is not None:
            lo, hi = min(lo, self._seen[0]), max(hi, self._seen[1])
        self._seen = (lo, hi)
        if self._span is None:
            new = sorted({lo, hi})
        else:
            first, last = self._span
            new = [t for t, beyond in ((lo, lo < first - step_ns), (hi, hi > last + step_ns)) if beyond]
        if new:
            self._span = (min([*new, *(self._span or ())]), max([*new, *(self._span or ())]))
            log_limits(self.rec, self.entities, self.params, new)
