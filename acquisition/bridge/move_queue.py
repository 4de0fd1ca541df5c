"""The drive's queue of moves: validation on arrival, one setpoint per 1 ms tick.

Validation happens in two steps, so that the costly one can run off the 1 kHz loop:

:func:`validate_move` (stateless, thread-safe) accepts a move only if

* its law is known and its numbers are finite with 0 s < duration ≤ :data:`MAX_MOVE_DURATION_S`; a
  ``sampled`` move's knots agree with its end points and duration, start and end at rest;
* both end positions lie in [0, L] (the polynomial laws do not overshoot their end points; a sampled
  path is checked at every 1 kHz sample and knot);
* its velocity stays within v_max over the whole move (the law's analytic peak, c_v·|d|/T) and its
  motor torque within tau_max at the 1 kHz execution samples and at :data:`CHECK_POINTS` evenly
  spaced times (so a move shorter than a few ticks is checked along its course, not only at its two
  ends, where it is at rest), with the nominal parameters.

:meth:`MoveQueue.enqueue` (on the loop, cheap) then accepts it only if

* it starts where the axis will be when it starts: |start_position_m − x_end| ≤ ``jump_tolerance_m``,
  with x_end the end position of the last queued move (or the held position) — no jumps;
* its start (if not "append") is not before the end of the moves already queued;
* fewer than :data:`MAX_QUEUED_MOVES` moves are queued, and a sampled move's knots fit with the queued
  ones' into :data:`MAX_QUEUED_KNOTS` (the count alone would let 1024 one-hour paths take ~300 GB).

Rejections raise :class:`~axisflow.acquisition.errors.MoveRejectedError` with the reason.

Timing: tick k is the drive time ``t0 + k·1 ms``. An appended move starts at the end tick of the
previous one (whose sample is the previous end point at rest, equal to this move's start point), or at
the current tick if the queue is empty: no idle tick between queued moves. A move spanning T seconds
ends at tick ``start +`` :func:`~axisflow.model.move_ticks` (T) (the sampling rule of
:mod:`axisflow.model.sampling`, the one the validation checks). With no move active the axis holds the
last position. :meth:`MoveQueue.advance` gives each tick's setpoint with the moves that started and
ended at it.

Senders: every queued move remembers its sender (the publisher id of its attachment). When a sender
disappears, :meth:`MoveQueue.drop_sender` removes its moves that have not started and every move
queued after the first of them (they would start from where its moves end); a move already running
ends, at rest, within the limits, and the axis holds there.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

import numpy as np

from ...model import (
    EXECUTION_PERIOD_NS,
    EXECUTION_PERIOD_S,
    AxisflowError,
    AxisParams,
    Motion,
    Move,
    SampledTrajectory,
    StopProfile,
    cart_force,
    check_limits,
    motor_angle,
    motor_speed,
    motor_torque,
    move_ticks,
    polynomial_law,
    stop_profile,
)
from ...model.braking import QUICK_STOP_FORCE
from ...model.trajectory import MAX_KNOTS
from ..drives.drive import Setpoint
from ..errors import MoveRejectedError
from ..wire.messages import APPEND, SAMPLED_LAW, Knots, MoveCommand
from ..wire.quick_stop import STOP_MOVE_ID
from .continuity import DEFAULT_JUMP_TOLERANCE_M

MAX_QUEUED_MOVES = 1024
"""moves a drive holds at once (running included); more are rejected until some have run"""
MAX_QUEUED_KNOTS = 2 * MAX_KNOTS
"""knots of sampled moves a drive holds at once (running included): two hours of a 1 kHz path. A
queued knot costs 80 B (the message's four float64 arrays, 32 B, and the validated trajectory, 48 B,
as tracemalloc of one queued one-hour path shows), so a full budget costs ~0.58 GB; a sampled move
that would pass it is rejected until some have run"""
CHECK_POINTS = 1001
"""evenly spaced times at which a move's torque is checked besides the 1 kHz samples"""
SETPOINT_BLOCK_TICKS = 1024
"""ticks of the running move sampled at once (vectorised) when the loop reaches them: a tick then
reads its setpoint from lists instead of evaluating the law (~0.1 µs instead of ~15 µs); a block of a
long move costs ~60 kB and ~0.1 ms"""


def validate_move(cmd: MoveCommand, params: AxisParams, axis: str = "") -> Motion:
    """The motion of ``cmd`` if it is one the axis can run anywhere (see the module doc); raises
    :class:`MoveRejectedError` with the reason. Depends on nothing queued: safe off the loop."""
    p = params
    tag = f"move {cmd.move_id}"
    if axis and cmd.axis and cmd.axis != axis:
        raise MoveRejectedError(f"{tag}: addressed to axis {cmd.axis!r}, this drive is {axis!r}")
    try:
        motion = _sampled_motion(cmd) if cmd.law == SAMPLED_LAW else _polynomial_move(cmd)
    except AxisflowError as exc:
        raise MoveRejectedError(f"{tag}: {exc}") from None
    for name, x in (("start_position_m", motion.x0_m), ("end_position_m", motion.x1_m)):
        if not 0.0 <= x <= p.L:
            raise MoveRejectedError(f"{tag}: {name} = {x} m is outside the stroke [0, {p.L}] m")
    if isinstance(motion, Move) and motion.peak_velocity_m_s > p.v_max:
        raise MoveRejectedError(
            f"{tag}: peak velocity {motion.peak_velocity_m_s:.6g} m/s exceeds v_max = {p.v_max} m/s"
        )
    knot_times = motion.t_s if isinstance(motion, SampledTrajectory) else None
    report = check_limits(motion, p, min_points=CHECK_POINTS, extra_times_s=knot_times)
    if report.velocity_violation > 0.0:
        raise MoveRejectedError(
            f"{tag}: peak velocity {report.peak_velocity_m_s:.6g} m/s exceeds v_max = {p.v_max} m/s"
        )
    if report.torque_violation > 0.0:
        raise MoveRejectedError(
            f"{tag}: peak motor torque {report.peak_torque_nm:.6g} N·m exceeds tau_max = {p.tau_max} N·m"
        )
    if report.min_position_m < 0.0 or report.max_position_m > p.L:
        raise MoveRejectedError(
            f"{tag}: its path reaches {report.min_position_m:.6g} … {report.max_position_m:.6g} m, outside "
            f"the stroke [0, {p.L}] m"
        )
    return motion


def _polynomial_move(cmd: MoveCommand) -> Move:
    if cmd.knots is not None:
        raise MoveRejectedError(
            f"law {cmd.law!r} takes no knots (got {len(cmd.knots)}); use law {SAMPLED_LAW!r}"
        )
    return Move(cmd.start_position_m, cmd.end_position_m, cmd.duration_s, polynomial_law(cmd.law))


def _sampled_motion(cmd: MoveCommand) -> SampledTrajectory:
    """The trajectory of a sampled move, consistent with the move's own end points and duration."""
    if cmd.knots is None:
        raise MoveRejectedError(f"law {SAMPLED_LAW!r} needs knots, the move has none")
    traj = SampledTrajectory(*cmd.knots.arrays())
    for name, given, knot in (
        ("duration_s", cmd.duration_s, traj.duration_s),
        ("start_position_m", cmd.start_position_m, traj.x0_m),
        ("end_position_m", cmd.end_position_m, traj.x1_m),
    ):
        if abs(given - knot) > 1e-9:
            raise MoveRejectedError(f"{name} = {given} differs from its knots' {knot}")
    return traj


@dataclass(frozen=True)
class QueuedMove:
    command: MoveCommand
    move: Motion
    start_tick: int
    end_tick: int
    """first tick after the move's last in-motion sample: the move's end point at rest"""
    sender: bytes = b""
    """publisher id of the move's sender (its attachment), b"" when unknown"""
    stop: StopProfile | None = None
    """set for the braking profile of a quick stop (not a move anyone sent)"""


@dataclass(frozen=True)
class StopOutcome:
    """What a quick stop did to the queue at its tick."""

    tick: int
    interrupted: QueuedMove | None
    """the running move, abandoned for the braking profile (None: nothing ran, or it ends sooner)"""
    kept: QueuedMove | None
    """the running move, kept because its own course reaches rest sooner than braking would"""
    dropped: list[QueuedMove]
    """the queued moves that had not started"""
    braking: QueuedMove | None
    """the braking profile now running"""
    speed_m_s: float
    """the setpoint speed when the stop was requested [m/s]"""


@dataclass(frozen=True)
class QueueStep:
    """One tick of the queue: the setpoint, the move whose first sample it is, the moves that ended."""

    setpoint: Setpoint
    started: QueuedMove | None
    finished: tuple[QueuedMove, ...]
    motor: tuple[float, float, float] = (0.0, 0.0, 0.0)
    """the setpoint's motor angle [rad], speed [rad/s] and feed-forward torque [N·m]: the motor joint
    of :meth:`Setpoint.to_sample`, which the bridge publishes"""


class _SetpointBlock:
    """The setpoints of ticks ``first`` … ``first + len − 1`` of one queued move, sampled at once: the
    same law, times and feed-forward as one tick at a time (numpy evaluates them element by element),
    as Python floats."""

    __slots__ = ("first", "motor", "queued", "setpoints", "stop")

    def __init__(self, q: QueuedMove, first: int, params: AxisParams) -> None:
        n = max(1, min(SETPOINT_BLOCK_TICKS, q.end_tick - first))
        offsets = np.arange(first - q.start_tick, first - q.start_tick + n)
        s = q.move.sample(offsets * EXECUTION_PERIOD_S)
        x = np.asarray(s.position_m, dtype=float)
        v = np.asarray(s.velocity_m_s, dtype=float)
        a = np.asarray(s.acceleration_m_s2, dtype=float)
        f = np.asarray(cart_force(v, a, params), dtype=float)
        self.queued, self.first, self.stop = q, first, first + n
        self.setpoints = [
            Setpoint(*row) for row in zip(x.tolist(), v.tolist(), a.tolist(), f.tolist(), strict=True)
        ]
        self.motor = list(
            zip(
                motor_angle(x, params).tolist(),
                motor_speed(v, params).tolist(),
                motor_torque(f, params).tolist(),
                strict=True,
            )
        )


def _knot_count(q: QueuedMove) -> int:
    return len(q.command.knots) if q.command.knots is not None else 0


class MoveQueue:
    """Validated moves in execution order and the hold position after them."""

    def __init__(
        self,
        params: AxisParams,
        hold_position_m: float,
        start_stamp_ns: int,
        axis: str = "",
        jump_tolerance_m: float = DEFAULT_JUMP_TOLERANCE_M,
    ) -> None:
        if not jump_tolerance_m >= 0.0:
            raise MoveRejectedError(f"jump tolerance = {jump_tolerance_m} m must be >= 0 m")
        self.params = params
        self.axis = axis
        self.jump_tolerance_m = jump_tolerance_m
        self._start_ns = start_stamp_ns
        self._queue: deque[QueuedMove] = deque()
        self._knots = 0
        """knots of the queued sampled moves, kept as moves enter and leave (summing them on every
        enqueue cost ~0.14 ms with 1024 sampled moves queued, on the 1 kHz loop)"""
        self._hold_m = hold_position_m
        self.completed = 0
        self._head_started = False
        """whether the move at the head of the queue has had its first sample"""
        self._block: _SetpointBlock | None = None
        """the head move's setpoints of the coming ticks (sampled a block at a time)"""
        self._hold_motor: tuple[float, tuple[float, float, float]] | None = None
        """(hold position, its motor joint): computed once per hold position"""

    def __len__(self) -> int:
        return len(self._queue)

    @property
    def end_position_m(self) -> float:
        """Where the axis will rest after the queued moves."""
        return self._queue[-1].move.x1_m if self._queue else self._hold_m

    @property
    def queued_knots(self) -> int:
        """Knots of the queued sampled moves (the running one included)."""
        return self._knots

    def _append(self, q: QueuedMove) -> None:
        self._queue.append(q)
        self._knots += _knot_count(q)

    def _removed(self, q: QueuedMove) -> QueuedMove:
        """``q``, just taken out of the queue (its knots no longer count)."""
        self._knots -= _knot_count(q)
        return q

    def end_tick(self, now_tick: int) -> int:
        return max(self._queue[-1].end_tick, now_tick) if self._queue else now_tick

    def tick_of(self, stamp_ns: int) -> int:
        return math.ceil((stamp_ns - self._start_ns) / EXECUTION_PERIOD_NS)

    def stamp_of(self, tick: int) -> int:
        """Drive time [ns] of ``tick``."""
        return self._start_ns + tick * EXECUTION_PERIOD_NS

    def validate(self, cmd: MoveCommand) -> Motion:
        """:func:`validate_move` with this queue's parameters and axis."""
        return validate_move(cmd, self.params, self.axis)

    def enqueue(self, cmd: MoveCommand, move: Motion, now_tick: int, sender: bytes = b"") -> QueuedMove:
        """Queue a validated move after the queued ones (jump, timing and capacity checks)."""
        tag = f"move {cmd.move_id}"
        if len(self._queue) >= MAX_QUEUED_MOVES:
            raise MoveRejectedError(f"{tag}: the queue is full ({MAX_QUEUED_MOVES} moves)")
        if cmd.knots is not None:
            queued_knots = self.queued_knots
            if queued_knots + len(cmd.knots) > MAX_QUEUED_KNOTS:
                raise MoveRejectedError(
                    f"{tag}: the queue is full: its {len(cmd.knots)} knots and the {queued_knots} queued "
                    f"would pass the limit of {MAX_QUEUED_KNOTS} knots of sampled moves"
                )
        x_end = self.end_position_m
        jump = abs(move.x0_m - x_end)
        if jump > self.jump_tolerance_m:
            raise MoveRejectedError(
                f"{tag}: start_position_m = {move.x0_m} m jumps {jump:.6g} m from the axis's position "
                f"{x_end} m at its start (tolerance {self.jump_tolerance_m} m)"
            )
        earliest = self.end_tick(now_tick)
        if cmd.appends:
            start_tick = earliest
        else:
            start_tick = self.tick_of(cmd.start_ns)
            if start_tick < earliest:
                early_ms = (earliest - start_tick) * EXECUTION_PERIOD_S * 1e3
                raise MoveRejectedError(
                    f"{tag}: start {cmd.start_ns} ns is {early_ms:.0f} ms before the end of the queued moves "
                    "/ the current drive time (use start 0 to append)"
                )
        queued = QueuedMove(cmd, move, start_tick, start_tick + move_ticks(move.duration_s), sender)
        self._append(queued)
        return queued

    def submit(self, cmd: MoveCommand, now_tick: int, sender: bytes = b"") -> QueuedMove:
        """Validate ``cmd`` and queue it; raises :class:`MoveRejectedError` with the reason."""
        return self.enqueue(cmd, self.validate(cmd), now_tick, sender)

    def drop_sender(self, sender: bytes, now_tick: int) -> list[QueuedMove]:
        """Remove the moves of ``sender`` that have not started by ``now_tick`` and every move queued
        after the first of them; returns the removed moves (a running move is kept)."""
        for i, q in enumerate(self._queue):
            if q.sender == sender and q.start_tick >= now_tick:
                dropped = []
                while len(self._queue) > i:
                    dropped.append(self._removed(self._queue.pop()))
                return dropped[::-1]
        return []

    def quick_stop(
        self, tick: int, sender: bytes = b"", force_fraction: float = QUICK_STOP_FORCE
    ) -> StopOutcome:
        """Abandon the queue at ``tick`` (before its setpoint): drop the moves that have not started and
        replace the running one by the fastest stop from its state at this tick (:func:`stop_profile`
        with ``force_fraction`` of the force limit) — unless the running move itself reaches rest
        sooner and no farther, which then runs to its end."""
        running = None
        if self._queue and self._head_started and self._queue[0].start_tick < tick:
            running = self._removed(self._queue.popleft())
        dropped = list(self._queue)
        self._queue.clear()
        self._knots = 0
        if running is None:
            self._head_started = False
            return StopOutcome(tick, None, None, dropped, None, 0.0)
        s = running.move.sample((tick - running.start_tick) * EXECUTION_PERIOD_S)
        x, v = float(s.position_m), float(s.velocity_m_s)
        profile = stop_profile(x, v, self.params, force_fraction)
        left_s = (running.end_tick - tick) * EXECUTION_PERIOD_S
        if profile.time_s >= left_s or profile.distance_m > abs(running.move.x1_m - x):
            self._append(running)
            return StopOutcome(tick, None, running, dropped, None, v)
        traj = profile.trajectory
        knots = Knots.of(traj)
        cmd = MoveCommand(
            0, self.axis, STOP_MOVE_ID, APPEND, SAMPLED_LAW, traj.x0_m, traj.x1_m, traj.duration_s, knots
        )
        braking = QueuedMove(cmd, traj, tick, tick + move_ticks(traj.duration_s), sender, profile)
        self._append(braking)
        self._head_started = True  # it continues the running move's course at this very tick
        return StopOutcome(tick, running, None, dropped, braking, v)

    def abandon(self, tick: int, hold_position_m: float) -> tuple[QueuedMove | None, list[QueuedMove]]:
        """Empty the queue at ``tick`` because the drive stopped following (a fault): the running move
        (None if none ran) and the moves that had not started; from now on hold ``hold_position_m``
        (where the drive measured the axis). Called again when the drive follows again, it only moves
        the hold position there."""
        running = None
        if self._queue and self._head_started and self._queue[0].start_tick < tick:
            running = self._removed(self._queue.popleft())
        dropped = [self._removed(q) for q in self._queue]
        self._queue.clear()
        self._head_started = False
        self._hold_m = hold_position_m
        return running, dropped

    def advance(self, tick: int) -> QueueStep:
        """The setpoint of ``tick`` (non-decreasing ticks): the active move's sample, or hold; with the
        moves that ended (their end tick reached) and the move that started at this tick."""
        finished = []
        while self._queue and tick >= self._queue[0].end_tick:
            done = self._removed(self._queue.popleft())
            self._hold_m = done.move.x1_m
            if done.stop is None:
                self.completed += 1
            finished.append(done)
        if finished:
            self._head_started = False
        if not self._queue or tick < self._queue[0].start_tick:
            return QueueStep(Setpoint(self._hold_m, 0.0, 0.0, 0.0), None, tuple(finished), self._held())
        q = self._queue[0]
        started = None
        if not self._head_started:
            self._head_started = True
            started = q
        block = self._block
        if block is None or block.queued is not q or not block.first <= tick < block.stop:
            block = self._block = _SetpointBlock(q, tick, self.params)
        i = tick - block.first
        return QueueStep(block.setpoints[i], started, tuple(finished), block.motor[i])

    def _held(self) -> tuple[float, float, float]:
        """The motor joint of the hold setpoint (at rest: the angle, zero speed and torque)."""
        if self._hold_motor is None or self._hold_motor[0] != self._hold_m:
            held = Setpoint(self._hold_m, 0.0, 0.0, 0.0).to_sample(0, "", self.params)
            motor = (held.motor_angle_rad, held.motor_speed_rad_s, held.motor_torque_nm)
            self._hold_motor = (self._hold_m, motor)
        return self._hold_motor[1]

    def setpoint(self, tick: int) -> Setpoint:
        """The setpoint of ``tick`` (see :meth:`advance`)."""
        return self.advance(tick).setpoint
