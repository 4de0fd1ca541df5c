"""The drive bridge: a 1 kHz loop between a :class:`~axisflow.acquisition.drive.Drive` and Zenoh.

While it runs the bridge holds the liveliness token ``<prefix>/<axis>/alive`` so senders can find it,
and watches the move senders' tokens ``<prefix>/<axis>/sender/*``. Moves arriving on
``<prefix>/<axis>/trajectory`` are decoded and validated off the loop
(:class:`~axisflow.acquisition.move_intake.MoveIntake`). Each tick k (drive time ``t0 + k·1 ms``) the
bridge

1. applies the senders that appeared or disappeared: a sender gone drops its moves that have not
   started (and those queued after them); the running move ends at rest;
2. queues the moves validated since the last tick (:class:`~axisflow.acquisition.move_queue.MoveQueue`),
   in arrival order; a move is accepted only from a live sender (one whose token has not arrived yet
   is held up to ``SENDER_GRACE_S``: the token and the move travel separately); each acceptance,
   rejection, completion and drop is logged and published on ``<prefix>/<axis>/event``;
3. reads the drive's sample and publishes it on ``state``;
4. computes the setpoint of tick k, publishes it on ``setpoint`` and applies it to the drive.

Pacing: at ``speed`` > 0 tick k starts at ``start + k·1 ms / speed`` on the monotonic clock (a late
tick runs at once; the schedule does not drift); at ``speed`` 0 ticks run back to back and telemetry
publishers block when the consumers are full ("as fast as the consumers allow"). The stamps are drive
time and always advance by exactly 1 ms; the first sample is read once the publishers are ready (and
the subscribers waited for), so a simulated drive's clock starts with the loop. The periods between
tick starts are kept in a histogram; their deviation from the nominal period is the jitter reported
on exit.
"""

from __future__ import annotations

import logging
import threading
import time
from collections import deque
from dataclasses import dataclass, field
from functools import partial

import zenoh

from ..model import AxisParams
from .drive import DRIVE_PERIOD_NS, Drive
from .errors import AcquisitionError
from .histogram import DurationHistogram, DurationStats
from .keys import AxisKeys, sender_of_token
from .messages import JOINT_STATE_TYPE, STRING_TYPE, BridgeEvent
from .move_intake import MoveIntake, ReceivedMove
from .move_queue import DEFAULT_JUMP_TOLERANCE_M, MoveQueue, validate_move
from .publisher import SequencedPublisher, Traffic, wait_for_subscribers

log = logging.getLogger(__name__)

SENDER_GRACE_S = 0.5
"""how long [s of wall time] a move may wait for its sender's liveliness token to arrive"""
_SLEEP_MARGIN_NS = 80_000  # wake this early and spin the rest: time.sleep overshoots ~50–100 µs


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
    period_jitter: DurationStats | None = None
    """|tick-start period − 1 ms/speed| [µs]; None at speed 0"""
    rejections: list[str] = field(default_factory=list)

    def summary(self) -> str:
        lines = [
            f"bridge: {self.ticks} ticks ({self.ticks / 1000:.3f} s of drive time) "
            f"in {self.wall_time_s:.3f} s",
            f"  moves: {self.moves_accepted} accepted, {self.moves_completed} completed, "
            f"{self.moves_rejected} rejected, {self.moves_dropped} dropped, {self.moves_missed} missed",
        ]
        if self.period_jitter is not None and self.period_jitter.count:
            j = self.period_jitter
            lines.append(
                f"  period jitter: p50 {j.p50_us:.0f} µs, p99 {j.p99_us:.0f} µs, max {j.max_us:.0f} µs "
                f"over {j.count} periods"
            )
        return "\n".join(lines)


def run_bridge(
    session: zenoh.Session,
    drive: Drive,
    params: AxisParams,
    config: BridgeConfig,
    stop: threading.Event | None = None,
) -> BridgeReport:
    """Run the 1 kHz loop until ``duration_s`` of drive time has passed or ``stop`` is set."""
    stop = stop or threading.Event()
    keys = config.keys
    report = BridgeReport()
    telemetry = Traffic.BULK if config.speed == 0 else Traffic.TELEMETRY
    n_ticks = None if config.duration_s is None else round(config.duration_s * 1e9 / DRIVE_PERIOD_NS)
    jitter = DurationHistogram()
    with (
        MoveIntake(session, keys.trajectory, partial(validate_move, params=params, axis=keys.axis)) as intake,
        session.liveliness().declare_subscriber(
            keys.senders, zenoh.handlers.FifoChannel(256), history=True
        ) as sender_tokens,
        SequencedPublisher(session, keys.state, JOINT_STATE_TYPE, telemetry) as state_pub,
        SequencedPublisher(session, keys.setpoint, JOINT_STATE_TYPE, telemetry) as setpoint_pub,
        SequencedPublisher(session, keys.event, STRING_TYPE, Traffic.COMMAND) as event_pub,
        session.liveliness().declare_token(keys.alive),
    ):
        if config.wait_subscribers_s > 0 and not wait_for_subscribers([state_pub], config.wait_subscribers_s):
            log.warning(
                "no subscriber on %s after %.1f s; starting anyway", keys.state, config.wait_subscribers_s
            )
        first = drive.read()
        queue = MoveQueue(params, first.position_m, first.stamp_ns, keys.axis, config.jump_tolerance_m)
        alive: set[bytes] = set()
        gone: set[bytes] = set()
        pending: deque[tuple[ReceivedMove, float]] = deque()

        def event(text: str) -> None:
            event_pub.put(BridgeEvent(text).encode())

        def reject(reason: str) -> None:
            report.moves_rejected += 1
            report.rejections.append(reason)
            log.warning("rejected: %s", reason)
            event(f"rejected {reason}")

        nominal_ns = DRIVE_PERIOD_NS / config.speed if config.speed > 0 else 0.0
        t_start = time.monotonic_ns()
        prev = t_start
        tick = 0
        while not stop.is_set() and (n_ticks is None or tick < n_ticks):
            if config.speed > 0:
                deadline = t_start + int(tick * nominal_ns)
                now = time.monotonic_ns()
                if deadline - now > _SLEEP_MARGIN_NS and stop.wait(
                    (deadline - now - _SLEEP_MARGIN_NS) * 1e-9
                ):
                    break
                while (now := time.monotonic_ns()) < deadline:
                    pass
                if tick:
                    jitter.add_ns(abs(now - prev - int(nominal_ns)))
                prev = now
            while (token := sender_tokens.try_recv()) is not None:
                gid = sender_of_token(str(token.key_expr))
                if gid is None:
                    continue
                if token.kind == zenoh.SampleKind.PUT:
                    alive.add(gid)
                    gone.discard(gid)
                    continue
                alive.discard(gid)
                gone.add(gid)
                dropped = queue.drop_sender(gid, tick)
                if dropped:
                    report.moves_dropped += len(dropped)
                    ids = ", ".join(str(q.command.move_id) for q in dropped)
                    text = (
                        f"dropped moves {ids}: sender {gid.hex()} disappeared (its moves that had not "
                        "started, and every move queued after the first of them)"
                    )
                    log.warning("%s", text)
                    event(text)
            for received in intake.poll():
                if received.error:
                    reject(received.error)
                else:
                    pending.append((received, time.monotonic() + SENDER_GRACE_S))
            # moves in arrival order; one whose sender's token has not arrived yet waits for it (the
            # token and the move travel separately), at most SENDER_GRACE_S
            while pending:
                received, deadline = pending[0]
                cmd, sender = received.command, received.sender
                assert cmd is not None and received.move is not None
                if sender not in alive:
                    if sender not in gone and time.monotonic() < deadline:
                        break
                    pending.popleft()
                    reject(
                        f"move {cmd.move_id}: its sender holds no liveliness token {keys.senders} "
                        "(send moves with MoveSender and keep it open while they run)"
                    )
                    continue
                pending.popleft()
                try:
                    queued = queue.enqueue(cmd, received.move, tick, sender)
                except AcquisitionError as exc:
                    reject(str(exc))
                    continue
                report.moves_accepted += 1
                log.info("accepted move %d: ticks %d..%d", cmd.move_id, queued.start_tick, queued.end_tick)
                event(
                    f"accepted move {cmd.move_id}: start tick {queued.start_tick}, end tick {queued.end_tick}"
                )
            sample = drive.read()
            state_pub.put(sample.encode())
            setpoint = queue.setpoint(tick)
            setpoint_pub.put(setpoint.to_sample(sample.stamp_ns, keys.axis, params).encode())
            drive.apply(setpoint)
            for done in queue.finished:
                event(f"completed move {done.command.move_id} at tick {done.end_tick}")
            queue.finished.clear()
            tick += 1
        for received, _deadline in pending:  # still waiting for a token when the bridge stops
            assert received.command is not None
            reject(f"move {received.command.move_id}: the bridge stopped before its sender's token arrived")
        report.ticks = tick
        report.wall_time_s = (time.monotonic_ns() - t_start) * 1e-9
        report.moves_completed = queue.completed
        report.moves_missed = intake.missed
        report.period_jitter = jitter.stats() if config.speed > 0 else None
    return report
