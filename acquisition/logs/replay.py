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

The recording is read through the log reader (:func:`.reader.iter_recording`): a file cut off by a
crash up to its last complete chunk; a chunk that cannot be read is skipped, named in the report with
the messages it held, and the replay goes on with the next one. ``progress`` hears how far it is
about once every :data:`PROGRESS_INTERVAL_S`.
"""

from __future__ import annotations

import itertools
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import zenoh

from ..bus.publisher import SequencedPublisher, Traffic, confirm_delivered, wait_for_subscribers
from ..bus.session import check_key_expression
from ..errors import AcquisitionError, RecordingError
from ..wire.keys import key_for_topic
from ..wire.messages import MOVE_TYPE
from .reader import McapFile, SkippedChunk, iter_recording
from .reader.messages import skipped_summary, why_nothing

PROGRESS_INTERVAL_S = 2.0
"""wall time between two calls of ``progress`` [s]"""


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
    skipped_chunks: tuple[SkippedChunk, ...] = ()
    """chunks of the recording that could not be read (their messages were not replayed)"""

    def format(self) -> str:
        text = (
            f"replayed {self.messages} messages on {self.topics} keys: {self.recorded_span_s:.3f} s "
            f"of recording in {self.wall_time_s:.3f} s"
        )
        if self.skipped_moves:
            text += f"; skipped {self.skipped_moves} moves (commands to a drive are never replayed)"
        if self.skipped_keys:
            text += f"; skipped {self.skipped_keys} messages on keys outside --keys (or no Zenoh keys)"
        if self.skipped_chunks:
            text += "; " + skipped_summary(self.skipped_chunks, lost="not replayed")
        return text


@dataclass(frozen=True)
class ReplayProgress:
    """How far a replay is."""

    messages: int
    """messages published so far"""
    replayed_s: float
    """recorded time replayed so far [s]"""
    recorded_span_s: float | None
    """the recording's span [s], from its summary (None: it has none)"""
    skipped_chunks: int

    def format(self) -> str:
        total = f" of {self.recorded_span_s:.1f}" if self.recorded_span_s is not None else ""
        skipped = f", {self.skipped_chunks} unreadable chunk(s) skipped" if self.skipped_chunks else ""
        return f"replayed {self.messages} messages, {self.replayed_s:.1f}{total} s of the recording{skipped}"


def recorded_span_s(path: str | Path) -> float | None:
    """The span of a recording's messages [s], from its summary's statistics (None: it has none)."""
    with McapFile.open(path) as file:
        stats = file.summary.statistics if file.summary is not None else None
    if stats is None or not stats.message_count:
        return None
    return (stats.message_end_time - stats.message_start_time) * 1e-9


def replay(
    session: zenoh.Session,
    path: str | Path,
    speed: float = 1.0,
    stop: threading.Event | None = None,
    wait_subscribers_s: float = 0.0,
    keys: str = "**",
    progress: Callable[[ReplayProgress], None] | None = None,
) -> ReplayReport:
    """Publish the messages of ``path`` (complete, truncated, or with chunks that cannot be read)
    back over Zenoh; a file with no readable message is a :class:`RecordingError` (nothing to replay
    is not a replay)."""
    if not speed >= 0.0:
        raise AcquisitionError(f"replay speed = {speed} must be >= 0 (0 = as fast as possible)")
    if not wait_subscribers_s >= 0.0:
        raise AcquisitionError(f"replay wait for subscribers = {wait_subscribers_s} s must be >= 0 s")
    wanted = check_key_expression(keys)
    skipped: list[SkippedChunk] = []
    records = iter_recording(path, on_skip=skipped.append)
    first_record = next(records, None)
    if first_record is None:
        raise RecordingError(f"{path} holds no complete message to replay ({why_nothing(skipped)})")
    span_s = recorded_span_s(path) if progress is not None else None
    next_progress = time.monotonic()
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
            if progress is not None and time.monotonic() >= next_progress:
                next_progress = time.monotonic() + PROGRESS_INTERVAL_S
                progress(ReplayProgress(n, (last_t - first_t) * 1e-9, span_s, len(skipped)))
    finally:
        # what put accepted may still wait to be sent: closing the session would drop it
        confirm_delivered(session, publishers.values())
        for pub in publishers.values():
            pub.undeclare()
    return ReplayReport(
        n,
        len(publishers),
        (time.monotonic_ns() - t0) * 1e-9,
        (last_t - first_t) * 1e-9,
        skipped_moves,
        skipped_keys,
        tuple(skipped),
    )
