"""The drive bridge: a 1 kHz loop between a :class:`~axisflow.acquisition.drives.drive.Drive` and Zenoh.

While it runs, the bridge holds the liveliness token ``<prefix>/<axis>/alive`` so senders can find it,
and watches the move senders' tokens ``<prefix>/<axis>/sender/*``. It declares the token last, after its
subscribers and publishers: a session that sees the token knows the bridge's move subscriber too. A
bridge that finds the token of another one on its axis refuses to start (:class:`AxisTakenError`,
naming where the other runs). Moves arriving on
``<prefix>/<axis>/trajectory`` are decoded and validated off the loop
(:class:`~axisflow.acquisition.bridge.move_intake.MoveIntake`). Each tick k (drive time ``t0 + k·1 ms``),
:meth:`Bridge.step`

1. applies the senders that appeared or disappeared, the quick stops requested, and queues the moves
   validated since the last tick (:class:`.move_queue.MoveQueue`): :mod:`.admission` decides which
   moves enter the queue and when, :mod:`.supervision` what stops the axis;
2. reads the drive's sample and publishes it on ``state`` (a sample the drive lost on the way is
   counted, and nothing is published for it);
3. computes the setpoint of tick k, publishes it on ``setpoint`` (stamped with the tick's drive time)
   and applies it to the drive; once a second of drive time (from tick 0) it publishes what drives the
   axis (:class:`~axisflow.acquisition.wire.drive_info.DriveInfo`) on ``drive``.

Every step of a move's life (accepted, rejected with the reason, started, completed, dropped) is a
typed :class:`~axisflow.acquisition.wire.move_status.MoveStatus` on ``<prefix>/<axis>/event``, published
after the tick's setpoint, at most :data:`STATUSES_PER_TICK` a tick (in order; each names its tick:
:mod:`.statuses`).

While the drive follows no setpoints (:mod:`.supervision`) the bridge keeps publishing what it knows:
a sample only when the drive measured a new one (:meth:`Drive.status`; none while nothing is heard
from it), a setpoint only when one reaches the drive.

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
from collections.abc import Callable, Sequence
from contextlib import ExitStack
from functools import partial

import zenoh

from ...model import EXECUTION_PERIOD_NS, AxisParams
from ..bus.publisher import (
    SequencedPublisher,
    Traffic,
    confirm_delivered,
    wait_for_subscribers,
    watch_consumers,
)
from ..bus.readiness import MatchWatch, NotReadyError, say_hello
from ..drives.drive import Drive
from ..errors import AcquisitionError, AxisTakenError, zenoh_reason
from ..wire.attachment import unpack_attachment
from ..wire.axis_sample_encoder import AxisSampleEncoder
from ..wire.drive_info import DRIVE_INFO_TYPE
from ..wire.drive_info import PERIOD_TICKS as DRIVE_INFO_PERIOD
from ..wire.keys import sender_of_token
from ..wire.messages import JOINT_STATE_TYPE
from ..wire.move_status import MOVE_STATUS_TYPE, MoveState
from .admission import MoveAdmission
from .config import BridgeConfig
from .move_intake import MoveIntake
from .move_queue import MoveQueue, validate_move
from .report import BridgeReport
from .statuses import StatusOutbox
from .supervision import Supervision
from .tick_clock import TickClock

log = logging.getLogger(__name__)

AXIS_CHECK_TIMEOUT_S = 2.0
"""how long a starting bridge asks for another bridge's token on its axis, and for its hello [s]"""
CONSUMER_POLL_S = 0.1
"""how often a bridge at speed 0 waiting for a consumer looks at its stop event [s]"""
NEXT_MOVE_GRACE_S = 0.25
"""at speed 0, how long [s of wall time] the loop waits at the tick where its last queued move ends,
while a sender is alive, for that sender's next move: a planner that plans while the axis runs ~40×
real time can be a few milliseconds behind the axis, and at speed 0 no clock is owed anything (an
appended move that arrives meanwhile starts at that very tick: no idle tick)"""
STATUSES_PER_TICK = 8
"""move statuses published per tick, after the tick's setpoint; more wait in order for the next ticks
(a sender that vanishes, or a quick stop, can drop a whole queue of 1024 moves at once: their statuses
go out over ~130 ms instead of stalling one tick by ~20 ms). Each carries the tick it happened at."""
__all__ = ["Bridge", "BridgeConfig", "BridgeReport", "run_bridge", "run_bridges"]


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
        self._queue: MoveQueue | None = None
        self._outbox = StatusOutbox(self.keys.axis, self.report, self._stamp_of)
        """statuses not published yet (at most STATUSES_PER_TICK go out per tick)"""
        self._admission: MoveAdmission | None = None
        self._supervision: Supervision | None = None
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
        queue = MoveQueue(
            self.params, first.position_m, self.drive.stamp_ns, keys.axis, self.config.jump_tolerance_m
        )
        self._admission = MoveAdmission(keys, self._intake, queue, self._outbox, self.report)
        self._supervision = Supervision(
            self.drive, self.params, queue, self._admission.reject_pending, self._outbox, self.report
        )
        self._queue = queue
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
            if self._admission is not None:  # still waiting for a token
                self._admission.reject_pending(
                    "the bridge stopped before its sender's token arrived", self.tick
                )
            self.report.ticks = self.tick
            self.report.moves_missed = self._intake.missed
            if self._queue is not None:
                self.report.moves_completed = self._queue.completed
            self._outbox.send(self._status_pub.put, len(self._outbox))
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
        queue, admission, supervision = self._queue, self._admission, self._supervision
        if queue is None or admission is None or supervision is None:
            raise AcquisitionError("Bridge.step() needs the bridge entered (use it as a context manager)")
        tick = self.tick
        self._apply_sender_tokens(admission)
        self._take_stops(supervision)
        admission.take_moves(tick, supervision.refusal())
        if (
            self.config.speed == 0
            and self._running_dry(queue, admission)
            and self._intake.wait(NEXT_MOVE_GRACE_S)
        ):
            admission.take_moves(tick, supervision.refusal())
        sample = self.drive.read()
        status = self.drive.status()
        supervision.take_drive_events(sample.position_m, tick)
        if status.fresh:
            self._state_pub.put(self._encoder.encode_sample(sample))
        else:
            self.report.stale_ticks += 1
        step = queue.advance(tick)
        for done in step.finished:
            if done.stop is not None:
                supervision.stopped(done, tick)
            else:
                self._outbox.move(MoveState.COMPLETED, done, tick, f"completed move {done.command.move_id}")
        if step.started is not None:
            q = step.started
            self._outbox.move(MoveState.STARTED, q, tick, f"started move {q.command.move_id}")
        if status.commanded and status.following:
            sp, (angle, speed, torque) = step.setpoint, step.motor  # Setpoint.to_sample's motor joint
            payload = self._encoder.encode(
                self._stamp_of(tick), sp.position_m, angle, sp.velocity_m_s, speed, sp.force_ff_n, torque
            )
            self._setpoint_pub.put(payload)
        drive = self.config.drive
        if self._drive_pub is not None and drive is not None and tick % DRIVE_INFO_PERIOD == 0:
            info = dataclasses.replace(drive, stamp_ns=self._stamp_of(tick), axis=self.keys.axis)
            self._drive_pub.put(info.encode())
        self.drive.apply(step.setpoint)
        self._outbox.send(self._status_pub.put, STATUSES_PER_TICK)
        self.tick += 1

    def _running_dry(self, queue: MoveQueue, admission: MoveAdmission) -> bool:
        """Whether the last queued move ends at this tick while a sender is alive and nothing waits."""
        return (
            len(queue) > 0
            and queue.end_tick(self.tick) == self.tick
            and bool(admission.alive)
            and not admission.pending
            and self._intake.waiting == 0
        )

    def _apply_sender_tokens(self, admission: MoveAdmission) -> None:
        """The move senders whose liveliness token came or went since the last tick."""
        while (token := self._tokens.try_recv()) is not None:
            gid = sender_of_token(str(token.key_expr))
            if gid is not None:
                admission.sender_token(gid, token.kind == zenoh.SampleKind.PUT, self.tick)

    def _take_stops(self, supervision: Supervision) -> None:
        """Quick stops requested since the last tick, with their senders' ids."""
        while (sample := self._stops.try_recv()) is not None:
            att = sample.attachment
            parsed = unpack_attachment(att.to_bytes()) if att is not None else None
            sender = parsed[2] if parsed is not None else b""
            supervision.quick_stop(sample.payload.to_bytes(), sender, self.tick)

    def _stamp_of(self, tick: int) -> int:
        assert self._queue is not None
        return self._queue.stamp_of(tick)

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
