"""The drive bridge: a 1 kHz loop between a :class:`~axisflow.acquisition.drives.drive.Drive` and Zenoh.

While it runs, the bridge holds the liveliness token ``<prefix>/<axis>/alive`` so senders can find it,
and watches the move senders' tokens ``<prefix>/<axis>/sender/*``. It declares the token last, after its
subscribers and publishers: a session that sees the token knows the bridge's move subscriber too. A
bridge that finds the token of another one on its axis refuses to start (:class:`AxisTakenError`,
naming where the other runs). Moves arriving on
``<prefix>/<axis>/trajectory`` are decoded and validated off the loop
(:class:`~axisflow.acquisition.bridge.move_intake.MoveIntake`). Each tick k (drive time ``t0 + k·1 ms``),
:meth:`Bridge.step`

1. applies the senders that appeared or disappeared: a sender gone drops its moves that have not
   started (and those queued after them); the running move ends at rest;
2. queues the moves validated since the last tick (:class:`.move_queue.MoveQueue`),
   in arrival order, at most :data:`MOVES_PER_TICK` a tick (a burst is spread over ticks); a move is
   accepted only from a live sender (one whose token has not arrived yet is held up to
   :data:`SENDER_GRACE_S`: the token and the move travel separately);
3. reads the drive's sample and publishes it on ``state`` (a sample the drive lost on the way is
   counted, and nothing is published for it);
4. computes the setpoint of tick k, publishes it on ``setpoint`` (stamped with the tick's drive time)
   and applies it to the drive; once a second of drive time (from tick 0) it publishes what drives the
   axis (:class:`~axisflow.acquisition.wire.drive_info.DriveInfo`) on ``drive``.

Every step of a move's life (accepted, rejected with the reason, started, completed, dropped) is a
typed :class:`~axisflow.acquisition.wire.move_status.MoveStatus` on ``<prefix>/<axis>/event``, published
after the tick's setpoint, at most :data:`STATUSES_PER_TICK` a tick (in order; each names its tick).

A drive that can fault (:mod:`axisflow.acquisition.drives.canopen`) reports events
(:meth:`Drive.events`); each becomes a status of move 0 with the drive's codes. When the drive stops
following setpoints (a fault, comm loss, its own stop) the bridge stops the axis — the running move
STOPPED, the queue DROPPED — refuses moves until a quick stop with ``reset_fault``
(``axisflow stop --reset-fault``) has brought the drive back (ENABLED), and keeps publishing what it
knows: a sample only when the drive measured a new one (:meth:`Drive.status`; none while nothing is
heard from it), a setpoint only when one reaches the drive.

:meth:`Bridge.run` paces the steps: at ``speed`` > 0 tick k starts at ``start + k·1 ms / speed`` on
the monotonic clock (a late tick runs at once; the schedule does not drift); at ``speed`` 0 ticks run
back to back and telemetry publishers block when the consumers are full ("as fast as the consumers
allow"); while nobody subscribes to its state, setpoint or event, it waits (Zenoh's matching
listeners say when someone does) instead of running ticks nobody receives. The stamps are drive time
and always advance by exactly 1 ms; the first sample is read once the publishers are ready (and the
subscribers waited for), so a simulated drive's clock starts with the loop. The periods between tick
starts are kept in a histogram; their deviation from the nominal period is the jitter reported on
exit. Tests drive :meth:`Bridge.step` directly. :func:`run_bridges` paces several bridges in one loop
(one per drive of a bus, each on its own keys), with a hook after each tick (the bus's SYNC).
"""

from __future__ import annotations

import dataclasses
import logging
import threading
import time
from collections import deque
from collections.abc import Callable, Sequence
from contextlib import ExitStack
from dataclasses import dataclass, field
from functools import partial

import zenoh

from ...model import EXECUTION_PERIOD_NS, AxisParams, stop_profile, ticks_to_seconds
from ..bus.publisher import (
    SequencedPublisher,
    Traffic,
    confirm_delivered,
    wait_for_subscribers,
    watch_consumers,
)
from ..bus.readiness import MatchWatch, NotReadyError, say_hello
from ..drives.drive import STOPPING_EVENTS, Drive, DriveEvent, DriveEventKind
from ..errors import AcquisitionError, AxisTakenError, WireError, zenoh_reason
from ..histogram import DurationStats
from ..wire.attachment import unpack_attachment
from ..wire.axis_sample_encoder import AxisSampleEncoder
from ..wire.drive_info import DRIVE_INFO_TYPE, DriveInfo
from ..wire.drive_info import PERIOD_TICKS as DRIVE_INFO_PERIOD
from ..wire.keys import AxisKeys, sender_of_token
from ..wire.messages import JOINT_STATE_TYPE
from ..wire.move_status import MOVE_STATUS_TYPE, NO_TICK, MoveState, MoveStatus
from ..wire.quick_stop import STOP_MOVE_ID, QuickStop
from .move_intake import MoveIntake, ReceivedMove
from .move_queue import DEFAULT_JUMP_TOLERANCE_M, MoveQueue, QueuedMove, validate_move
from .tick_clock import TickClock, TickTiming

log = logging.getLogger(__name__)

AXIS_CHECK_TIMEOUT_S = 2.0
"""how long a starting bridge asks for another bridge's token on its axis, and for its hello [s]"""
CONSUMER_POLL_S = 0.1
"""how often a bridge at speed 0 waiting for a consumer looks at its stop event [s]"""
SENDER_GRACE_S = 0.5
"""how long [s of wall time] a move may wait for its sender's liveliness token to arrive"""
NEXT_MOVE_GRACE_S = 0.25
"""at speed 0, how long [s of wall time] the loop waits at the tick where its last queued move ends,
while a sender is alive, for that sender's next move: a planner that plans while the axis runs ~40×
real time can be a few milliseconds behind the axis, and at speed 0 no clock is owed anything (an
appended move that arrives meanwhile starts at that very tick: no idle tick)"""
MOVES_PER_TICK = 4
"""moves the loop takes per tick from the intake, and from those waiting for their sender's token:
a burst of thousands (valid or not) is spread over ticks instead of stalling one, since each costs a
status message and a log line on the loop (~20–60 µs)"""
STATUSES_PER_TICK = 8
"""move statuses published per tick, after the tick's setpoint; more wait in order for the next ticks
(a sender that vanishes, or a quick stop, can drop a whole queue of 1024 moves at once: their statuses
go out over ~130 ms instead of stalling one tick by ~20 ms). Each carries the tick it happened at."""
MAX_REPORTED_REJECTIONS = 100
"""rejection texts kept in the report (the first ones; all are counted and each has its status)"""
_EVENT_STATES = {
    DriveEventKind.FAULT: MoveState.FAULT,
    DriveEventKind.COMM_LOST: MoveState.COMM_LOST,
    DriveEventKind.DRIVE_STOPPED: MoveState.DRIVE_STOPPED,
    DriveEventKind.WARNING: MoveState.WARNING,
    DriveEventKind.ENABLED: MoveState.ENABLED,
}


@dataclass(frozen=True)
class BridgeConfig:
    keys: AxisKeys
    speed: float = 1.0
    """multiple of real time; 0 = as fast as the consumers allow"""
    duration_s: float | None = None
    """drive time to run [s]; None = until stopped"""
    wait_subscribers_s: float = 0.0
    """before the first tick, wait up to this long for a subscriber on the state key"""
    jump_tolerance_m: float = DEFAULT_JUMP_TOLERANCE_M
    drive: DriveInfo | None = None
    """what drives the axis: published on ``<prefix>/<axis>/drive`` at the start and every
    :data:`DRIVE_INFO_PERIOD`, and named in the report (None: neither)"""
    timing: TickTiming = field(default_factory=TickTiming)
    """the ticking thread's real-time priority and cores (tick_clock.py)"""

    def __post_init__(self) -> None:
        if not self.speed >= 0.0:
            raise AcquisitionError(f"bridge speed = {self.speed} must be >= 0 (0 = as fast as possible)")
        if self.duration_s is not None and not self.duration_s > 0.0:
            raise AcquisitionError(f"bridge duration = {self.duration_s} s must be > 0 s")
        if not self.jump_tolerance_m >= 0.0:
            raise AcquisitionError(f"bridge jump tolerance = {self.jump_tolerance_m} m must be >= 0 m")
        if not self.wait_subscribers_s >= 0.0:
            raise AcquisitionError(
                f"bridge wait for subscribers = {self.wait_subscribers_s} s must be >= 0 s"
            )

    @property
    def ticks(self) -> int | None:
        """Ticks to run (None: until stopped)."""
        return None if self.duration_s is None else round(self.duration_s * 1e9 / EXECUTION_PERIOD_NS)


@dataclass
class BridgeReport:
    """What a bridge run did."""

    ticks: int = 0
    wall_time_s: float = 0.0
    moves_accepted: int = 0
    moves_rejected: int = 0
    moves_completed: int = 0
    moves_dropped: int = 0
    """queued moves dropped because their sender disappeared"""
    moves_missed: int = 0
    """moves lost on the way, from the senders' sequence numbers"""
    quick_stops: int = 0
    stale_ticks: int = 0
    """ticks without a new sample from the drive (lost on the way, the drive silent, or between the
    cycles of a drive on a slower bus): none published for them"""
    drive_faults: int = 0
    """times the drive stopped following setpoints (fault, comm lost, its own stop)"""
    drive: str = ""
    """what drove the axis (:attr:`BridgeConfig.drive`)"""
    period_jitter: DurationStats | None = None
    """|tick-start period − 1 ms/speed| [µs]; None at speed 0"""
    late_ticks: int = 0
    """ticks that started more than a whole period after their deadline (at speed > 0)"""
    tick_lateness: DurationStats | None = None
    """tick start − its deadline [µs]; None at speed 0"""
    rejections: list[str] = field(default_factory=list)

    def summary(self) -> str:
        lines = [
            f"bridge: {self.ticks} ticks ({ticks_to_seconds(self.ticks):.3f} s of drive time) "
            f"in {self.wall_time_s:.3f} s" + (f"; drive: {self.drive}" if self.drive else ""),
            f"  moves: {self.moves_accepted} accepted, {self.moves_completed} completed, "
            f"{self.moves_rejected} rejected, {self.moves_dropped} dropped, {self.moves_missed} missed",
        ]
        if self.stale_ticks:
            lines.append(f"  ticks without a new sample from the drive: {self.stale_ticks} of {self.ticks}")
        if self.drive_faults:
            lines.append(f"  drive: stopped following {self.drive_faults} time(s) (see the event key)")
        if self.period_jitter is not None and self.period_jitter.count:
            j = self.period_jitter
            lines.append(
                f"  period jitter: p50 {j.p50_us:.0f} µs, p99 {j.p99_us:.0f} µs, max {j.max_us:.0f} µs "
                f"over {j.count} periods; {self.late_ticks} ticks late by more than a period"
            )
        if self.tick_lateness is not None and self.tick_lateness.count:
            t = self.tick_lateness
            lines.append(
                f"  tick start after its deadline: p50 {t.p50_us:.0f} µs, p99 {t.p99_us:.0f} µs, "
                f"max {t.max_us:.0f} µs"
            )
        return "\n".join(lines)

    def to_dict(self) -> dict[str, object]:
        return {
            "ticks": self.ticks,
            "wall_time_s": self.wall_time_s,
            "moves_accepted": self.moves_accepted,
            "moves_rejected": self.moves_rejected,
            "moves_completed": self.moves_completed,
            "moves_dropped": self.moves_dropped,
            "moves_missed": self.moves_missed,
            "quick_stops": self.quick_stops,
            "stale_ticks": self.stale_ticks,
            "drive_faults": self.drive_faults,
            "drive": self.drive,
            "period_jitter": self.period_jitter.to_dict() if self.period_jitter else None,
            "late_ticks": self.late_ticks,
            "tick_lateness": self.tick_lateness.to_dict() if self.tick_lateness else None,
            "rejections": self.rejections,
        }


class _RateLimitedLog:
    """At most ``per_second`` log lines a second, then one line saying how many were left out: a flood
    of bad moves must not make the loop write thousands of lines (a stderr pipe nobody reads would
    block it once full)."""

    def __init__(self, logger: logging.Logger, per_second: int) -> None:
        self._log, self._per_second = logger, per_second
        self._window = -1
        self._count = self._skipped = 0

    def warning(self, text: str) -> None:
        window = int(time.monotonic())
        if window != self._window:
            if self._skipped:
                self._log.warning(
                    "… and %d more rejections in that second (each has its move status)", self._skipped
                )
            self._window, self._count, self._skipped = window, 0, 0
        self._count += 1
        if self._count <= self._per_second:
            self._log.warning("%s", text)
        else:
            self._skipped += 1


class Bridge:
    """The bridge of one axis (a context manager: entering declares everything on the session and
    reads the first sample; leaving rejects the moves still waiting and undeclares)."""

    def __init__(
        self, session: zenoh.Session, drive: Drive, params: AxisParams, config: BridgeConfig
    ) -> None:
        self.session = session
        self.drive = drive
        self.params = params
        self.config = config
        self.keys = config.keys
        self.report = BridgeReport(drive=config.drive.describe() if config.drive is not None else "")
        self.tick = 0
        """the next tick to run"""
        self._stack = ExitStack()
        self._alive: set[bytes] = set()
        self._gone: set[bytes] = set()
        self._pending: deque[tuple[ReceivedMove, float]] = deque()
        self._reject_log = _RateLimitedLog(log, per_second=10)
        self._outbox: deque[MoveStatus] = deque()
        """statuses not published yet (at most STATUSES_PER_TICK go out per tick)"""
        self._queue: MoveQueue | None = None
        self._drive_down: str | None = None
        """why the drive follows no setpoints (None: it follows); moves are refused meanwhile"""
        self._reset_sender = ""
        """the hex id of whoever asked for the running fault reset (its answer carries it)"""
        self._encoder = AxisSampleEncoder(self.keys.axis)
        self._consumers: MatchWatch | None = None
        """at speed 0: whether anyone subscribes to the state, setpoint or event"""

    # ---- set-up and tear-down ---------------------------------------------------------------------
    def __enter__(self) -> Bridge:
        keys, session, stack = self.keys, self.session, self._stack
        telemetry = Traffic.BULK if self.config.speed == 0 else Traffic.TELEMETRY
        self._refuse_a_taken_axis()
        try:
            validate = partial(validate_move, params=self.params, axis=keys.axis)
            self._intake = stack.enter_context(MoveIntake(session, keys.trajectory, validate))
            self._tokens = stack.enter_context(
                session.liveliness().declare_subscriber(
                    keys.senders, zenoh.handlers.FifoChannel(256), history=True
                )
            )
            self._state_pub = stack.enter_context(
                SequencedPublisher(session, keys.state, JOINT_STATE_TYPE, telemetry)
            )
            self._setpoint_pub = stack.enter_context(
                SequencedPublisher(session, keys.setpoint, JOINT_STATE_TYPE, telemetry)
            )
            self._status_pub = stack.enter_context(
                SequencedPublisher(session, keys.event, MOVE_STATUS_TYPE, Traffic.COMMAND)
            )
            self._stops = stack.enter_context(
                session.declare_subscriber(keys.stop, zenoh.handlers.FifoChannel(64))
            )
            self._drive_pub = (
                stack.enter_context(SequencedPublisher(session, keys.drive, DRIVE_INFO_TYPE, Traffic.COMMAND))
                if self.config.drive is not None
                else None
            )
            if self.config.speed == 0:
                self._consumers = stack.enter_context(
                    watch_consumers([self._state_pub, self._setpoint_pub, self._status_pub])
                )
            stack.enter_context(session.liveliness().declare_token(keys.alive))  # last: see the docstring
        except BaseException:
            stack.close()
            raise
        wait = self.config.wait_subscribers_s
        if wait > 0 and not wait_for_subscribers([self._state_pub], wait):
            log.warning("no subscriber on %s after %.1f s; starting anyway", keys.state, wait)
        first = self.drive.read()
        self._queue = MoveQueue(
            self.params, first.position_m, self.drive.stamp_ns, keys.axis, self.config.jump_tolerance_m
        )
        return self

    def _refuse_a_taken_axis(self) -> None:
        """An :class:`AxisTakenError` if another bridge holds this axis's token, naming where it runs
        (from its hello, and the endpoint this session reaches it at)."""
        keys = self.keys
        try:
            replies = list(self.session.liveliness().get(keys.alive, timeout=AXIS_CHECK_TIMEOUT_S))
        except zenoh.ZError as exc:
            raise AcquisitionError(
                f"cannot look for another bridge on {keys.alive}: {zenoh_reason(exc)}"
            ) from None
        if not any(r.ok is not None for r in replies):
            return
        try:
            answered = say_hello(self.session, keys.state, AXIS_CHECK_TIMEOUT_S)
            hellos = answered.hellos if answered is not None else ()
        except NotReadyError:
            hellos = ()
        links = {str(link.zid): link.dst for link in self.session.info.links()}
        where = "; ".join(
            f"{h.where}" + (f", reached at {links[h.zid]}" if h.zid in links else "") for h in hellos
        )
        raise AxisTakenError(
            f"axis {keys.axis!r} already has a bridge (it holds {keys.alive}): "
            + (where or f"where it runs is unknown (no answer to a hello on {keys.state})")
            + "; stop it first, or give this bridge another --axis"
        )

    def __exit__(self, *_exc: object) -> None:
        try:
            for received, _deadline in self._pending:  # still waiting for a token
                self._reject(received, "the bridge stopped before its sender's token arrived")
            self._pending.clear()
            self.report.ticks = self.tick
            self.report.moves_missed = self._intake.missed
            if self._queue is not None:
                self.report.moves_completed = self._queue.completed
            self._send_statuses(len(self._outbox))
            # what put accepted may still wait to be sent: closing the session would drop it
            confirm_delivered(self.session, [self._state_pub, self._setpoint_pub, self._status_pub])
        finally:
            self._stack.close()

    @property
    def moves_waiting(self) -> int:
        """Moves received and validated by the intake that no tick has taken yet."""
        return self._intake.waiting

    # ---- one tick ---------------------------------------------------------------------------------
    def step(self) -> None:
        """Run tick :attr:`tick`: senders, new moves, sample, setpoint (see the module docstring)."""
        queue = self._queue
        if queue is None:
            raise AcquisitionError("Bridge.step() needs the bridge entered (use it as a context manager)")
        self._apply_sender_tokens()
        self._take_stops()
        self._take_moves()
        if self.config.speed == 0 and self._running_dry(queue) and self._intake.wait(NEXT_MOVE_GRACE_S):
            self._take_moves()
        sample = self.drive.read()
        status = self.drive.status()
        self._take_drive_events(sample.position_m)
        if status.fresh:
            self._state_pub.put(self._encoder.encode_sample(sample))
        else:
            self.report.stale_ticks += 1
        step = queue.advance(self.tick)
        for done in step.finished:
            if done.stop is not None:
                self._stopped(done)
            else:
                self._status(MoveState.COMPLETED, done, f"completed move {done.command.move_id}")
        if step.started is not None:
            q = step.started
            self._status(MoveState.STARTED, q, f"started move {q.command.move_id}")
        if status.commanded and status.following:
            sp, (angle, speed, torque) = step.setpoint, step.motor  # Setpoint.to_sample's motor joint
            payload = self._encoder.encode(
                self._stamp(), sp.position_m, angle, sp.velocity_m_s, speed, sp.force_ff_n, torque
            )
            self._setpoint_pub.put(payload)
        drive = self.config.drive
        if self._drive_pub is not None and drive is not None and self.tick % DRIVE_INFO_PERIOD == 0:
            info = dataclasses.replace(drive, stamp_ns=self._stamp(), axis=self.keys.axis)
            self._drive_pub.put(info.encode())
        self.drive.apply(step.setpoint)
        self._send_statuses(STATUSES_PER_TICK)
        self.tick += 1

    def _running_dry(self, queue: MoveQueue) -> bool:
        """Whether the last queued move ends at this tick while a sender is alive and nothing waits."""
        return (
            len(queue) > 0
            and queue.end_tick(self.tick) == self.tick
            and bool(self._alive)
            and not self._pending
            and self._intake.waiting == 0
        )

    def _apply_sender_tokens(self) -> None:
        assert self._queue is not None
        while (token := self._tokens.try_recv()) is not None:
            gid = sender_of_token(str(token.key_expr))
            if gid is None:
                continue
            if token.kind == zenoh.SampleKind.PUT:
                self._alive.add(gid)
                self._gone.discard(gid)
                continue
            self._alive.discard(gid)
            self._gone.add(gid)
            dropped = self._queue.drop_sender(gid, self.tick)
            self._dropped(
                dropped,
                f"sender {gid.hex()} disappeared (its moves that had not started, and every move queued "
                "after the first of them, are dropped)",
            )
            if dropped:
                log.warning("sender %s disappeared: dropped %d queued moves", gid.hex(), len(dropped))

    def _take_moves(self) -> None:
        """Queue the moves validated since the last tick, in arrival order, at most
        :data:`MOVES_PER_TICK` a tick (the rest wait for the next ticks); a move whose sender's token
        has not arrived yet waits for it (the token and the move travel separately), at most
        :data:`SENDER_GRACE_S`."""
        assert self._queue is not None
        for received in self._intake.poll(MOVES_PER_TICK):
            if received.error:
                self._reject(received, received.error)
            else:
                self._pending.append((received, time.monotonic() + SENDER_GRACE_S))
        for _ in range(MOVES_PER_TICK):
            if not self._pending:
                break
            received, deadline = self._pending[0]
            sender = received.sender
            if sender not in self._alive:
                if sender not in self._gone and time.monotonic() < deadline:
                    break
                self._pending.popleft()
                self._reject(
                    received,
                    f"its sender holds no liveliness token {self.keys.senders} (send moves with MoveSender "
                    "and keep it open while they run)",
                )
                continue
            self._pending.popleft()
            cmd, move = received.command, received.move
            assert cmd is not None and move is not None
            if self._drive_down is not None:
                self._reject(received, self._refusal())
                continue
            try:
                queued = self._queue.enqueue(cmd, move, self.tick, sender)
            except AcquisitionError as exc:
                self._reject(received, str(exc))
                continue
            self.report.moves_accepted += 1
            log.info("accepted move %d: ticks %d..%d", cmd.move_id, queued.start_tick, queued.end_tick)
            self._status(
                MoveState.ACCEPTED,
                queued,
                f"accepted move {cmd.move_id}: start tick {queued.start_tick}, end tick {queued.end_tick}",
            )

    def _take_stops(self) -> None:
        """Quick stops requested since the last tick (each answered with statuses, see quick_stop.py)."""
        assert self._queue is not None
        while (sample := self._stops.try_recv()) is not None:
            att = sample.attachment
            parsed = unpack_attachment(att.to_bytes()) if att is not None else None
            sender = parsed[2] if parsed is not None else b""
            try:
                request = QuickStop.decode(sample.payload.to_bytes())
                reason, reset = request.reason, request.reset_fault
            except WireError as exc:
                reason, reset = f"(undecodable request: {exc})", False
            self.report.quick_stops += 1
            log.warning("quick stop at tick %d: %s", self.tick, reason or "no reason given")
            for received, _deadline in self._pending:
                self._reject(received, "a quick stop was requested before it was queued")
            self._pending.clear()
            if self._drive_down is not None:
                why = f"quick stop: the drive follows no setpoints ({self._drive_down}); it stops on its own"
                self._axis_status(MoveState.STOPPED, sender.hex(), why)
                if reset:
                    self._reset_fault(sender)
                continue
            outcome = self._queue.quick_stop(self.tick, sender)
            self._dropped(outcome.dropped, "quick stop")
            if outcome.interrupted is not None:
                q = outcome.interrupted
                self._status(
                    MoveState.STOPPED,
                    q,
                    f"stopped move {q.command.move_id} at {outcome.speed_m_s:+.4g} m/s: quick stop",
                )
            if outcome.braking is None:
                ends = outcome.kept.end_tick if outcome.kept is not None else self.tick
                text = (
                    f"quick stop: move {outcome.kept.command.move_id} reaches rest sooner on its own course "
                    f"(at tick {ends}, {outcome.kept.move.x1_m:.6g} m)"
                    if outcome.kept is not None
                    else "quick stop: the axis was at rest"
                )
                self._publish(MoveStatus(self._stamp(), self.keys.axis, MoveState.STOPPED, STOP_MOVE_ID,
                                         self.tick, self.tick, ends, sender.hex(), text))  # fmt: skip
            if reset:
                self._reset_fault(sender)

    # ---- the drive's events ----------------------------------------------------------------------------
    def _take_drive_events(self, position_m: float) -> None:
        """The drive's events since the last tick, as statuses of move 0; a stopping one stops the axis
        (the queue abandoned where the drive measured it), an enabled one lets moves in again."""
        assert self._queue is not None
        for event in self.drive.events():
            sender = ""
            if event.kind in STOPPING_EVENTS:
                self._drive_stopped(event, position_m)
            elif event.kind is DriveEventKind.ENABLED:
                self._queue.abandon(self.tick, position_m)
                self._drive_down = None
                sender, self._reset_sender = self._reset_sender, ""
                log.warning("%s", event.text)
            else:
                log.warning("%s", event.text)
            if event.kind is DriveEventKind.FAULT and self._reset_sender:
                sender, self._reset_sender = self._reset_sender, ""  # the answer to the reset: it failed
            self._axis_status(_EVENT_STATES[event.kind], sender, event.text, event)

    def _drive_stopped(self, event: DriveEvent, position_m: float) -> None:
        assert self._queue is not None
        first = self._drive_down is None
        self._drive_down = event.text
        if not first:
            return
        self.report.drive_faults += 1
        log.error("%s: the axis is stopped, moves are refused until the fault is reset", event.text)
        for received, _deadline in self._pending:
            self._reject(received, self._refusal())
        self._pending.clear()
        running, dropped = self._queue.abandon(self.tick, position_m)
        if running is not None:
            self._status(MoveState.STOPPED, running, f"stopped move {running.command.move_id}: {event.text}")
        self._dropped(dropped, event.text)

    def _reset_fault(self, sender: bytes) -> None:
        """A quick stop asked for a fault reset: start it, or answer at once that nothing needs it."""
        if self._drive_down is None:
            self._axis_status(MoveState.ENABLED, sender.hex(), "no fault to reset; the drive follows")
            return
        self._reset_sender = sender.hex()
        log.warning("fault reset requested at tick %d", self.tick)
        self.drive.reset_fault()

    def _refusal(self) -> str:
        return f"the drive follows no setpoints ({self._drive_down}): reset it (axisflow stop --reset-fault)"

    def _axis_status(self, state: MoveState, sender: str, text: str, event: DriveEvent | None = None) -> None:
        """A status of move 0 (about the axis, not a move), with the drive's codes of ``event``."""
        codes = (event.error_code, event.error_register, event.statusword) if event is not None else (0, 0, 0)
        self._publish(MoveStatus(self._stamp(), self.keys.axis, state, STOP_MOVE_ID, self.tick, NO_TICK,
                                 NO_TICK, sender, text, *codes))  # fmt: skip

    def _stopped(self, braking: QueuedMove) -> None:
        """The braking profile of a quick stop has brought the axis to rest."""
        profile = braking.stop
        assert profile is not None
        fastest = stop_profile(braking.move.x0_m, float(braking.move.sample(0.0).velocity_m_s), self.params)
        self._status(
            MoveState.STOPPED,
            braking,
            f"quick stop: at rest at {braking.move.x1_m:.6g} m after {profile.distance_m * 1e3:.2f} mm and "
            f"{profile.time_s * 1e3:.1f} ms (the axis's physical minimum with the nominal parameters: "
            f"{fastest.distance_m * 1e3:.2f} mm, {fastest.time_s * 1e3:.1f} ms)",
        )

    # ---- move status ------------------------------------------------------------------------------
    def _dropped(self, moves: list[QueuedMove], why: str) -> None:
        """A DROPPED status for each of ``moves`` (taken out of the queue), saying ``why``; counted."""
        for q in moves:
            self._status(MoveState.DROPPED, q, f"dropped move {q.command.move_id}: {why}")
        self.report.moves_dropped += len(moves)

    def _status(self, state: MoveState, q: QueuedMove, text: str) -> None:
        self._publish(MoveStatus(self._stamp(), self.keys.axis, state, q.command.move_id, self.tick,
                                 q.start_tick, q.end_tick, q.sender.hex(), text))  # fmt: skip

    def _reject(self, received: ReceivedMove, reason: str) -> None:
        move_id = received.command.move_id if received.command is not None else 0
        text = reason if reason.startswith(f"move {move_id}") else f"move {move_id}: {reason}"
        self.report.moves_rejected += 1
        if len(self.report.rejections) < MAX_REPORTED_REJECTIONS:
            self.report.rejections.append(text)
        self._reject_log.warning(f"rejected {text}")
        self._publish(MoveStatus(self._stamp(), self.keys.axis, MoveState.REJECTED, move_id, self.tick,
                                 NO_TICK, NO_TICK, received.sender.hex(), f"rejected {text}"))  # fmt: skip

    def _stamp(self) -> int:
        assert self._queue is not None
        return self._queue.stamp_of(self.tick)

    def _publish(self, status: MoveStatus) -> None:
        self._outbox.append(status)

    def _send_statuses(self, limit: int) -> None:
        for _ in range(min(limit, len(self._outbox))):
            self._status_pub.put(self._outbox.popleft().encode())

    def wait_for_consumer(self, stop: threading.Event) -> bool:
        """At speed 0, with nobody subscribed to the state, setpoint or event: wait until someone
        is (True) or ``stop`` is set (False). At once True while someone is, or at speed > 0."""
        if self._consumers is None or self._consumers.event.is_set():
            return True
        keys = self.keys
        log.info("nobody subscribes to %s, %s or %s: waiting", keys.state, keys.setpoint, keys.event)
        while not self._consumers.wait(CONSUMER_POLL_S):
            if stop.is_set():
                return False
        log.info("a consumer subscribed: running")
        return True

    # ---- the paced loop ---------------------------------------------------------------------------
    def run(self, stop: threading.Event | None = None) -> BridgeReport:
        """Step at ``speed`` until ``duration_s`` of drive time has passed or ``stop`` is set."""
        return run_bridges([self], stop)[0]


def run_bridges(
    bridges: Sequence[Bridge],
    stop: threading.Event | None = None,
    after_tick: Callable[[], None] | None = None,
) -> list[BridgeReport]:
    """Step every bridge once per tick, then ``after_tick`` (a bus's SYNC), at the first bridge's
    ``speed`` until its ``duration_s`` of drive time has passed or ``stop`` is set."""
    stop = stop or threading.Event()
    config = bridges[0].config
    speed = config.speed
    n_ticks = config.ticks
    t_start = time.monotonic_ns()
    done = 0
    # the deadlines, the thread's priority and the collector's schedule: tick_clock.py
    with TickClock(EXECUTION_PERIOD_NS / speed if speed > 0 else 0.0, stop, config.timing) as clock:
        while not stop.is_set() and (n_ticks is None or done < n_ticks):
            if speed == 0 and not all(b.wait_for_consumer(stop) for b in bridges):
                break
            if speed > 0 and not clock.wait():
                break
            for bridge in bridges:
                bridge.step()
            if after_tick is not None:
                after_tick()
            clock.after_tick()
            done += 1
    wall_s = (time.monotonic_ns() - t_start) * 1e-9
    for bridge in bridges:
        report = bridge.report
        report.ticks = bridge.tick
        report.wall_time_s = wall_s
        report.period_jitter = clock.period_jitter.stats() if speed > 0 else None
        report.tick_lateness = clock.lateness.stats() if speed > 0 else None
        report.late_ticks += clock.late_ticks
    return [b.report for b in bridges]


def run_bridge(
    session: zenoh.Session,
    drive: Drive,
    params: AxisParams,
    config: BridgeConfig,
    stop: threading.Event | None = None,
) -> BridgeReport:
    """Run a :class:`Bridge` until ``duration_s`` of drive time has passed or ``stop`` is set."""
    with Bridge(session, drive, params, config) as bridge:
        bridge.run(stop)
    return bridge.report
