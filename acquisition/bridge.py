"""The drive bridge: a 1 kHz loop between a :class:`~axisflow.acquisition.drive.Drive` and Zenoh.

Each tick k (drive time ``t0 + k·1 ms``) the bridge

While it runs it holds the liveliness token ``<prefix>/<axis>/alive`` so senders can find it.

1. takes the moves that arrived on ``<prefix>/<axis>/trajectory`` (a Zenoh FIFO channel filled on
   Zenoh's thread) and validates/queues them (:class:`~axisflow.acquisition.move_queue.MoveQueue`);
   each accepted or rejected move is logged and published on ``<prefix>/<axis>/event``;
2. reads the drive's sample and publishes it on ``state``;
3. computes the setpoint of tick k, publishes it on ``setpoint`` and applies it to the drive.

Pacing: at ``speed`` > 0 tick k starts at ``start + k·1 ms / speed`` on the monotonic clock (a late
tick runs at once; the schedule does not drift); at ``speed`` 0 ticks run back to back and telemetry
publishers block when the consumers are full ("as fast as the consumers allow"). The stamps are drive
time and always advance by exactly 1 ms. The periods between tick starts are kept in a histogram;
their deviation from the nominal period is the jitter reported on exit.
"""

from __future__ import annotations

import logging
import threading
import time
from dataclasses import dataclass, field

import zenoh

from ..model import AxisParams
from .attachment import unpack_attachment
from .drive import DRIVE_PERIOD_NS, Drive
from .errors import AcquisitionError
from .histogram import DurationHistogram, DurationStats
from .keys import AxisKeys
from .messages import JOINT_STATE_TYPE, STRING_TYPE, BridgeEvent, MoveCommand
from .move_queue import DEFAULT_JUMP_TOLERANCE_M, MoveQueue
from .publisher import SequencedPublisher, Traffic, wait_for_subscribers

log = logging.getLogger(__name__)

TRAJECTORY_QUEUE_CAPACITY = 1024
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
            f"{self.moves_rejected} rejected, {self.moves_missed} missed",
        ]
        if self.period_jitter is not None and self.period_jitter.count:
            j = self.period_jitter
            lines.append(
                f"  period jitter: p50 {j.p50_us:.0f} µs, p99 {j.p99_us:.0f} µs, max {j.max_us:.0f} µs "
                f"over {j.count} periods"
            )
        return "\n".join(lines)


class _SequenceTracker:
    """Counts sequence-number gaps per publisher id."""

    def __init__(self) -> None:
        self._last: dict[bytes, int] = {}
        self.missed = 0

    def see(self, attachment: bytes | None) -> None:
        parsed = unpack_attachment(attachment) if attachment is not None else None
        if parsed is None:
            return
        seq, _stamp, gid = parsed
        last = self._last.get(gid)
        if last is not None and seq > last + 1:
            self.missed += seq - last - 1
        self._last[gid] = seq


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
    first = drive.read()
    queue = MoveQueue(params, first.position_m, first.stamp_ns, keys.axis, config.jump_tolerance_m)
    n_ticks = None if config.duration_s is None else round(config.duration_s * 1e9 / DRIVE_PERIOD_NS)
    tracker = _SequenceTracker()
    jitter = DurationHistogram()
    with (
        session.declare_subscriber(
            keys.trajectory, zenoh.handlers.FifoChannel(TRAJECTORY_QUEUE_CAPACITY)
        ) as moves_in,
        SequencedPublisher(session, keys.state, JOINT_STATE_TYPE, telemetry) as state_pub,
        SequencedPublisher(session, keys.setpoint, JOINT_STATE_TYPE, telemetry) as setpoint_pub,
        SequencedPublisher(session, keys.event, STRING_TYPE, Traffic.COMMAND) as event_pub,
        session.liveliness().declare_token(keys.alive),
    ):
        if config.wait_subscribers_s > 0 and not wait_for_subscribers([state_pub], config.wait_subscribers_s):
            log.warning(
                "no subscriber on %s after %.1f s; starting anyway", keys.state, config.wait_subscribers_s
            )

        def event(text: str) -> None:
            event_pub.put(BridgeEvent(text).encode())

        nominal_ns = DRIVE_PERIOD_NS / config.speed if config.speed > 0 else 0.0
        t_start = time.monotonic_ns()
        prev = t_start
        tick = 0
        while not stop.is_set() and (n_ticks is None or tick < n_ticks):
            if config.speed > 0:
                deadline = t_start + int(tick * nominal_ns)
                now = time.monotonic_ns()
                if deadline - now > _SLEEP_MARGIN_NS:
                    time.sleep((deadline - now - _SLEEP_MARGIN_NS) * 1e-9)
                while (now := time.monotonic_ns()) < deadline:
                    pass
                if tick:
                    jitter.add_ns(abs(now - prev - int(nominal_ns)))
                prev = now
            while (sample_in := moves_in.try_recv()) is not None:
                tracker.see(sample_in.attachment.to_bytes() if sample_in.attachment is not None else None)
                try:
                    cmd = MoveCommand.decode(sample_in.payload.to_bytes())
                    queued = queue.submit(cmd, tick)
                except AcquisitionError as exc:
                    report.moves_rejected += 1
                    report.rejections.append(str(exc))
                    log.warning("rejected: %s", exc)
                    event(f"rejected {exc}")
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
            tick += 1
        report.ticks = tick
        report.wall_time_s = (time.monotonic_ns() - t_start) * 1e-9
        report.moves_completed = queue.completed
        report.moves_missed = tracker.missed
        report.period_jitter = jitter.stats() if config.speed > 0 else None
    return report
