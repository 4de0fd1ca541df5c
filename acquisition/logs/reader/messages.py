"""The middle layer of reading a log: records → typed messages. Schemas and channels (from the
summary, then from the records as they come), the message records of the channels wanted, a chunk at
a time and in file order, with their raw payloads; chunks that cannot be read are skipped and said.

:class:`MessageScan` walks a file (:class:`~.framing.McapFile`) and yields, in file order, a
:class:`MessageBatch` per chunk (or batch of messages outside chunks) holding messages of the selected
channels — the decompressed records, the offsets of those messages and their checked 31-byte heads —
and a :class:`SkippedChunk` for each chunk that cannot be read and may have held some. Chunks whose
message index names none of the selected channels are not decompressed.

On top of it: :func:`list_topics` (:class:`TopicInfo` with message counts), :func:`read_messages`
(one topic's payloads as :class:`RawMessage`) and :func:`iter_recording` (every message as a
:class:`RecordedMessage`, for replay and recover). A skipped chunk is handed to ``on_skip`` when the
caller gives one, else issued as a :class:`~axisflow.acquisition.errors.DamagedLogWarning` (one line:
the file, the chunk, its byte offset, the reason and what was lost) once the read has succeeded.
"""

from __future__ import annotations

import warnings
from collections import Counter
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import zstandard
from mcap.opcode import Opcode
from mcap.records import Channel, Message, Schema
from mcap.summary import Summary

from ...errors import DamagedLogWarning, RecordingError
from ...wire.messages import JOINT_STATE_TYPE
from .framing import (
    MESSAGE_FIELDS_SIZE,
    MESSAGE_HEAD_SIZE,
    RECORD_PREFIX,
    ChunkContents,
    ChunkError,
    ChunkRef,
    DamagedChunk,
    LooseRecord,
    McapFile,
    message_heads,
    parse_definition,
    walk_chunk,
)

LOOSE_BATCH_BYTES = 4 << 20
"""messages outside chunks are handed on in batches of this many bytes"""


# ---- what a file holds -------------------------------------------------------------------------------


@dataclass(frozen=True)
class TopicInfo:
    """One topic of a file (channels with the same topic, schema and encoding are merged)."""

    topic: str
    schema_name: str
    """e.g. ``sensor_msgs/msg/JointState``; "" for a channel without schema"""
    schema_encoding: str
    """e.g. ``ros2msg``; "" without schema"""
    message_encoding: str
    """e.g. ``cdr``"""
    message_count: int | None
    """messages in the file (up to the truncation), or None when the summary has no statistics"""

    @property
    def is_joint_state(self) -> bool:
        """True for a topic :func:`~.columns.read_joint_states` reads (ROS 2 CDR JointState)."""
        return self.schema_name == JOINT_STATE_TYPE and self.message_encoding == "cdr"


class Catalog:
    """Schemas and channels known so far (from the summary, then from the records as they come)."""

    def __init__(self, summary: Summary | None) -> None:
        self.schemas: dict[int, Schema] = dict(summary.schemas) if summary else {}
        self.channels: dict[int, Channel] = dict(summary.channels) if summary else {}
        self.version = 0
        """grows with every schema or channel learnt"""

    def add(self, record: Schema | Channel) -> None:
        table: dict = self.schemas if isinstance(record, Schema) else self.channels
        if record.id not in table:
            table[record.id] = record
            self.version += 1

    def knows(self, channel_ids: Iterable[int]) -> bool:
        return all(cid in self.channels for cid in channel_ids)

    def schema_of(self, channel: Channel) -> Schema | None:
        return self.schemas.get(channel.schema_id)

    def topics(self, counts: dict[int, int] | None) -> list[TopicInfo]:
        merged: dict[tuple[str, str, str, str], int | None] = {}
        for cid, channel in self.channels.items():
            schema = self.schema_of(channel)
            key = (
                channel.topic,
                schema.name if schema else "",
                schema.encoding if schema else "",
                channel.message_encoding,
            )
            count = None if counts is None else counts.get(cid, 0)
            previous = merged.get(key, 0)
            merged[key] = None if count is None or previous is None else previous + count
        return [TopicInfo(*key, count) for key, count in sorted(merged.items())]


class Selection:
    """The channels a scan hands on: those of ``topic`` (None: every channel) among the channels
    learnt so far, each passed to ``check`` once (which raises if the channel cannot be read as
    wanted), recomputed only when the catalog grew."""

    def __init__(
        self, catalog: Catalog, topic: str | None, check: Callable[[Channel], None] | None = None
    ) -> None:
        self.catalog, self.topic, self.check = catalog, topic, check
        self._wanted: set[int] = set()
        self._version = -1

    def wanted_ids(self) -> set[int]:
        if self._version != self.catalog.version:
            self._version = self.catalog.version
            for cid, channel in self.catalog.channels.items():
                if cid not in self._wanted and (self.topic is None or channel.topic == self.topic):
                    if self.check is not None:
                        self.check(channel)
                    self._wanted.add(cid)
        return self._wanted

    @property
    def name(self) -> str:
        """What is selected, for messages: the topic, or "every topic"."""
        return self.topic if self.topic is not None else "every topic"


# ---- what a scan yields ------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class MessageBatch:
    """Message records of the selected channels in one buffer (a decompressed chunk, or messages
    outside chunks): ``offsets`` (int64, ascending) of the records in ``buffer`` and their checked
    heads (:data:`~.framing.MESSAGE_HEAD`), in file order."""

    buffer: bytes
    offsets: np.ndarray
    heads: np.ndarray
    where: str
    """where the records are, for messages: "FILE: chunk 3 at byte 1234" """

    def __len__(self) -> int:
        return len(self.offsets)

    def payload_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """(start, end) byte offsets of each message's payload in ``buffer``."""
        starts = self.offsets + MESSAGE_HEAD_SIZE
        return starts, self.offsets + RECORD_PREFIX.size + self.heads["length"].astype(np.int64)


@dataclass(frozen=True)
class SkippedChunk:
    """A chunk that could not be read, skipped by a read of ``of`` (a topic, or every topic)."""

    chunk: DamagedChunk
    messages: int | None
    """messages of ``of`` it held (from its message indexes; None: not known)"""
    of: str

    def describe(self) -> str:
        """One line: the file, the chunk, its byte offset, why, and what was skipped."""
        what = "an unknown number of" if self.messages is None else str(self.messages)
        return (
            f"{self.chunk.describe()}; skipped it: {what} messages of {self.of} "
            f"({self.chunk.span_s:.3f} s of log time)"
        )


SkipHandler = Callable[[SkippedChunk], None]


def warn_skipped(skipped: SkippedChunk) -> None:
    """The default ``on_skip``: a :class:`DamagedLogWarning` with :meth:`SkippedChunk.describe`."""
    warnings.warn(DamagedLogWarning(skipped.describe()), stacklevel=2)


def report_skipped(skipped: Iterable[SkippedChunk], on_skip: SkipHandler | None) -> None:
    """Hand each skipped chunk to ``on_skip`` (None: :func:`warn_skipped`)."""
    for s in skipped:
        (on_skip or warn_skipped)(s)


def skipped_summary(skipped: Iterable[SkippedChunk], lost: str = "lost") -> str:
    """What a pass over a whole file skipped, for its report: "skipped 2 chunk(s) that could not be
    read (4011 messages lost): chunk 3 at byte 1234, chunk 9 at byte 5678" ("" if nothing)."""
    chunks = list(skipped)
    if not chunks:
        return ""
    counts = [s.messages for s in chunks]
    total = "an unknown number of" if None in counts else str(sum(c or 0 for c in counts))
    where = ", ".join(f"chunk {s.chunk.ordinal} at byte {s.chunk.offset}" for s in chunks)
    return f"skipped {len(chunks)} chunk(s) that could not be read ({total} messages {lost}): {where}"


def why_nothing(skipped: Iterable[SkippedChunk]) -> str:
    """Why a pass over a whole file found no message to use, for an error message."""
    chunks = list(skipped)
    if not chunks:
        return "its first chunk was never written"
    first = chunks[0].chunk
    return (
        f"{len(chunks)} chunk(s) could not be read; the first: chunk {first.ordinal} at byte "
        f"{first.offset}: {first.reason}"
    )


def skipped_note(skipped: Iterable[SkippedChunk]) -> str:
    """What a read skipped, as a clause for an error message ("" if nothing)."""
    chunks = list(skipped)
    if not chunks:
        return ""
    first = chunks[0].chunk
    return (
        f" ({len(chunks)} chunk(s) that may have held some could not be read and were skipped; the "
        f"first: chunk {first.ordinal} at byte {first.offset}: {first.reason})"
    )


# ---- the scan ----------------------------------------------------------------------------------------


class MessageScan:
    """Walks a file's records in order (see the module docstring): learns schemas and channels into
    ``catalog``, counts messages per channel (:attr:`counts`), collects every chunk that cannot be
    read (:attr:`damaged`), and yields the selected channels' messages (none without a selection)."""

    def __init__(self, file: McapFile, catalog: Catalog, selection: Selection | None) -> None:
        self.file, self.catalog, self.selection = file, catalog, selection
        self.counts: Counter[int] = Counter()
        self.damaged: list[DamagedChunk] = []
        self._unwalked: list[ChunkRef] = []
        self._walked: set[int] = set()
        """ordinals of the chunks walked record by record"""
        self._loose = bytearray()
        self._loose_offsets: list[int] = []
        self._zstd = zstandard.ZstdDecompressor()

    @property
    def truncated(self) -> bool:
        return self.file.truncated

    def events(self) -> Iterator[MessageBatch | SkippedChunk]:
        """The selected messages, a batch at a time, and the chunks skipped, in file order."""
        for block in self.file.blocks():
            if isinstance(block, ChunkRef):
                yield from self._flush_loose()  # the messages before the chunk come first
                yield from self._chunk(block)
            elif block.opcode == Opcode.MESSAGE:
                yield from self._loose_message(block)
            else:
                self._learn(block)
        yield from self._flush_loose()

    # -- blocks

    def _learn(self, block: LooseRecord) -> None:
        body = block.record[RECORD_PREFIX.size :]
        self.catalog.add(parse_definition(block.opcode, body, f"{self.file.path}: byte {block.offset}"))

    def _wanted(self) -> set[int]:
        return self.selection.wanted_ids() if self.selection is not None else set()

    def _chunk(self, chunk: ChunkRef) -> Iterator[MessageBatch | SkippedChunk]:
        data: bytes | ChunkError | None = None
        if chunk.indexes_complete:
            self.counts.update({cid: len(offsets) for cid, offsets in chunk.indexes.items()})
            offsets_by_channel = chunk.indexes
            if not self.catalog.knows(chunk.indexes):
                data = self._load(chunk)
                if not isinstance(data, ChunkError):
                    contents = self._walk(chunk, data)
                    if isinstance(contents, ChunkError):
                        data = contents
                    else:
                        self._discover(chunk)
        else:  # no (complete) message index: find the messages record by record
            data = self._load(chunk)
            contents = data if isinstance(data, ChunkError) else self._walk(chunk, data)
            if isinstance(contents, ChunkError):
                yield from self._skip(chunk, contents)
                return
            offsets_by_channel = {cid: np.array(o, np.int64) for cid, o in contents.offsets.items()}
            self.counts.update({cid: len(offsets) for cid, offsets in offsets_by_channel.items()})
        wanted = self._wanted() & offsets_by_channel.keys()
        unknown = not self.catalog.knows(offsets_by_channel)
        if wanted or (unknown and self.selection is not None) or isinstance(data, ChunkError):
            if data is None:
                data = self._load(chunk)
            if isinstance(data, ChunkError):
                yield from self._skip(chunk, data)
                return
            if wanted:
                offsets = np.sort(np.concatenate([offsets_by_channel[cid] for cid in wanted]))
                try:
                    heads = message_heads(np.frombuffer(data, np.uint8), offsets, wanted)
                except ChunkError as exc:
                    yield from self._skip(chunk, exc)
                    return
                yield MessageBatch(data, offsets, heads, self._where(chunk))
        chunk.indexes = {}  # done with them; an unwalked chunk is kept only to be walked later
        if chunk.ordinal not in self._walked:
            self._unwalked.append(chunk)

    def _skip(self, chunk: ChunkRef, damage: ChunkError) -> Iterator[SkippedChunk]:
        damaged = chunk.damage(self.file.path, str(damage))
        self.damaged.append(damaged)
        chunk.indexes = {}
        if self.selection is None:
            return
        wanted = self._wanted()
        messages = damaged.messages_of(wanted)
        if damaged.messages is not None and not self.catalog.knows(damaged.messages):
            messages = None  # it held channels never defined elsewhere: some may have been wanted
        if messages != 0:
            yield SkippedChunk(damaged, messages, self.selection.name)

    # -- loading and walking chunks

    def _load(self, chunk: ChunkRef) -> bytes | ChunkError:
        """The chunk's records, or why they cannot be had."""
        try:
            return self.file.load(chunk, self._zstd)
        except ChunkError as exc:
            return exc

    def _walk(self, chunk: ChunkRef, data: bytes) -> ChunkContents | ChunkError:
        """Walk the chunk's records: learn its schemas and channels, find its messages."""
        try:
            contents = walk_chunk(data)
        except ChunkError as exc:
            return exc
        for record in contents.definitions:
            self.catalog.add(record)
        self._walked.add(chunk.ordinal)
        return contents

    def _discover(self, chunk: ChunkRef) -> None:
        """If the chunk's index still names unknown channels, walk the earlier chunks not walked yet
        (a channel record may precede its first message by chunks)."""
        if self.catalog.knows(chunk.indexes):
            return
        for earlier in self._unwalked:
            records = self._load(earlier)
            if not isinstance(records, ChunkError):
                self._walk(earlier, records)
        self._unwalked.clear()

    def _where(self, chunk: ChunkRef) -> str:
        return f"{self.file.path}: chunk {chunk.ordinal} at byte {chunk.record_offset}"

    # -- messages outside chunks

    def _loose_message(self, block: LooseRecord) -> Iterator[MessageBatch]:
        record = block.record
        if len(record) < RECORD_PREFIX.size + MESSAGE_FIELDS_SIZE:
            raise RecordingError(
                f"{self.file.path}: message record at byte {block.offset} is "
                f"{len(record) - RECORD_PREFIX.size} bytes short"
            )
        channel_id = int.from_bytes(record[RECORD_PREFIX.size : RECORD_PREFIX.size + 2], "little")
        self.counts[channel_id] += 1
        if channel_id in self._wanted():
            self._loose_offsets.append(len(self._loose))
            self._loose += record
            if len(self._loose) >= LOOSE_BATCH_BYTES:
                yield from self._flush_loose()

    def _flush_loose(self) -> Iterator[MessageBatch]:
        if not self._loose_offsets:
            return
        buffer = bytes(self._loose)
        offsets = np.array(self._loose_offsets, np.int64)
        self._loose.clear()
        self._loose_offsets.clear()
        where = f"{self.file.path}: messages outside chunks"
        try:
            heads = message_heads(np.frombuffer(buffer, np.uint8), offsets, self._wanted())
        except ChunkError as exc:
            raise RecordingError(f"{where}: {exc}") from None
        yield MessageBatch(buffer, offsets, heads, where)


# ---- reads -------------------------------------------------------------------------------------------


def list_topics(path: str | Path, on_skip: SkipHandler | None = None) -> list[TopicInfo]:
    """The topics of an MCAP file, sorted by name, with their message counts.

    A complete file answers from its summary (counts from its statistics, None without them); a file
    without summary (or cut off by a crash) is scanned, counting messages up to the last complete chunk
    (a chunk that cannot be read and has no message index counts nothing, and is reported).
    Raises :class:`RecordingError` for a missing or non-MCAP file.
    """
    with McapFile.open(path) as file:
        catalog = Catalog(file.summary)
        if file.summary is not None and file.summary.channels:
            stats = file.summary.statistics
            return catalog.topics(dict(stats.channel_message_counts) if stats else None)
        scan = MessageScan(file, catalog, None)
        for _event in scan.events():
            pass
    lost = [SkippedChunk(c, c.messages_of(set(c.messages or ())), "every topic") for c in scan.damaged]
    report_skipped(lost, on_skip)
    return catalog.topics(scan.counts)


@dataclass(frozen=True)
class RawMessage:
    """One message as stored: MCAP times [ns], sequence and the payload bytes (decode with the type's
    ``decode``, e.g. :meth:`~axisflow.acquisition.wire.move_status.MoveStatus.decode`)."""

    log_time_ns: int
    publish_time_ns: int
    sequence: int
    data: bytes


def read_messages(
    path: str | Path, topic: str, type_name: str | None = None, on_skip: SkipHandler | None = None
) -> list[RawMessage]:
    """Every message of ``topic`` as stored, in file order (a complete, summary-less or truncated file;
    chunks that cannot be read are skipped and handed to ``on_skip``, default a warning).

    Chunks whose message index does not name the topic's channel are not decompressed, so a few
    messages (move statuses, plans) are found in a long recording in about the time of one pass over its
    indexes. ``type_name`` (e.g. ``axisflow_msgs/msg/MoveStatus``) makes a topic of another schema an
    error. An absent topic gives an empty list.
    """
    messages: list[RawMessage] = []
    skipped: list[SkippedChunk] = []
    with McapFile.open(path) as file:
        catalog = Catalog(file.summary)

        def check(channel: Channel) -> None:
            schema = catalog.schema_of(channel)
            if type_name is not None and (schema is None or schema.name != type_name):
                found = schema.name if schema is not None else "no schema"
                raise RecordingError(f"{file.path}: topic {topic} is {found}, not {type_name}")

        scan = MessageScan(file, catalog, Selection(catalog, topic, check))
        for event in scan.events():
            if isinstance(event, SkippedChunk):
                skipped.append(event)
                continue
            starts, ends = event.payload_bounds()
            heads, buffer = event.heads, event.buffer
            columns = zip(
                heads["log_time"].tolist(),
                heads["publish_time"].tolist(),
                heads["sequence"].tolist(),
                starts.tolist(),
                ends.tolist(),
                strict=True,
            )
            messages += [RawMessage(log, pub, seq, buffer[a:b]) for log, pub, seq, a, b in columns]
    report_skipped(skipped, on_skip)
    return messages


@dataclass(frozen=True)
class RecordedMessage:
    """One message with its channel and schema (mcap's record classes; the schema None for a channel
    without one)."""

    schema: Schema | None
    channel: Channel
    message: Message


def iter_recording(
    path: str | Path, complete_only: bool = False, on_skip: SkipHandler | None = None
) -> Iterator[RecordedMessage]:
    """Every message of a recording in file order: a complete file, one without summary, one cut off
    by a crash (up to its last complete chunk; with ``complete_only`` such a file is an error). A chunk
    that cannot be read is skipped and handed to ``on_skip`` (default a warning) when met."""
    with McapFile.open(path) as file:
        if complete_only and not file.has_footer:
            raise RecordingError(
                f"recording {file.path} has no summary/footer (run `axisflow recover {file.path}`)"
            )
        catalog = Catalog(file.summary)
        scan = MessageScan(file, catalog, Selection(catalog, None))
        for event in scan.events():
            if isinstance(event, SkippedChunk):
                (on_skip or warn_skipped)(event)
                continue
            starts, ends = event.payload_bounds()
            heads, buffer = event.heads, event.buffer
            for cid, seq, log, pub, a, b in zip(
                heads["channel_id"].tolist(), heads["sequence"].tolist(), heads["log_time"].tolist(),
                heads["publish_time"].tolist(), starts.tolist(), ends.tolist(), strict=True,
            ):  # fmt: skip
                channel = catalog.channels[cid]
                message = Message(
                    channel_id=cid, log_time=log, data=buffer[a:b], publish_time=pub, sequence=seq
                )
                yield RecordedMessage(catalog.schema_of(channel), channel, message)
