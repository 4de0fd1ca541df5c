"""The recorder: every Zenoh key matching an expression into one (or several, split) MCAP files.

Hot path. The subscriber hands samples to a Zenoh FIFO channel (filled on Zenoh's thread; when full
it applies back-pressure instead of dropping). The recording thread waits in the channel's blocking
receive while it is empty, so a sample is taken the moment it arrives (a waker thread puts an empty
sample on a key of the recorded expression, delivered only inside this session, at least every
0.1 s and as soon as ``stop`` is set, and the loop drops it unrecorded). It drains the channel and,
per sample, writes the payload bytes exactly as received (no decode, no re-encode) to the channel of
topic ``/`` + key, with ``log_time`` = the time of writing and ``publish_time``/``sequence`` from the
sender's attachment (:mod:`~axisflow.acquisition.wire.attachment`). A channel and its ``ros2msg``
schema are registered the first time a key appears; the type comes from the sample's
``application/cdr;<type>`` encoding.

Joining. The subscriber is declared once the routes from the publishers on the recorded keys are
proven (:class:`~axisflow.acquisition.bus.readiness.JoinedSubscriber`): from then on the recorder is
*ready* (``ready`` is set, ``on_ready`` called, the liveliness token
:func:`~axisflow.acquisition.wire.keys.recorder_token` declared) and misses nothing an axisflow
publisher sends.

Crash safety. About once a second (``flush_interval_s``) the open chunk goes to the writer thread,
which writes and fsyncs it while receiving goes on (a slow disk does not hold up the subscriber), so a
SIGKILL loses at most the last second and what the disk had not taken yet; the file on disk stays
readable by a streaming read and ``axisflow recover`` rebuilds it into a complete one.
SIGINT/SIGTERM (set ``stop``): one hello proves that what the publishers sent before it has arrived,
the channel is drained, then the summary and footer are written: nothing sent before the stop is lost.

Splitting: with ``split_bytes`` or ``split_duration_s`` the recording rolls over to
``<stem>_0000.mcap``, ``<stem>_0001.mcap``, … at the first flush past the limit.

Counting. Per topic: messages, first/last log time, and messages missed: the gaps in the sequence
numbers of each publisher (key, publisher id), and what no gap shows — the numbers a publisher sent
before the first message that arrived (its number in the answer to the join's last hello says where
the recorder's due begins) and after the last one (a closing publisher says its last number with its
receipt query, a running one in its answer to the stop's hello): recorded + dropped + missed is what
the publishers sent. A publisher that never said its last number (killed, or its link lost) is
counted as *untold*. Publish→write latency in a histogram.
"""

from __future__ import annotations

import logging
import os
import socket
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import zenoh

from ..bus.publisher import mcap_encoding_of
from ..bus.readiness import HELLO_TIMEOUT_S, HelloRound, JoinedSubscriber, JoinReport
from ..bus.session import check_key_expression
from ..errors import RecordingError
from ..histogram import DurationHistogram, DurationStats
from ..wire.attachment import unpack_attachment
from ..wire.keys import key_within, recorder_token, topic_for_key
from ..wire.last_sequences import LastSequence, LastSequences
from ..wire.sequence import SequenceTracker
from .recorder_config import (
    LIVE_STAMP_WINDOW_NS,
    RecorderConfig,
    check_outputs,
    split_path,
)
from .recording_writer import LOSS_METADATA, RecordingWriter

log = logging.getLogger(__name__)

_IDLE_SLEEP_S = 0.0005
"""how long the loop sleeps when the channel is empty and it has no waker (see :class:`_Waker`)"""
_WAKE_PERIOD_S = 0.1
"""the longest the loop waits in its blocking receive (it then looks at the clock: flush, deadline)"""
_DRAIN_BATCH = 256
"""samples written before the loop looks at the clock again"""


@dataclass
class TopicStats:
    topic: str
    messages: int = 0
    first_log_ns: int = 0
    last_log_ns: int = 0
    dropped: int = 0
    """messages received and not written: the writer's backlog was full (see RecorderConfig)"""
    sequences: SequenceTracker = field(default_factory=SequenceTracker)
    """per publisher id: its sequence numbers' span, gaps and duplicates (a sender that restarts is a
    new publisher: its sequence starts again at 1)"""

    @property
    def missed(self) -> int:
        """messages lost on the way (from the sequence numbers: gaps, and the heads and tails the
        publishers' own numbers reveal)"""
        return self.sequences.missed

    @property
    def duration_s(self) -> float:
        return (self.last_log_ns - self.first_log_ns) * 1e-9

    @property
    def rate_hz(self) -> float | None:
        """messages per second over the topic's span; None for a span under 1 s (a burst, not a rate)"""
        return (self.messages - 1) / self.duration_s if self.duration_s >= 1.0 else None


@dataclass
class RecordSummary:
    keys: str = ""
    """the key expression recorded"""
    files: list[Path] = field(default_factory=list)
    topics: dict[str, TopicStats] = field(default_factory=dict)
    wall_time_s: float = 0.0
    latency: DurationStats | None = None
    """publish (attachment stamp) → write [µs]"""
    stale_stamps: int = 0
    """messages whose stamp was more than LIVE_STAMP_WINDOW_NS from the wall clock (not in latency)"""
    joined: JoinReport | None = None
    """how the subscriber joined (the publishers whose routes were proven)"""

    @property
    def messages(self) -> int:
        return sum(t.messages for t in self.topics.values())

    @property
    def missed(self) -> int:
        return sum(t.missed for t in self.topics.values())

    @property
    def dropped(self) -> int:
        return sum(t.dropped for t in self.topics.values())

    @property
    def untold(self) -> int:
        """publishers that never said their last number: a loss after their last message is not known"""
        return sum(t.sequences.untold for t in self.topics.values())

    def format(self) -> str:
        lines = [
            f"recorded {self.messages} messages on {len(self.topics)} topics in {self.wall_time_s:.3f} s "
            f"to {', '.join(str(f) for f in self.files) or 'no file'}; missed {self.missed}",
            f"  {'topic':<40} {'messages':>9} {'duration s':>10} {'rate Hz':>9} {'missed':>7}",
        ]
        for t in sorted(self.topics.values(), key=lambda t: t.topic):
            rate = "–" if t.rate_hz is None else f"{t.rate_hz:.1f}"
            lines.append(f"  {t.topic:<40} {t.messages:>9} {t.duration_s:>10.3f} {rate:>9} {t.missed:>7}")
        ordered = sorted(self.topics.values(), key=lambda t: t.topic)
        if self.dropped:
            lines.append(
                f"  dropped {self.dropped} messages, the writer's backlog being full: "
                + ", ".join(f"{t.topic} {t.dropped}" for t in ordered if t.dropped)
            )
        for t in sorted(self.topics.values(), key=lambda t: t.topic):
            publishers = t.sequences.publishers.values()
            if len(publishers) > 1:
                spans = ", then ".join(f"seq {p.first}–{p.last}" for p in publishers)
                lines.append(
                    f"  {t.topic}: {len(publishers)} publishers one after the other ({spans}): its sender "
                    "restarted; the stamps show the gap"
                )
            if t.sequences.duplicates:
                lines.append(f"  {t.topic}: {t.sequences.duplicates} messages repeated or out of order")
        if self.untold:
            lines.append(
                f"  {self.untold} publishers did not say their last sequence number (killed, or their link "
                "lost): a loss after their last recorded message is not counted"
            )
        if not self.files:
            lines.append("  stopped before the recording began: no file written")
        elif not self.topics:
            lines.append(
                f"  no message matched {self.keys}: is a publisher running, and reachable with the "
                "--connect/--listen endpoints given?"
            )
        if self.stale_stamps:
            lines.append(
                f"  publish→write latency: n/a (stamps not live: {self.stale_stamps} of {self.messages} "
                f"more than {LIVE_STAMP_WINDOW_NS * 1e-9:g} s from the wall clock, e.g. a replay)"
            )
        elif self.latency is not None and self.latency.count:
            lines.append(
                f"  publish→write latency: p50 {self.latency.p50_us:.0f} µs, p99 {self.latency.p99_us:.0f} µs"
            )
        return "\n".join(lines)

    def to_dict(self) -> dict[str, object]:
        return {
            "files": [str(f) for f in self.files],
            "messages": self.messages,
            "missed": self.missed,
            "dropped": self.dropped,
            "untold_publishers": self.untold,
            "wall_time_s": self.wall_time_s,
            "latency": self.latency.to_dict() if self.latency and not self.stale_stamps else None,
            "stale_stamps": self.stale_stamps,
            "topics": {
                t.topic: {
                    "messages": t.messages,
                    "missed": t.missed,
                    "dropped": t.dropped,
                    "duration_s": t.duration_s,
                    "rate_hz": t.rate_hz,
                    "duplicates": t.sequences.duplicates,
                    "publishers": [
                        {
                            "id": gid.hex(),
                            "first_sequence": p.first,
                            "last_sequence": p.last,
                            "messages": p.messages,
                            "missed": p.missed,
                            "gaps": p.gaps,
                            "head": p.head,
                            "tail": p.tail,
                            "said_last_sequence": p.said or None,
                        }
                        for gid, p in t.sequences.publishers.items()
                    ],
                }
                for t in self.topics.values()
            },
        }


class _Waker:
    """Wakes the recording loop out of its blocking receive: an empty sample on ``key`` (a key the
    subscription matches), put so that only this session delivers it (it never leaves the process),
    every :data:`_WAKE_PERIOD_S`, at ``deadline`` (monotonic) and as soon as ``stop`` is set."""

    def __init__(
        self, session: zenoh.Session, key: str, stop: threading.Event, deadline: float | None
    ) -> None:
        self._stop = stop
        self._deadline = deadline
        self._done = threading.Event()
        self._pub = session.declare_publisher(key, allowed_destination=zenoh.Locality.SESSION_LOCAL)
        self._thread = threading.Thread(target=self._run, name="recorder-waker", daemon=True)
        self._thread.start()

    @staticmethod
    def key_for(expression: str) -> str | None:
        """The waker's key for a subscription on ``expression``: one it matches and no publisher uses;
        None for an expression without a wildcard (its only key is the data's)."""
        key = key_within(expression, "_axisflow_recorder_wake")
        return key if key != expression and zenoh.KeyExpr(expression).includes(zenoh.KeyExpr(key)) else None

    def _run(self) -> None:
        while not self._done.is_set():
            wait = _WAKE_PERIOD_S
            left = None if self._deadline is None else self._deadline - time.monotonic()
            if left is not None and 0.0 < left < wait:
                wait = left
            stopped = self._stop.wait(wait)
            if self._done.is_set():
                return
            self._pub.put(b"")
            if stopped:  # the loop does not wait again after a stop
                return

    def close(self) -> None:
        self._done.set()
        self._thread.join()
        self._pub.undeclare()


class Recorder:
    """Records ``config.keys`` from a session until stopped (see the module docstring)."""

    def __init__(self, config: RecorderConfig) -> None:
        """Checks the key expression and the outputs (:func:`check_outputs`) before anything is opened: a
        bad expression must not leave an empty recording behind."""
        check_key_expression(config.keys)
        check_outputs(config)
        self.config = config
        self.summary = RecordSummary(keys=config.keys)
        self._split = config.split_bytes is not None or config.split_duration_s is not None
        self._file_index = 0
        self._writer: RecordingWriter | None = None
        self._file_started = 0.0
        self._latency = DurationHistogram()
        self._routes: dict[str, tuple[int, TopicStats]] = {}
        """per key of the open file: its channel id and its counts"""
        self._reported_drops = 0
        self._wake_key: str | None = None
        self._owed_from: dict[tuple[str, bytes], int] = {}
        """per (key, publisher id) that answered the join's last hello: its first number owed"""
        self._said: dict[tuple[str, bytes], int] = {}
        """per (key, publisher id): the last number it said it sent (filled on Zenoh's thread)"""
        self._said_lock = threading.Lock()
        self.ready = threading.Event()
        """set once the subscriber has joined: nothing published from then on is missed"""

    def _open_next(self) -> RecordingWriter:
        path = split_path(self.config.output, self._file_index) if self._split else self.config.output
        self._file_index += 1
        try:
            c = self.config
            writer = RecordingWriter(path, c.compression, c.chunk_size, c.backlog_bytes)
        except OSError as exc:  # e.g. no room for the chunk-index spill file
            raise RecordingError(f"cannot start {path}: {exc.strerror or exc}") from None
        self.summary.files.append(path)
        self._file_started = time.monotonic()
        self._routes.clear()  # channel ids are the new file's
        return writer

    def _on_counts(self, counts: LastSequences) -> None:
        """A closing publisher's last numbers (on Zenoh's thread): kept for :meth:`_count_the_untold`."""
        recorded = zenoh.KeyExpr(self.config.keys)
        with self._said_lock:
            for p in counts.publishers:
                if recorded.includes(zenoh.KeyExpr(p.key)):
                    where = (p.key, p.publisher_id)
                    self._said[where] = max(self._said.get(where, 0), p.sequence)

    def _heard(self, round_: HelloRound | None) -> None:
        """The last numbers the publishers had when they answered the stop's hello."""
        if round_ is not None:
            heard = tuple(LastSequence(h.key, h.publisher, h.sequence) for h in round_.hellos)
            self._on_counts(LastSequences(heard))

    def _count_the_untold(self) -> None:
        """Once the stream has ended: the numbers owed before each publisher's first message and after
        its last (:meth:`SequenceTracker.expect`, :meth:`SequenceTracker.said`)."""
        with self._said_lock:
            said = dict(self._said)
        for (key, gid), first in self._owed_from.items():
            self._stats_of(key).sequences.expect(gid, first)
        for (key, gid), last in said.items():
            self._stats_of(key).sequences.said(gid, last)

    def _stats_of(self, key: str) -> TopicStats:
        topic = topic_for_key(key)
        stats = self.summary.topics.get(topic)
        if stats is None:  # nothing of it arrived
            stats = self.summary.topics[topic] = TopicStats(topic)
        return stats

    def _finish_file(self) -> None:
        """Finish the open file, with the loss of this recording so far in its metadata."""
        assert self._writer is not None
        self._writer.finish({t.topic: t.missed for t in self.summary.topics.values() if t.missed})

    def _maybe_split(self) -> None:
        c = self.config
        assert self._writer is not None
        too_big = c.split_bytes is not None and self._writer.bytes_written >= c.split_bytes
        too_long = (
            c.split_duration_s is not None and time.monotonic() - self._file_started >= c.split_duration_s
        )
        if too_big or too_long:
            self._finish_file()
            self._writer = self._open_next()

    def _report_drops(self) -> None:
        """Say (at most once a flush interval) that messages were dropped since the last time."""
        dropped = self.summary.dropped
        if dropped > self._reported_drops:
            by_topic = ", ".join(f"{t.topic} {t.dropped}" for t in self.summary.topics.values() if t.dropped)
            log.warning(
                "the writer's backlog is full (%d MB): %d messages dropped since the last report, %d in all "
                "(%s); they are counted in the recording's metadata %s",
                self.config.backlog_bytes // 2**20, dropped - self._reported_drops, dropped, by_topic,
                LOSS_METADATA,
            )  # fmt: skip
            self._reported_drops = dropped

    def _route(self, sample: zenoh.Sample, now: int) -> tuple[int, TopicStats]:
        """The channel and the counts of a key seen for the first time in this file."""
        assert self._writer is not None
        key = str(sample.key_expr)
        topic = topic_for_key(key)
        message_encoding, type_name = mcap_encoding_of(sample.encoding)
        channel_id = self._writer.channel_for(topic, type_name, message_encoding)
        stats = self.summary.topics.get(topic)
        if stats is None:
            stats = self.summary.topics[topic] = TopicStats(topic, first_log_ns=now)
        self._routes[key] = (channel_id, stats)
        return channel_id, stats

    def _drain(self, sub: zenoh.Subscriber, limit: int, first: zenoh.Sample | None = None) -> int:
        """Write ``first`` and up to ``limit`` samples waiting in the channel in all; returns how many
        were taken. Per sample: the payload bytes exactly as received (no decode, no re-encode),
        ``log_time`` = now, the attachment's stamp and sequence number; a sample the writer's backlog
        has no room for is dropped and counted; the waker's samples are dropped unrecorded."""
        writer, routes, latency, recv = self._writer, self._routes, self._latency, sub.try_recv
        assert writer is not None
        n = 0
        sample = first if first is not None else recv()
        while sample is not None:
            n += 1
            now = time.time_ns()
            key = str(sample.key_expr)
            route = routes.get(key)
            if route is None:
                if key == self._wake_key:
                    sample = recv() if n < limit else None
                    continue
                route = self._route(sample, now)
            channel_id, stats = route
            att = sample.attachment
            parsed = unpack_attachment(att.to_bytes()) if att is not None else None
            if parsed is not None:
                seq, stamp, gid = parsed
                stats.sequences.add(gid, seq)
                if -LIVE_STAMP_WINDOW_NS <= now - stamp <= LIVE_STAMP_WINDOW_NS:
                    latency.add_ns(now - stamp)
                else:
                    self.summary.stale_stamps += 1
            else:
                seq, stamp = 0, now
            if writer.add(channel_id, now, stamp, seq, sample.payload.to_bytes()):
                stats.messages += 1
                stats.last_log_ns = now
            else:
                stats.dropped += 1
            sample = recv() if n < limit else None
        return n

    def run(
        self,
        session: zenoh.Session,
        stop: threading.Event | None = None,
        on_ready: Callable[[], None] | None = None,
    ) -> RecordSummary:
        """Record until ``stop`` is set or ``duration_s`` has passed; returns the summary.
        ``on_ready`` is called once the subscriber has joined (see the module docstring)."""
        stop = stop or threading.Event()
        c = self.config
        t0 = time.monotonic()
        failure: OSError | None = None
        handler = lambda: zenoh.handlers.FifoChannel(c.queue_capacity)  # noqa: E731
        # joined before the file is created: a recorder that cannot join leaves no file behind
        token = recorder_token(socket.gethostname(), os.getpid())
        with JoinedSubscriber(
            session, c.keys, handler, c.join_timeout_s or HELLO_TIMEOUT_S, stop, token, self._on_counts
        ) as joined:
            if joined.subscriber is None or joined.report is None:  # stopped before it was ready
                self.summary.wall_time_s = time.monotonic() - t0
                return self.summary
            self.summary.joined = joined.report
            self._owed_from = {(h.key, h.publisher_id): h.sequence + 1 for h in joined.report.after.hellos}
            self._writer = self._open_next()
            try:
                self.ready.set()
                if on_ready is not None:
                    on_ready()
                self._record(session, joined, stop, time.monotonic())
            except OSError as exc:  # a full disk, a file system gone read-only
                failure = exc
            finally:
                self._count_the_untold()
                try:
                    self._finish_file()
                except OSError as exc:
                    failure = failure or exc
                self.summary.wall_time_s = time.monotonic() - t0
                self.summary.latency = self._latency.stats()
        if failure is not None:
            path = self._writer.path
            raise RecordingError(
                f"writing {path} failed: {failure.strerror or failure}; what was flushed before is on disk "
                f"(`axisflow recover {path}` rebuilds it into a complete file)"
            )
        return self.summary

    def _record(
        self, session: zenoh.Session, joined: JoinedSubscriber, stop: threading.Event, started: float
    ) -> None:
        """The recording loop: drain, write, flush every ``flush_interval_s``, wait in the channel's
        blocking receive while it is empty, until stopped; then one hello (draining meanwhile) and what
        the channel still holds of the time before it."""
        c = self.config
        sub = joined.subscriber
        assert sub is not None and self._writer is not None
        deadline = None if c.duration_s is None else started + c.duration_s
        next_flush = started + c.flush_interval_s
        self._wake_key = _Waker.key_for(c.keys)
        waker = None if self._wake_key is None else _Waker(session, self._wake_key, stop, deadline)
        try:
            while True:
                written = self._drain(sub, _DRAIN_BATCH)
                now = time.monotonic()
                if now >= next_flush:
                    self._writer.flush(wait=False)  # the writer thread fsyncs; receiving goes on
                    next_flush = now + c.flush_interval_s
                    self._report_drops()
                    if self._split:
                        self._maybe_split()
                if stop.is_set() or (deadline is not None and now >= deadline):
                    self._heard(joined.flush(while_waiting=lambda: self._drain(sub, _DRAIN_BATCH)))
                    # everything sent before the hello is in the channel now, behind at most its capacity
                    # (a bridge at speed 0 refills it as fast as it is drained: take no more than that)
                    self._drain(sub, c.queue_capacity)
                    return
                if written:
                    continue
                if waker is not None:
                    self._drain(sub, _DRAIN_BATCH, sub.recv())  # until a sample comes, or the waker's
                else:  # a subscription on one key: nothing to wake the receive with
                    time.sleep(_IDLE_SLEEP_S)
        finally:
            if waker is not None:
                waker.close()
