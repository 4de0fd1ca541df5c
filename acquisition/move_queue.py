"""The drive's queue of moves: validation on arrival, one setpoint per 1 ms tick.

A move (:class:`~axisflow.acquisition.messages.MoveCommand`) is accepted only if

* its law is known and its numbers are finite with duration > 0 s;
* both end positions lie in [0, L] (the polynomial laws do not overshoot their end points);
* it starts where the axis will be when it starts: |start_position_m − x_end| ≤ ``jump_tolerance_m``,
  with x_end the end position of the last queued move (or the held position) — no jumps;
* its velocity and motor torque stay within v_max and tau_max at the 1 kHz execution samples
  (:func:`axisflow.model.check_limits` with the nominal parameters);
* its start (if not "append") is not before the end of the moves already queued.

Rejections raise :class:`~axisflow.acquisition.errors.MoveRejectedError` with the reason.

Timing: tick k is the drive time ``t0 + k·1 ms``. An appended move starts at the end tick of the
previous one (whose sample is the previous end point at rest, equal to this move's start point), or at
the current tick if the queue is empty: no idle tick between queued moves. A move spanning T seconds
ends at tick ``start + ceil(T / 1 ms)``. With no move active the axis holds the last position.
Moves are whole trajectories, so a move that was accepted always runs to its end even if its sender
disappears; the axis then holds, at rest, within [0, L].
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

from ..model import AxisflowError, AxisParams, Move, cart_force, check_limits, polynomial_law
from .drive import DRIVE_PERIOD_NS, Setpoint
from .errors import MoveRejectedError
from .messages import MoveCommand

DEFAULT_JUMP_TOLERANCE_M = 1e-4
_DT_S = DRIVE_PERIOD_NS * 1e-9


@dataclass(frozen=True)
class QueuedMove:
    command: MoveCommand
    move: Move
    start_tick: int
    end_tick: int
    """first tick after the move's last in-motion sample: the move's end point at rest"""


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
        self.params = params
        self.axis = axis
        self.jump_tolerance_m = jump_tolerance_m
        self._start_ns = start_stamp_ns
        self._queue: deque[QueuedMove] = deque()
        self._hold_m = hold_position_m
        self.completed = 0

    def __len__(self) -> int:
        return len(self._queue)

    @property
    def end_position_m(self) -> float:
        """Where the axis will rest after the queued moves."""
        return self._queue[-1].move.x1_m if self._queue else self._hold_m

    def end_tick(self, now_tick: int) -> int:
        return max(self._queue[-1].end_tick, now_tick) if self._queue else now_tick

    def tick_of(self, stamp_ns: int) -> int:
        return math.ceil((stamp_ns - self._start_ns) / DRIVE_PERIOD_NS)

    def submit(self, cmd: MoveCommand, now_tick: int) -> QueuedMove:
        """Validate ``cmd`` and queue it; raises :class:`MoveRejectedError` with the reason."""
        p = self.params
        tag = f"move {cmd.move_id}"
        if self.axis and cmd.axis and cmd.axis != self.axis:
            raise MoveRejectedError(f"{tag}: addressed to axis {cmd.axis!r}, this drive is {self.axis!r}")
        try:
            law = polynomial_law(cmd.law)
            move = Move(cmd.start_position_m, cmd.end_position_m, cmd.duration_s, law)
        except AxisflowError as exc:
            raise MoveRejectedError(f"{tag}: {exc}") from None
        for name, x in (("start_position_m", move.x0_m), ("end_position_m", move.x1_m)):
            if not 0.0 <= x <= p.L:
                raise MoveRejectedError(f"{tag}: {name} = {x} m is outside the stroke [0, {p.L}] m")
        x_end = self.end_position_m
        jump = abs(move.x0_m - x_end)
        if jump > self.jump_tolerance_m:
            raise MoveRejectedError(
                f"{tag}: start_position_m = {move.x0_m} m jumps {jump:.6g} m from the axis's position "
                f"{x_end} m at its start (tolerance {self.jump_tolerance_m} m)"
            )
        report = check_limits(move, p)
        if report.velocity_violation > 0.0:
            raise MoveRejectedError(
                f"{tag}: peak velocity {report.peak_velocity_m_s:.6g} m/s exceeds v_max = {p.v_max} m/s"
            )
        if report.torque_violation > 0.0:
            raise MoveRejectedError(
                f"{tag}: peak motor torque {report.peak_torque_nm:.6g} N·m exceeds tau_max = {p.tau_max} N·m"
            )
        earliest = self.end_tick(now_tick)
        if cmd.appends:
            start_tick = earliest
        else:
            start_tick = self.tick_of(cmd.start_ns)
            if start_tick < earliest:
                raise MoveRejectedError(
                    f"{tag}: start {cmd.start_ns} ns is {(earliest - start_tick) * _DT_S * 1e3:.0f} ms "
                    "before "
                    f"the end of the queued moves / the current drive time (use start 0 to append)"
                )
        n_ticks = math.ceil(cmd.duration_s / _DT_S - 1e-9)
        queued = QueuedMove(cmd, move, start_tick, start_tick + n_ticks)
        self._queue.append(queued)
        return queued

    def setpoint(self, tick: int) -> Setpoint:
        """The setpoint of ``tick`` (non-decreasing ticks): the active move's sample, or hold."""
        while self._queue and tick >= self._queue[0].end_tick:
            done = self._queue.popleft()
            self._hold_m = done.move.x1_m
            self.completed += 1
        if not self._queue or tick < self._queue[0].start_tick:
            return Setpoint(self._hold_m, 0.0, 0.0, 0.0)
        q = self._queue[0]
        s = q.move.sample((tick - q.start_tick) * _DT_S)
        v = float(s.velocity_m_s)
        a = float(s.acceleration_m_s2)
        return Setpoint(float(s.position_m), v, a, float(cart_force(v, a, self.params)))
