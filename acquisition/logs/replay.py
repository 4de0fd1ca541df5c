"""Replaying a recording over Zenoh at its recorded pace.

Each message goes back out on key = its topic without the leading ``/``, with the recorded payload
bytes and encoding ``application/cdr;<schema name>``. Its time is the recorded ``publish_time`` (the
sender's stamp, which keeps the source's pace; the recorder's ``log_time`` where a message has none):
it goes out at ``start + (t − t_first)/speed`` (``speed`` 0: as fast as the consumers allow). The
replay numbers its messages afresh per key (a recorder of the replay counts gaps as usual); the
attachment's source stamp is the recorded ``publish_time``.

Only keys matching ``keys`` are replayed (a topic that is no valid Zenoh key, as other tools may
write, is skipped). Moves (``axisflow_msgs/msg/Move``, the commands sent to a
drive) are never replayed: a recording must not command a live axis. They are counted as skipped.
"""

from __future__ import annotations

import itertools
import threading
import time
from dataclasses import dataclass
from pathlib import Path

import zenoh

from ..bus.publisher import SequencedPublisher, Traffic, wait_for_subscribers
from ..bus.session import check_key_expression
from ..errors import AcquisitionError, RecordingError
from ..wire.keys import key_for_topic
from ..wire.messages import MOVE_TYPE
from .recording import iter_recording


@dataclass(frozen=True)
class ReplayReport:
    messages: int
    topics: int
    wall_time_s: float
    recorded_span_s: float
    skipped_moves: int = 0
    """recorded moves (commands to a drive) that were not replayed"""
    skipped_keys: int = 0
    """messages on keys that do not match the replay's key expression"""

    def format(self) -> str:
        text = (
            f"replayed {self.messages} messages on {self.topics} keys: {self.recorded_span_s:.3f} s "
            f"of recording in {self.wall_time_s:.3f} s"
        )
        if self.skipped_moves:
            text += f"; skipped {self.skipped_moves} moves (commands to a drive are never replayed)"
        if self.skipped_keys:
            text += f"; skipped {self.skipped_keys} messages on keys outside --keys (or no Zenoh keys)"
        return text


def replay(
    session: zenoh.Session,
    path: str | Path,
    speed: float = 1.0,
    stop: threading.Event | None = None,
    wait_subscribers_s: float = 0.0,
    keys: str = "**",
) -> ReplayReport:
    """Publish the messages of ``path`` (complete or truncated) back over Zenoh; a file with no
    complete message is a :class:`RecordingError` (nothing to replay is not a replay)."""
    if not speed >= 0.0:
        raise AcquisitionError(f"replay speed = {speed} must be >= 0 (0 = as fast as possible)")
    if not wait_subscribers_s >= 0.0:
        raise AcquisitionError(f"replay wait for subscribers = {wait_subscribers_s} s must be >= 0 s")
    wanted = check_key_expression(keys)
    records = iter_recording(path)
    first_record = next(records, None)
    if first_record is None:
        raise RecordingError(
            f"{path} holds no complete message to replay (its first chunk was never written)"
        )
    stop = stop or threading.Event()
    traffic = Traffic.BULK if speed == 0 else Traffic.TELEMETRY
    publishers: dict[str, SequencedPublisher] = {}
    matches: dict[str, bool] = {}
    n = skipped_moves = skipped_keys = 0
    first_t = last_t = 0
    t0 = time.monotonic_ns()
    try:
        for rec in itertools.chain([first_record], records):
            if stop.is_set():
                break
            topic = rec.channel.topic
            type_name = rec.schema.name if rec.schema is not None else "unknown"
            if type_name == MOVE_TYPE:
                skipped_moves += 1
                continue
            key = key_for_topic(topic)
            if topic not in matches:
                try:
                    matches[topic] = wanted.intersects(zenoh.KeyExpr(key))
                except zenoh.ZError:  # a topic of another tool that is no Zenoh key (e.g. "/a//b")
                    matches[topic] = False
            if not matches[topic]:
                skipped_keys += 1
                continue
            pub = publishers.get(topic)
            if pub is None:
                pub = publishers[topic] = SequencedPublisher(session, key, type_name, traffic)
            m = rec.message
            t = m.publish_time or m.log_time
            if n == 0:
                first_t = t
                if wait_subscribers_s > 0:
                    wait_for_subscribers([pub], wait_subscribers_s)
                t0 = time.monotonic_ns()
            if speed > 0:
                delay_ns = t0 + int((t - first_t) / speed) - time.monotonic_ns()
                if delay_ns > 0 and stop.wait(delay_ns * 1e-9):
                    break
            pub.put(m.data, m.publish_time)
            last_t = max(last_t, t)
            n += 1
    finally:
        for pub in publishers.values():
            pub.undeclare()
    return ReplayReport(
        n,
        len(publishers),
        (time.monotonic_ns() - t0) * 1e-9,
        (last_t - first_t) * 1e-9,
        skipped_moves,
        skipped_keys,
    )
