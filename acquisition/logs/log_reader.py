"""Reading one JointState topic of an MCAP log into numpy columns, fast.

:func:`read_joint_states` returns a topic's ``sensor_msgs/msg/JointState`` messages as a
:class:`JointStateColumns` (stamps, MCAP times and sequence numbers as int64, position/velocity/effort
as float64 arrays of shape (n, joints)); :func:`list_topics` lists what a file holds. Both read
complete files, files without summary, and files cut off by a crash (up to the last complete chunk).

Rows are in **file order** of the topic's messages — the order in which the recorder wrote them, i.e.
arrival order for ``axisflow record`` — and are never sorted: check ``stamp_ns`` if you need it
monotonic.

File layout relied on (MCAP, https://mcap.dev/spec; integers little endian)
-------------------------------------------------------------------------
The file is the 8-byte magic ``89 4D 43 41 50 30 0D 0A`` and a sequence of records, each
``opcode u8, length u64, body[length]``. This module walks those top-level records itself (the framing
is all it needs, and mcap's ``StreamReader`` parses every MessageIndex entry in Python, far too slow
for 7 M entries an hour) and parses Schema and Channel bodies with mcap's record classes:

* **Chunk** (0x06): ``message_start_time u64, message_end_time u64, uncompressed_size u64,
  uncompressed_crc u32, compression (u32 length + UTF-8: "", "zstd" or "lz4"), records_length u64,
  records``; the records, decompressed, are again ``opcode u8, length u64, body`` (Schema, Channel and
  Message records).
* **Message** (0x05), inside a chunk or not: ``channel_id u16, sequence u32, log_time u64,
  publish_time u64, data`` — so a message record has a fixed 31-byte head (opcode, length and those
  four fields) and its payload is ``length − 22`` bytes at record offset 31.
* **MessageIndex** (0x07), written right after its chunk, one per channel present in it (in files cut
  off by a crash too): ``channel_id u16, records_length u32, records_length/16 × (log_time u64,
  offset u64)``, the offset of each of the channel's message records in the decompressed chunk.
* Schema (0x03), Channel (0x04), DataEnd (0x0F), Footer (0x02), the summary records: the summary
  (through mcap's seeking reader) gives channels and per-channel message counts up front when the file
  has one; without it the channels are learnt from the records as they come.

Per chunk: the message index gives the offsets of the wanted channel's records, one numpy gather (or
a strided view, when they are evenly spaced — two topics interleaved at one rate are) gives their
heads. When the records all have the same length and their payloads the same bytes outside the stamp
and the float arrays (frame_id, joint names, sequence counts, padding: see
:mod:`.joint_state_layout`) as the first one, the stamps and arrays are read at fixed offsets for the
whole chunk at once (the *vectorised* path). Anything else — different lengths, big-endian CDR, a
chunk without message index, messages outside chunks — goes through :meth:`JointState.decode` one
message at a time (the *per-message* path); both give identical columns (tested bit for bit).

Memory: the result (3.6 M rows × 2 joints = ~290 MB for an hour) is preallocated from the summary's
message counts (grown when there is none) and filled chunk by chunk; only one decompressed chunk is
held at a time.

Speed (2-core machine, one topic of a synthetic hour: 7.2 M messages of two interleaved topics,
525 MB of zstd chunks): 1.9 s and 365 MB peak RSS vectorised (a third of it decompression); 34 s
per message; the same hour cut off before its summary: 2.0 s.
"""

from __future__ import annotations

import os
import struct
from collections import Counter, defaultdict
from collections.abc import Iterator
from dataclasses import dataclass
from io import BytesIO
from pathlib import Path
from typing import BinaryIO

import lz4.frame
import numpy as np
import zstandard
from mcap.data_stream import ReadDataStream
from mcap.opcode import Opcode
from mcap.records import Channel, Schema
from mcap.summary import Summary

from ..errors import RecordingError, WireError
from ..wire.messages import JOINT_STATE_TYPE, JointState
from .joint_state_layout import DecodedJointStates, JointStateLayout
from .recording import MCAP_MAGIC, check_mcap, read_summary

RECORD_PREFIX = struct.Struct("<BQ")
"""opcode u8, body length u64: the start of every MCAP record"""
MESSAGE_HEAD_SIZE = 31
"""bytes of a Message record before its payload: opcode 1, length 8, channel_id 2, sequence 4,
log_time 8, publish_time 8"""
MESSAGE_FIELDS_SIZE = 22
"""bytes of a Message body before its payload (channel_id, sequence, log_time, publish_time)"""
MESSAGE_HEAD = np.dtype(
    {
        "names": ["opcode", "length", "channel_id", "sequence", "log_time", "publish_time"],
        "formats": ["u1", "<u8", "<u2", "<u4", "<u8", "<u8"],
        "offsets": [0, 1, 9, 11, 15, 23],
        "itemsize": MESSAGE_HEAD_SIZE,
    }
)
"""the 31-byte head of a Message record as a numpy structured dtype"""
_CHUNK_FIXED = struct.Struct("<QQQII")  # start, end, uncompressed_size, crc, compression length
_U64 = struct.Struct("<Q")
_U16 = struct.Struct("<H")
_LOOSE_BATCH_BYTES = 4 << 20
"""messages outside chunks are decoded in batches of this many bytes"""


# ---- results ---------------------------------------------------------------------------------------


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
        """True for a topic :func:`read_joint_states` reads (ROS 2 CDR JointState)."""
        return self.schema_name == JOINT_STATE_TYPE and self.message_encoding == "cdr"


@dataclass(frozen=True)
class JointColumns:
    """One joint of a :class:`JointStateColumns` (views into its arrays, shape (n,)). For the axis
    contract: ``carriage`` in m, m/s, N; ``motor`` in rad, rad/s, N·m."""

    name: str
    stamp_ns: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    effort: np.ndarray


@dataclass(frozen=True, eq=False)
class JointStateColumns:
    """The JointState messages of one topic as columns, rows in file order (not sorted).

    ``stamp_ns`` is the header stamp (ns since the Unix epoch), ``log_time_ns`` and ``publish_time_ns``
    the MCAP record times [ns], ``sequence`` the MCAP record sequence number (the recorder's per-topic
    count mod 2³²) — all int64, shape (n,). ``position``, ``velocity``, ``effort``: float64, shape
    (n, len(joint_names)), column j for joint ``joint_names[j]``; a message that sends an empty array
    (ROS allows it, e.g. no effort) gives NaN there. Every message of the topic names the same joints.
    """

    path: Path
    topic: str
    joint_names: tuple[str, ...]
    frame_ids: tuple[str, ...]
    """the distinct header.frame_id values of the rows, in order of first appearance"""
    stamp_ns: np.ndarray
    log_time_ns: np.ndarray
    publish_time_ns: np.ndarray
    sequence: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    effort: np.ndarray
    truncated: bool
    """True if the file has no footer (a crash): it was read up to its last complete chunk"""
    vectorised_messages: int
    """messages decoded by the vectorised path (before the time filter)"""
    per_message_messages: int
    """messages decoded one by one with :meth:`JointState.decode` (before the time filter)"""

    def __len__(self) -> int:
        return len(self.stamp_ns)

    @property
    def frame_id(self) -> str:
        """The frame_id of every row (the axis name for axisflow's topics); an error if they differ."""
        if len(self.frame_ids) != 1:
            raise RecordingError(
                f"{self.path}: topic {self.topic} has {len(self.frame_ids)} frame_ids "
                f"{list(self.frame_ids)}: use frame_ids"
            )
        return self.frame_ids[0]

    def joint(self, name: str) -> JointColumns:
        """The columns of joint ``name``."""
        if name not in self.joint_names:
            raise RecordingError(
                f"{self.path}: topic {self.topic} has no joint {name!r}; "
                f"its joints are {list(self.joint_names)}"
            )
        j = self.joint_names.index(name)
        return JointColumns(name, self.stamp_ns, self.position[:, j], self.velocity[:, j], self.effort[:, j])


# ---- the catalog of schemas and channels -----------------------------------------------------------


class _Catalog:
    """Schemas and channels known so far (from the summary, then from the records as they come)."""

    def __init__(self, summary: Summary | None) -> None:
        self.schemas: dict[int, Schema] = dict(summary.schemas) if summary else {}
        self.channels: dict[int, Channel] = dict(summary.channels) if summary else {}
        self.version = 0

    def add(self, record: Schema | Channel) -> None:
        table: dict = self.schemas if isinstance(record, Schema) else self.channels
        if record.id not in table:
            table[record.id] = record
            self.version += 1

    def knows(self, channel_ids: set[int]) -> bool:
        return channel_ids <= self.channels.keys()

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


def _parse_record(cls: type[Schema] | type[Channel], body: bytes) -> Schema | Channel:
    return cls.read(ReadDataStream(BytesIO(body)))


# ---- chunks ----------------------------------------------------------------------------------------


@dataclass
class _ChunkRef:
    """A chunk record on disk (data not loaded) and the message indexes that followed it."""

    record_offset: int
    compression: str
    uncompressed_size: int
    data_offset: int
    data_length: int
    indexes: dict[int, np.ndarray]
    """channel id → offsets (int64) of its message records in the decompressed chunk"""
    walked: bool = False

    @classmethod
    def read(cls, fh: BinaryIO, body_offset: int, body_length: int) -> _ChunkRef:
        if body_length < _CHUNK_FIXED.size + 8:
            raise RecordingError(
                f"chunk at byte {body_offset - RECORD_PREFIX.size} is {body_length} bytes short"
            )
        fh.seek(body_offset)
        fixed = fh.read(_CHUNK_FIXED.size)
        _start, _end, uncompressed_size, _crc, name_length = _CHUNK_FIXED.unpack(fixed)
        compression = fh.read(name_length).decode("utf-8", "replace")
        (data_length,) = _U64.unpack(fh.read(8))
        data_offset = body_offset + _CHUNK_FIXED.size + name_length + 8
        if data_offset + data_length > body_offset + body_length:
            raise RecordingError(
                f"chunk at byte {body_offset - RECORD_PREFIX.size}: its {data_length} bytes of records "
                f"overrun the record's length {body_length}"
            )
        return cls(
            body_offset - RECORD_PREFIX.size, compression, uncompressed_size, data_offset, data_length, {}
        )

    def add_index(self, body: bytes) -> None:
        (channel_id,) = _U16.unpack_from(body, 0)
        entries = np.frombuffer(body, dtype="<u8", offset=6, count=(len(body) - 6) // 8)
        self.indexes[channel_id] = entries[1::2].astype(np.int64)

    def load(self, fh: BinaryIO, zstd: zstandard.ZstdDecompressor) -> bytes:
        """The decompressed records of the chunk."""
        fh.seek(self.data_offset)
        data = fh.read(self.data_length)
        if self.compression == "zstd":
            out = zstd.decompress(data, max_output_size=self.uncompressed_size)
        elif self.compression == "lz4":
            out = lz4.frame.decompress(data)
        elif self.compression == "":
            out = data
        else:
            raise RecordingError(
                f"chunk at byte {self.record_offset} uses compression {self.compression!r}; "
                "readable: zstd, lz4 or none"
            )
        if len(out) != self.uncompressed_size:
            raise RecordingError(
                f"chunk at byte {self.record_offset} decompresses to {len(out)} bytes, its header says "
                f"{self.uncompressed_size}"
            )
        return out


@dataclass
class _ChunkContents:
    """What a record-by-record walk of a decompressed chunk found."""

    records: list[Schema | Channel]
    offsets: dict[int, list[int]]
    """channel id → offsets of its message records"""


def _walk_chunk(data: bytes, where: str) -> _ChunkContents:
    """Schemas, channels and message offsets of a decompressed chunk, one record at a time."""
    records: list[Schema | Channel] = []
    offsets: dict[int, list[int]] = defaultdict(list)
    pos, end = 0, len(data)
    while pos + RECORD_PREFIX.size <= end:
        opcode, length = RECORD_PREFIX.unpack_from(data, pos)
        body = pos + RECORD_PREFIX.size
        if body + length > end:
            raise RecordingError(f"{where}: record at byte {pos} of length {length} overruns the chunk")
        if opcode == Opcode.MESSAGE:
            offsets[_U16.unpack_from(data, body)[0]].append(pos)
        elif opcode == Opcode.SCHEMA:
            records.append(_parse_record(Schema, data[body : body + length]))
        elif opcode == Opcode.CHANNEL:
            records.append(_parse_record(Channel, data[body : body + length]))
        pos = body + length
    return _ChunkContents(records, offsets)


# ---- message records as numpy rows -----------------------------------------------------------------


def _rows(data: np.ndarray, offsets: np.ndarray, width: int) -> np.ndarray:
    """``width`` bytes at each offset of ``data`` as uint8 rows (n, width): a strided view when the
    offsets are evenly spaced, else a gather (copy)."""
    n = len(offsets)
    step = int(offsets[1] - offsets[0]) if n > 1 else width
    if step > 0 and (n < 3 or bool((np.diff(offsets) == step).all())):
        return np.ndarray((n, width), np.uint8, buffer=data, offset=int(offsets[0]), strides=(step, 1))
    return data[offsets[:, None] + np.arange(width)]


def _message_heads(data: np.ndarray, offsets: np.ndarray, channel_ids: set[int], where: str) -> np.ndarray:
    """The 31-byte heads (:data:`MESSAGE_HEAD`, shape (n,)) of the message records at ``offsets``,
    checked: each is a Message of one of ``channel_ids`` that ends inside ``data``."""
    size = len(data)
    if offsets[0] < 0 or offsets[-1] + MESSAGE_HEAD_SIZE > size:
        raise RecordingError(f"{where}: a message index points outside the chunk's {size} bytes")
    heads = _rows(data, offsets, MESSAGE_HEAD_SIZE).view(MESSAGE_HEAD)[:, 0]
    bad = heads["opcode"] != Opcode.MESSAGE
    if bad.any():
        i = int(np.argmax(bad))
        raise RecordingError(
            f"{where}: the message index points at byte {offsets[i]}, a record with opcode "
            f"0x{heads['opcode'][i]:02x}, not a Message (0x05)"
        )
    lengths = heads["length"]
    bad = (lengths < MESSAGE_FIELDS_SIZE) | (lengths > size)
    if not bad.any():
        bad = offsets + RECORD_PREFIX.size + lengths.astype(np.int64) > size
    if bad.any():
        i = int(np.argmax(bad))
        raise RecordingError(
            f"{where}: message record at byte {offsets[i]} has an impossible length {lengths[i]}"
        )
    bad = ~np.isin(heads["channel_id"], list(channel_ids))
    if bad.any():
        i = int(np.argmax(bad))
        raise RecordingError(
            f"{where}: the message index points at byte {offsets[i]}, a message of channel "
            f"{heads['channel_id'][i]}, not of channel {sorted(channel_ids)}"
        )
    return heads


def _decode_vectorised(
    data: np.ndarray, offsets: np.ndarray, heads: np.ndarray
) -> tuple[JointStateLayout, DecodedJointStates] | None:
    """The payloads decoded at fixed offsets, or None if they do not all share the first one's layout."""
    lengths = heads["length"]
    length = int(lengths[0])
    if bool((lengths != length).any()):
        return None
    rows = _rows(data, offsets + MESSAGE_HEAD_SIZE, length - MESSAGE_FIELDS_SIZE)
    layout = JointStateLayout.of(rows[0].tobytes())
    if layout is None or not layout.matches(rows):
        return None
    try:
        return layout, layout.decode(rows)
    except WireError:  # a bad stamp: the per-message path names the message
        return None


# ---- growing the result ----------------------------------------------------------------------------

_INT_COLUMNS = ("stamp_ns", "log_time_ns", "publish_time_ns", "sequence")
_FLOAT_COLUMNS = ("position", "velocity", "effort")


class _ColumnBuilder:
    """The result's arrays, preallocated (``capacity`` rows) and grown in place when full.

    Growing and the final trim use ``ndarray.resize`` (a realloc, which for large blocks remaps pages
    instead of copying); it is safe here because no view of these arrays exists before :meth:`finish`.
    """

    def __init__(self, capacity: int) -> None:
        self.capacity = max(capacity, 1024)
        self.n = 0
        self.arrays: dict[str, np.ndarray] = {}

    def _ensure(self, joints: int, rows: int) -> None:
        if not self.arrays:
            for name in _INT_COLUMNS:
                self.arrays[name] = np.empty(self.capacity, np.int64)
            for name in _FLOAT_COLUMNS:
                self.arrays[name] = np.empty((self.capacity, joints), np.float64)
        if self.n + rows > self.capacity:
            self.capacity = max(2 * self.capacity, self.n + rows)
            self._resize(self.capacity)

    def _resize(self, rows: int) -> None:
        for array in self.arrays.values():
            array.resize((rows, *array.shape[1:]), refcheck=False)

    def append(self, heads: np.ndarray, decoded: DecodedJointStates, keep: np.ndarray | None) -> None:
        rows = len(heads) if keep is None else int(keep.sum())
        self._ensure(decoded.position.shape[1], rows)
        sources = {
            "stamp_ns": decoded.stamp_ns,
            "log_time_ns": heads["log_time"],
            "publish_time_ns": heads["publish_time"],
            "sequence": heads["sequence"],
            "position": decoded.position,
            "velocity": decoded.velocity,
            "effort": decoded.effort,
        }
        part = slice(self.n, self.n + rows)
        for name, source in sources.items():
            self.arrays[name][part] = source if keep is None else source[keep]
        self.n += rows

    def finish(self) -> dict[str, np.ndarray]:
        if self.n != self.capacity:
            self._resize(self.n)
        return self.arrays


# ---- reading one topic -----------------------------------------------------------------------------


class _ChannelReader:
    """What the scan hands a topic's messages to: the topic's channel ids among the channels learnt so
    far, each checked by :meth:`check_channel` once (recomputed only when the catalogue grew), and
    :meth:`decode` for a batch of its message records."""

    def __init__(self, path: Path, topic: str, catalog: _Catalog) -> None:
        self.path, self.topic, self.catalog = path, topic, catalog
        self._wanted: set[int] = set()
        self._catalog_version = -1

    def wanted_ids(self) -> set[int]:
        """The channel ids of the topic among the known channels (each checked)."""
        if self._catalog_version != self.catalog.version:
            self._catalog_version = self.catalog.version
            for cid, channel in self.catalog.channels.items():
                if channel.topic == self.topic and cid not in self._wanted:
                    self.check_channel(channel)
                    self._wanted.add(cid)
        return self._wanted

    def check_channel(self, channel: Channel) -> None:
        """A :class:`RecordingError` if the topic's ``channel`` cannot be read here."""

    def decode(self, buffer: bytes, offsets: np.ndarray, where: str) -> None:
        """Take the message records at ``offsets`` of ``buffer``."""
        raise NotImplementedError


class _TopicRead(_ChannelReader):
    """Decodes the messages of one topic, batch by batch (a chunk, or messages outside chunks)."""

    def __init__(
        self,
        path: Path,
        topic: str,
        catalog: _Catalog,
        start_ns: int | None,
        end_ns: int | None,
        per_message: bool,
    ) -> None:
        super().__init__(path, topic, catalog)
        self.start_ns, self.end_ns = start_ns, end_ns
        self.per_message = per_message
        self.joint_names: tuple[str, ...] | None = None
        self.frame_ids: dict[str, None] = {}
        self.decoded = {"vectorised": 0, "per_message": 0}
        self.stamp_range: tuple[int, int] | None = None
        self.builder = _ColumnBuilder(0)

    def reserve(self, rows: int) -> None:
        """Preallocate the result for ``rows`` rows (e.g. the summary's message count)."""
        if self.builder.n == 0:
            self.builder = _ColumnBuilder(rows)

    def check_channel(self, channel: Channel) -> None:
        """It must be JointState in CDR."""
        schema = self.catalog.schema_of(channel)
        if schema is None:
            raise RecordingError(
                f"{self.path}: topic {self.topic} has no schema (message encoding "
                f"{channel.message_encoding!r}), so it cannot be read as {JOINT_STATE_TYPE}"
            )
        if schema.name != JOINT_STATE_TYPE:
            raise RecordingError(
                f"{self.path}: topic {self.topic} has schema {schema.name!r} ({schema.encoding}), "
                f"not {JOINT_STATE_TYPE}"
            )
        if channel.message_encoding != "cdr":
            raise RecordingError(
                f"{self.path}: topic {self.topic} ({JOINT_STATE_TYPE}) has message encoding "
                f"{channel.message_encoding!r}; only ROS 2 CDR ('cdr') is read"
            )

    def decode(self, buffer: bytes, offsets: np.ndarray, where: str) -> None:
        """Decode the topic's message records at ``offsets`` (any order) of ``buffer`` and keep the rows
        whose stamp is in the time range."""
        offsets = np.sort(offsets)
        data = np.frombuffer(buffer, np.uint8)
        heads = _message_heads(data, offsets, self.wanted_ids(), where)
        fast = None if self.per_message else _decode_vectorised(data, offsets, heads)
        if fast is not None:
            layout, decoded = fast
            self._check_joints(layout.joint_names, heads, 0)
            frame_ids = [layout.frame_id]
            self.decoded["vectorised"] += len(heads)
        else:
            decoded, frame_ids = self._decode_each(buffer, offsets, heads, where)
            self.decoded["per_message"] += len(heads)
        keep = self._in_range(decoded.stamp_ns)
        if keep is None or keep.any():
            if keep is not None and len(frame_ids) > 1:
                frame_ids = [f for f, k in zip(frame_ids, keep.tolist(), strict=True) if k]
            self.frame_ids.update(dict.fromkeys(frame_ids))
            self.builder.append(heads, decoded, keep)

    def _decode_each(
        self, buffer: bytes, offsets: np.ndarray, heads: np.ndarray, where: str
    ) -> tuple[DecodedJointStates, list[str]]:
        """The per-message path: :meth:`JointState.decode` on each payload."""
        view = memoryview(buffer)
        ends = offsets + RECORD_PREFIX.size + heads["length"].astype(np.int64)
        n = len(offsets)
        stamp_ns = np.empty(n, np.int64)
        arrays: list[np.ndarray] = []
        frame_ids: list[str] = []
        for i, (start, end) in enumerate(
            zip((offsets + MESSAGE_HEAD_SIZE).tolist(), ends.tolist(), strict=True)
        ):
            try:
                message = JointState.decode(view[start:end])
            except WireError as exc:
                raise WireError(f"{self._message_name(heads, i)} in {where}: {exc}") from None
            self._check_joints(message.name, heads, i)
            if not arrays:
                arrays = [np.empty((n, len(message.name)), np.float64) for _ in range(3)]
            stamp_ns[i] = message.stamp_ns
            for array, field in zip(arrays, ("position", "velocity", "effort"), strict=True):
                values = getattr(message, field)
                if len(values) not in (0, len(message.name)):
                    raise WireError(
                        f"{self._message_name(heads, i)}: {field} has {len(values)} values for "
                        f"{len(message.name)} joints (one per joint or none)"
                    )
                array[i] = values if values else np.nan
            frame_ids.append(message.frame_id)
        return DecodedJointStates(stamp_ns, *arrays), frame_ids

    def _message_name(self, heads: np.ndarray, i: int) -> str:
        return (
            f"{self.path}: topic {self.topic}, message with sequence {heads['sequence'][i]} "
            f"and log time {heads['log_time'][i]} ns"
        )

    def _check_joints(self, names: tuple[str, ...], heads: np.ndarray, i: int) -> None:
        if self.joint_names is None:
            self.joint_names = names
        elif names != self.joint_names:
            raise RecordingError(
                f"{self._message_name(heads, i)} names the joints {list(names)}, the topic's first "
                f"message {list(self.joint_names)}: columns need the same joints in every message"
            )

    def _in_range(self, stamp_ns: np.ndarray) -> np.ndarray | None:
        """The rows to keep (None: all), and the stamp range seen so far updated."""
        low, high = int(stamp_ns.min()), int(stamp_ns.max())
        if self.stamp_range is not None:
            low, high = min(low, self.stamp_range[0]), max(high, self.stamp_range[1])
        self.stamp_range = (low, high)
        if self.start_ns is None and self.end_ns is None:
            return None
        keep = np.ones(len(stamp_ns), bool)
        if self.start_ns is not None:
            keep &= stamp_ns >= self.start_ns
        if self.end_ns is not None:
            keep &= stamp_ns < self.end_ns
        return keep

    def result(self, truncated: bool) -> JointStateColumns:
        if self.builder.n == 0:
            raise RecordingError(self._empty_reason())
        arrays = self.builder.finish()
        return JointStateColumns(
            path=self.path,
            topic=self.topic,
            joint_names=self.joint_names or (),
            frame_ids=tuple(self.frame_ids),
            truncated=truncated,
            vectorised_messages=self.decoded["vectorised"],
            per_message_messages=self.decoded["per_message"],
            **arrays,
        )

    def _empty_reason(self) -> str:
        if self.stamp_range is None:
            return f"{self.path}: topic {self.topic} holds no message"
        low, high = self.stamp_range
        return (
            f"{self.path}: no message of topic {self.topic} has a header stamp in "
            f"[{self.start_ns}, {self.end_ns}) ns; its stamps span [{low}, {high}] ns"
        )

    def topic_missing(self, truncated: bool) -> RecordingError:
        present = [t.topic for t in self.catalog.topics(None) if t.is_joint_state]
        cut = (
            " (it has no footer: cut off by a crash, read up to its last complete chunk)" if truncated else ""
        )
        listed = ", ".join(present) or "none"
        return RecordingError(f"{self.path} has no topic {self.topic}; its JointState topics: {listed}{cut}")


# ---- reading any topic as raw payloads -------------------------------------------------------------


@dataclass(frozen=True)
class RawMessage:
    """One message as stored: MCAP times [ns], sequence and the payload bytes (decode with the type's
    ``decode``, e.g. :meth:`~axisflow.acquisition.wire.move_status.MoveStatus.decode`)."""

    log_time_ns: int
    publish_time_ns: int
    sequence: int
    data: bytes


class _PayloadRead(_ChannelReader):
    """Collects the raw messages of one topic of any type."""

    def __init__(self, path: Path, topic: str, catalog: _Catalog, type_name: str | None) -> None:
        super().__init__(path, topic, catalog)
        self.type_name = type_name
        self.messages: list[RawMessage] = []

    def check_channel(self, channel: Channel) -> None:
        """With a ``type_name``, its schema must be that type."""
        schema = self.catalog.schema_of(channel)
        if self.type_name is not None and (schema is None or schema.name != self.type_name):
            found = schema.name if schema is not None else "no schema"
            raise RecordingError(f"{self.path}: topic {self.topic} is {found}, not {self.type_name}")

    def decode(self, buffer: bytes, offsets: np.ndarray, where: str) -> None:
        offsets = np.sort(offsets)
        heads = _message_heads(np.frombuffer(buffer, np.uint8), offsets, self.wanted_ids(), where)
        starts = (offsets + MESSAGE_HEAD_SIZE).tolist()
        ends = (offsets + RECORD_PREFIX.size + heads["length"].astype(np.int64)).tolist()
        columns = zip(heads["log_time"].tolist(), heads["publish_time"].tolist(), heads["sequence"].tolist(),
                      starts, ends, strict=True)  # fmt: skip
        self.messages += [RawMessage(log, pub, seq, buffer[a:b]) for log, pub, seq, a, b in columns]


def read_messages(path: str | Path, topic: str, type_name: str | None = None) -> list[RawMessage]:
    """Every message of ``topic`` as stored, in file order (a complete, summary-less or truncated file).

    Chunks whose message index does not name the topic's channel are not decompressed, so a few
    messages (move statuses, plans) are found in a long recording in about the time of one pass over its
    indexes. ``type_name`` (e.g. ``axisflow_msgs/msg/MoveStatus``) makes a topic of another schema an
    error. An absent topic gives an empty list.
    """
    p = check_mcap(path)
    with open(p, "rb") as fh:
        has_footer, summary = read_summary(fh)
        catalog = _Catalog(summary)
        reader = _PayloadRead(p, topic, catalog, type_name)
        scan = _LogScan(fh, p, catalog, has_footer)
        scan.run(reader)
    return reader.messages


# ---- the walk over the file ------------------------------------------------------------------------


class _LogScan:
    """Walks the top-level records of a file in order: learns schemas and channels, counts messages
    per channel, and hands the wanted channels' message records, a chunk at a time and in file
    order, to a :class:`_TopicRead` (if any)."""

    def __init__(self, fh: BinaryIO, path: Path, catalog: _Catalog, has_footer: bool) -> None:
        self.fh, self.path, self.catalog = fh, path, catalog
        self.has_footer = has_footer
        self.size = os.fstat(fh.fileno()).st_size
        self.truncated = False
        self.counts: Counter[int] = Counter()
        self._reader: _ChannelReader | None = None
        self._pending: _ChunkRef | None = None
        self._unwalked: list[_ChunkRef] = []
        self._loose = bytearray()
        self._loose_offsets: list[int] = []
        self._zstd = zstandard.ZstdDecompressor()

    def run(self, reader: _ChannelReader | None) -> None:
        self._reader = reader
        for opcode, body, length in self._records():
            if opcode == Opcode.CHUNK:
                self._close_chunk(indexes_complete=True)
                self._pending = _ChunkRef.read(self.fh, body, length)
            elif opcode == Opcode.MESSAGE_INDEX:
                if self._pending is not None:
                    self._pending.add_index(self._body(body, length))
            else:
                self._close_chunk(indexes_complete=True)
                self._top_level(opcode, body, length)
        # after a truncation the index records of the last chunk may be cut: walk it instead
        self._close_chunk(indexes_complete=not self.truncated)
        self._flush_loose()

    def _records(self) -> Iterator[tuple[int, int, int]]:
        """(opcode, body offset, body length) of each complete top-level record up to the footer."""
        pos = len(MCAP_MAGIC)
        while True:
            self.fh.seek(pos)
            prefix = self.fh.read(RECORD_PREFIX.size)
            if len(prefix) < RECORD_PREFIX.size:
                break
            opcode, length = RECORD_PREFIX.unpack(prefix)
            body = pos + RECORD_PREFIX.size
            if body + length > self.size:
                break
            yield opcode, body, length
            if opcode == Opcode.FOOTER:
                return
            pos = body + length
        if self.has_footer:
            raise RecordingError(
                f"{self.path}: the record at byte {pos} runs past the end of the file ({self.size} bytes) "
                "although the file has a footer: the file is corrupt"
            )
        self.truncated = True

    def _body(self, offset: int, length: int) -> bytes:
        self.fh.seek(offset)
        return self.fh.read(length)

    def _top_level(self, opcode: int, body: int, length: int) -> None:
        if opcode == Opcode.SCHEMA:
            self.catalog.add(_parse_record(Schema, self._body(body, length)))
        elif opcode == Opcode.CHANNEL:
            self.catalog.add(_parse_record(Channel, self._body(body, length)))
        elif opcode == Opcode.MESSAGE:
            if length < MESSAGE_FIELDS_SIZE:
                raise RecordingError(
                    f"{self.path}: message record at byte {body - 9} is {length} bytes short"
                )
            record = self._body(body - RECORD_PREFIX.size, length + RECORD_PREFIX.size)
            (channel_id,) = _U16.unpack_from(record, RECORD_PREFIX.size)
            self.counts[channel_id] += 1
            if self._reader is not None and channel_id in self._reader.wanted_ids():
                self._loose_offsets.append(len(self._loose))
                self._loose += record
                if len(self._loose) >= _LOOSE_BATCH_BYTES:
                    self._flush_loose()

    def _flush_loose(self) -> None:
        if self._loose_offsets and self._reader is not None:
            offsets = np.array(self._loose_offsets, np.int64)
            self._reader.decode(bytes(self._loose), offsets, f"{self.path}: messages outside chunks")
        self._loose.clear()
        self._loose_offsets.clear()

    def _close_chunk(self, indexes_complete: bool) -> None:
        chunk, self._pending = self._pending, None
        if chunk is None:
            return
        self._flush_loose()  # the messages before the chunk come first
        where = f"{self.path}: chunk at byte {chunk.record_offset}"
        data: bytes | None = None
        if indexes_complete and chunk.indexes:
            for cid, offsets in chunk.indexes.items():
                self.counts[cid] += len(offsets)
            if not self.catalog.knows(set(chunk.indexes)):
                data = self._discover(chunk)
            offsets_by_channel = chunk.indexes
        else:  # no (complete) message index: find the messages record by record
            data = self._load(chunk)
            contents = self._walk(chunk, data)
            self.counts.update({cid: len(offs) for cid, offs in contents.offsets.items()})
            offsets_by_channel = {cid: np.array(offs, np.int64) for cid, offs in contents.offsets.items()}
        reader = self._reader
        wanted = reader.wanted_ids() & offsets_by_channel.keys() if reader is not None else set()
        if reader is not None and wanted:
            data = data if data is not None else self._load(chunk)
            offsets = np.concatenate([offsets_by_channel[cid] for cid in sorted(wanted)])
            reader.decode(data, offsets, where)
        chunk.indexes = {}  # done with them; an unwalked chunk is kept only to be walked later
        if not chunk.walked:
            self._unwalked.append(chunk)

    def _load(self, chunk: _ChunkRef) -> bytes:
        return chunk.load(self.fh, self._zstd)

    def _walk(self, chunk: _ChunkRef, data: bytes) -> _ChunkContents:
        contents = _walk_chunk(data, f"{self.path}: chunk at byte {chunk.record_offset}")
        for record in contents.records:
            self.catalog.add(record)
        chunk.walked = True
        return contents

    def _discover(self, chunk: _ChunkRef) -> bytes:
        """Learn the channels of a chunk whose index names unknown ones: from its own records, else
        from the earlier chunks not walked yet (a channel record may precede its first message by
        chunks). Returns the chunk's decompressed records."""
        data = self._load(chunk)
        self._walk(chunk, data)
        if not self.catalog.knows(set(chunk.indexes)):
            for earlier in self._unwalked:
                self._walk(earlier, self._load(earlier))
            self._unwalked.clear()
        return data


# ---- public API ------------------------------------------------------------------------------------


def list_topics(path: str | Path) -> list[TopicInfo]:
    """The topics of an MCAP file, sorted by name, with their message counts.

    A complete file answers from its summary (counts from its statistics, None without them); a file
    without summary (or cut off by a crash) is scanned, counting messages up to the last complete chunk.
    Raises :class:`RecordingError` for a missing or non-MCAP file.
    """
    p = check_mcap(path)
    with open(p, "rb") as fh:
        has_footer, summary = read_summary(fh)
        catalog = _Catalog(summary)
        if summary is not None and summary.channels:
            stats = summary.statistics
            return catalog.topics(dict(stats.channel_message_counts) if stats else None)
        scan = _LogScan(fh, p, catalog, has_footer)
        scan.run(None)
        return catalog.topics(scan.counts)


def read_joint_states(
    path: str | Path,
    topic: str,
    *,
    start_ns: int | None = None,
    end_ns: int | None = None,
    per_message: bool = False,
) -> JointStateColumns:
    """The ``sensor_msgs/msg/JointState`` messages of ``topic`` as columns, rows in file order.

    ``start_ns``/``end_ns`` keep the rows whose header stamp is in [start_ns, end_ns) (either may be
    None: unbounded). ``per_message=True`` decodes every message with :meth:`JointState.decode` (the
    reference the vectorised path is tested against; ~18× slower). A file cut off by a crash is read
    up to its last complete chunk (``truncated`` is then True).

    Raises :class:`RecordingError` for a missing or non-MCAP file, a topic that is not in the file
    (naming the JointState topics it has), a topic that is not ROS 2 CDR JointState (naming its schema),
    joints that change between messages, and an empty result; :class:`WireError` for a payload that does
    not decode (naming the message).
    """
    p = check_mcap(path)
    with open(p, "rb") as fh:
        has_footer, summary = read_summary(fh)
        catalog = _Catalog(summary)
        reader = _TopicRead(p, topic, catalog, start_ns, end_ns, per_message)
        if summary is not None and summary.channels:
            wanted = reader.wanted_ids()
            if not wanted:
                raise reader.topic_missing(truncated=False)
            if summary.statistics is not None:
                counts = summary.statistics.channel_message_counts
                reader.reserve(sum(counts.get(cid, 0) for cid in wanted))
        scan = _LogScan(fh, p, catalog, has_footer)
        scan.run(reader)
        if not reader.wanted_ids():
            raise reader.topic_missing(scan.truncated)
        return reader.result(scan.truncated)
