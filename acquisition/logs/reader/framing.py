"""The bottom layer of reading a log: an MCAP file as records — its summary, its chunks with the
message indexes that follow each, the records outside chunks, and the records inside a chunk once
decompressed and checked.

File layout relied on (MCAP, https://mcap.dev/spec; integers little endian)
-------------------------------------------------------------------------
The file is the 8-byte magic ``89 4D 43 41 50 30 0D 0A`` and a sequence of records, each
``opcode u8, length u64, body[length]``. The top-level records are walked here directly (the framing
is all a reader needs, and mcap's ``StreamReader`` parses every MessageIndex entry in Python, far too
slow for 7 M entries an hour); Schema and Channel bodies are parsed with mcap's record classes.

* **Chunk** (0x06): ``message_start_time u64, message_end_time u64, uncompressed_size u64,
  uncompressed_crc u32, compression (u32 length + UTF-8: "", "zstd" or "lz4"), records_length u64,
  records``; the records, decompressed, are again ``opcode u8, length u64, body`` (Schema, Channel and
  Message records). ``uncompressed_crc`` is the CRC-32 of the decompressed records (0: none).
* **Message** (0x05), inside a chunk or not: ``channel_id u16, sequence u32, log_time u64,
  publish_time u64, data`` — so a message record has a fixed 31-byte head (opcode, length and those
  four fields) and its payload is ``length − 22`` bytes at record offset 31.
* **MessageIndex** (0x07), written right after its chunk, one per channel present in it (in files cut
  off by a crash too): ``channel_id u16, records_length u32, records_length/16 × (log_time u64,
  offset u64)``, the offset of each of the channel's message records in the decompressed chunk.
* Schema (0x03), Channel (0x04), DataEnd (0x0F), Footer (0x02), the summary records: the summary
  (through mcap's seeking reader) gives channels and per-channel message counts up front when the file
  has one.

Damage. A file cut off by a crash has no footer: its records are walked up to the last complete one
(:attr:`McapFile.truncated`). A chunk whose header is inconsistent, whose data do not decompress, do
not decompress to the size its header says, fail its CRC, or hold records that overrun it cannot be
read; :meth:`McapFile.load` raises :class:`ChunkError` for it, and the layers above skip it as a
:class:`DamagedChunk` (which names the file, the chunk, its byte offset and the reason) and go on with
the next one: the record framing around a chunk is intact when only its data are damaged, and its
message indexes (outside the compressed data) still say how many messages of which channels it held.
"""

from __future__ import annotations

import os
import struct
from collections import defaultdict
from collections.abc import Iterator
from dataclasses import dataclass, field
from io import BytesIO
from pathlib import Path
from typing import BinaryIO

import lz4.frame
import numpy as np
import zstandard
from mcap.data_stream import ReadDataStream
from mcap.exceptions import McapError
from mcap.opcode import Opcode
from mcap.reader import make_reader
from mcap.records import Channel, Schema
from mcap.summary import Summary
from zlib_ng.zlib_ng import crc32

from ....model.files import InputError, check_input_file
from ...errors import RecordingError

MCAP_MAGIC = b"\x89MCAP0\r\n"
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


class ChunkError(Exception):
    """A chunk cannot be read (the reason is the message). Internal to the reader: the layers above
    turn it into a :class:`DamagedChunk` and go on."""


# ---- the file ----------------------------------------------------------------------------------------


def check_mcap(path: str | Path) -> Path:
    """``path`` as a Path if it is a readable file that starts with the MCAP magic; else a
    :class:`RecordingError` naming it and the reason (missing, a directory, a name too long, not
    MCAP)."""
    try:
        p = check_input_file(path, "recording")
    except InputError as exc:
        raise RecordingError(str(exc)) from None
    with open(p, "rb") as fh:
        head = fh.read(len(MCAP_MAGIC))
    if head != MCAP_MAGIC:
        raise RecordingError(
            f"{p} is not an MCAP file: its first {len(head)} bytes {head!r} are not the "
            f"{len(MCAP_MAGIC)}-byte MCAP magic {MCAP_MAGIC!r}"
        )
    return p


def read_summary(fh: BinaryIO) -> tuple[bool, Summary | None]:
    """(the file has a readable footer, its summary or None), through mcap's seeking reader."""
    try:
        summary = make_reader(fh).get_summary()
    except (McapError, OSError, ValueError, EOFError, struct.error, UnicodeDecodeError):
        return False, None
    return True, summary


def is_complete(path: str | Path) -> bool:
    """True if the file has a readable summary/footer (what a clean finish writes)."""
    try:
        with open(path, "rb") as fh:
            return read_summary(fh)[0]
    except OSError:
        return False


@dataclass(frozen=True)
class DamagedChunk:
    """A chunk that could not be read, and what is known of what it held."""

    path: Path
    ordinal: int
    """its place among the file's chunks, from 1"""
    offset: int
    """byte offset of the chunk record in the file"""
    reason: str
    start_log_ns: int
    """the chunk header's earliest message log time [ns] (as written: may be damaged too)"""
    end_log_ns: int
    messages: dict[int, int] | None
    """channel id → messages it held, from its message indexes (None: it has none)"""

    def describe(self) -> str:
        """One line: the file, the chunk, its byte offset and why it cannot be read."""
        return f"{self.path}: chunk {self.ordinal} at byte {self.offset} cannot be read: {self.reason}"

    def messages_of(self, channel_ids: set[int]) -> int | None:
        """How many messages of ``channel_ids`` it held (None: not known)."""
        if self.messages is None:
            return None
        return sum(n for cid, n in self.messages.items() if cid in channel_ids)

    @property
    def span_s(self) -> float:
        """The log time it covered [s] (per its header)."""
        return max(self.end_log_ns - self.start_log_ns, 0) * 1e-9


@dataclass
class ChunkRef:
    """A chunk record on disk (data not loaded) and the message indexes that followed it."""

    ordinal: int
    record_offset: int
    start_log_ns: int = 0
    end_log_ns: int = 0
    uncompressed_size: int = 0
    uncompressed_crc: int = 0
    compression: str = ""
    data_offset: int = 0
    data_length: int = 0
    header_damage: str | None = None
    """why the header itself is unusable (None: it is fine)"""
    indexes: dict[int, np.ndarray] = field(default_factory=dict)
    """channel id → offsets (int64) of its message records in the decompressed chunk"""
    indexes_complete: bool = False
    """the message indexes that followed it were all read (False: a truncation cut them, or none)"""

    @classmethod
    def parse(cls, ordinal: int, head: bytes, body_offset: int, body_length: int) -> ChunkRef:
        """The chunk whose record body starts at ``body_offset``; ``head`` holds its first bytes (up
        to the start of its data)."""
        ref = cls(ordinal, body_offset - RECORD_PREFIX.size)
        if body_length < _CHUNK_FIXED.size + 8 or len(head) < _CHUNK_FIXED.size:
            ref.header_damage = f"its record is {body_length} bytes, too short for a chunk header"
            return ref
        start, end, size, crc, name_length = _CHUNK_FIXED.unpack_from(head)
        ref.start_log_ns, ref.end_log_ns, ref.uncompressed_size, ref.uncompressed_crc = start, end, size, crc
        data_start = _CHUNK_FIXED.size + name_length + 8
        if data_start > min(body_length, len(head)):
            ref.header_damage = f"its compression name of {name_length} bytes overruns its header"
            return ref
        ref.compression = head[_CHUNK_FIXED.size : _CHUNK_FIXED.size + name_length].decode("utf-8", "replace")
        (ref.data_length,) = _U64.unpack_from(head, data_start - 8)
        ref.data_offset = body_offset + data_start
        if data_start + ref.data_length > body_length:
            ref.header_damage = (
                f"its {ref.data_length} bytes of records overrun the record's length {body_length}"
            )
        return ref

    def add_index(self, body: bytes) -> None:
        if len(body) < 6:
            return
        (channel_id,) = _U16.unpack_from(body, 0)
        entries = np.frombuffer(body, dtype="<u8", offset=6, count=(len(body) - 6) // 8)
        self.indexes[channel_id] = entries[1::2].astype(np.int64)

    def damage(self, path: Path, reason: str) -> DamagedChunk:
        counts = {cid: len(o) for cid, o in self.indexes.items()} if self.indexes_complete else None
        return DamagedChunk(
            path, self.ordinal, self.record_offset, reason, self.start_log_ns, self.end_log_ns, counts
        )

    def decompress(self, data: bytes, zstd: zstandard.ZstdDecompressor) -> bytes:
        """The chunk's records from its (compressed) ``data``, checked against its header's size and
        CRC; :class:`ChunkError` if they cannot be had."""
        if self.header_damage is not None:
            raise ChunkError(self.header_damage)
        if len(data) != self.data_length:
            raise ChunkError(f"{len(data)} of its {self.data_length} bytes could be read")
        try:
            if self.compression == "zstd":
                out = zstd.decompress(data, max_output_size=self.uncompressed_size)
            elif self.compression == "lz4":
                out = lz4.frame.decompress(data)
            elif self.compression == "":
                out = data
            else:
                raise ChunkError(f"it uses compression {self.compression!r}; readable: zstd, lz4 or none")
        except (zstandard.ZstdError, RuntimeError, ValueError) as exc:
            raise ChunkError(f"its {self.compression} data do not decompress ({exc})") from None
        if len(out) != self.uncompressed_size:
            raise ChunkError(f"it decompresses to {len(out)} bytes, its header says {self.uncompressed_size}")
        if self.uncompressed_crc and (crc := crc32(out)) != self.uncompressed_crc:
            raise ChunkError(
                f"its records fail their CRC check (CRC-32 {crc:#010x}, the header says "
                f"{self.uncompressed_crc:#010x})"
            )
        return out


@dataclass(frozen=True)
class LooseRecord:
    """A top-level Schema, Channel or Message record (outside any chunk)."""

    opcode: int
    offset: int
    """byte offset of the record in the file"""
    record: bytes
    """the whole record: prefix and body"""


class McapFile:
    """An open MCAP file (a context manager): its path, size, summary when it has a readable footer,
    and its records in file order (:meth:`blocks`)."""

    def __init__(self, path: Path, fh: BinaryIO) -> None:
        self.path = path
        self.fh = fh
        self.size = os.fstat(fh.fileno()).st_size
        self.has_footer, self.summary = read_summary(fh)
        self.truncated = False
        """True once :meth:`blocks` found the file cut off (no footer, a record past its end)"""
        self.chunks = 0
        """chunk records met so far"""

    @classmethod
    def open(cls, path: str | Path) -> McapFile:
        """The file at ``path``, checked (:func:`check_mcap`)."""
        p = check_mcap(path)
        try:
            fh = open(p, "rb")  # noqa: SIM115 - owned by the McapFile, closed with it
        except OSError as exc:
            raise RecordingError(f"recording {p} cannot be read: {exc.strerror}") from None
        try:
            return cls(p, fh)
        except BaseException:
            fh.close()
            raise

    def close(self) -> None:
        self.fh.close()

    def __enter__(self) -> McapFile:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()

    def read(self, offset: int, length: int) -> bytes:
        """``length`` bytes at ``offset``."""
        self.fh.seek(offset)
        return self.fh.read(length)

    def load(self, chunk: ChunkRef, zstd: zstandard.ZstdDecompressor) -> bytes:
        """The decompressed, checked records of ``chunk``; :class:`ChunkError` if they cannot be
        had."""
        if chunk.header_damage is not None:
            raise ChunkError(chunk.header_damage)
        return chunk.decompress(self.read(chunk.data_offset, chunk.data_length), zstd)

    def blocks(self) -> Iterator[ChunkRef | LooseRecord]:
        """The file in order: each chunk (after the message indexes that follow it) and each
        Schema, Channel and Message record outside chunks, up to the footer or the truncation."""
        pending: ChunkRef | None = None
        for opcode, body, length in self._records():
            if opcode == Opcode.MESSAGE_INDEX:
                if pending is not None:
                    pending.add_index(self.read(body, length))
                continue
            if pending is not None:
                pending.indexes_complete = bool(pending.indexes)
                yield pending
                pending = None
            if opcode == Opcode.CHUNK:
                self.chunks += 1
                pending = ChunkRef.parse(self.chunks, self._chunk_head(body, length), body, length)
            elif opcode in (Opcode.SCHEMA, Opcode.CHANNEL, Opcode.MESSAGE):
                start = body - RECORD_PREFIX.size
                yield LooseRecord(opcode, start, self.read(start, length + RECORD_PREFIX.size))
        if pending is not None:
            # after a truncation the index records of the last chunk may be cut: the layer above
            # walks the chunk instead
            pending.indexes_complete = bool(pending.indexes) and not self.truncated
            yield pending

    def _chunk_head(self, body: int, length: int) -> bytes:
        """The bytes of a chunk record's body before its data: fixed fields, compression name and
        records length."""
        head = self.read(body, min(length, 64))
        if len(head) >= _CHUNK_FIXED.size:
            name_length = _CHUNK_FIXED.unpack_from(head)[-1]
            needed = _CHUNK_FIXED.size + name_length + 8
            if needed > len(head):
                head = self.read(body, min(length, needed))
        return head

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


# ---- records -----------------------------------------------------------------------------------------


def parse_schema(body: bytes) -> Schema:
    return Schema.read(ReadDataStream(BytesIO(body)))


def parse_channel(body: bytes) -> Channel:
    return Channel.read(ReadDataStream(BytesIO(body)))


def parse_definition(opcode: int, body: bytes, where: str) -> Schema | Channel:
    """A Schema or Channel record's body; a :class:`RecordingError` naming ``where`` if it does not
    parse."""
    try:
        return parse_schema(body) if opcode == Opcode.SCHEMA else parse_channel(body)
    except (McapError, ValueError, EOFError, struct.error, UnicodeDecodeError) as exc:
        kind = "schema" if opcode == Opcode.SCHEMA else "channel"
        raise RecordingError(f"{where}: a {kind} record does not parse ({exc})") from None


@dataclass
class ChunkContents:
    """What a record-by-record walk of a decompressed chunk found."""

    definitions: list[Schema | Channel]
    offsets: dict[int, list[int]]
    """channel id → offsets of its message records"""


def walk_chunk(data: bytes) -> ChunkContents:
    """Schemas, channels and message offsets of a decompressed chunk, one record at a time;
    :class:`ChunkError` if a record overruns it or does not parse."""
    definitions: list[Schema | Channel] = []
    offsets: dict[int, list[int]] = defaultdict(list)
    pos, end = 0, len(data)
    while pos + RECORD_PREFIX.size <= end:
        opcode, length = RECORD_PREFIX.unpack_from(data, pos)
        body = pos + RECORD_PREFIX.size
        if body + length > end:
            raise ChunkError(f"its record at byte {pos} of length {length} overruns it")
        if opcode == Opcode.MESSAGE:
            if length < MESSAGE_FIELDS_SIZE:
                raise ChunkError(f"its message record at byte {pos} is {length} bytes short")
            offsets[_U16.unpack_from(data, body)[0]].append(pos)
        elif opcode in (Opcode.SCHEMA, Opcode.CHANNEL):
            try:
                definitions.append(parse_definition(opcode, data[body : body + length], ""))
            except RecordingError as exc:
                raise ChunkError(str(exc).lstrip(": ")) from None
        pos = body + length
    return ChunkContents(definitions, offsets)


def rows(data: np.ndarray, offsets: np.ndarray, width: int) -> np.ndarray:
    """``width`` bytes at each offset of ``data`` as uint8 rows (n, width): a strided view when the
    offsets are evenly spaced, else a gather (copy)."""
    n = len(offsets)
    step = int(offsets[1] - offsets[0]) if n > 1 else width
    if step > 0 and (n < 3 or bool((np.diff(offsets) == step).all())):
        return np.ndarray((n, width), np.uint8, buffer=data, offset=int(offsets[0]), strides=(step, 1))
    return data[offsets[:, None] + np.arange(width)]


def message_heads(data: np.ndarray, offsets: np.ndarray, channel_ids: set[int]) -> np.ndarray:
    """The 31-byte heads (:data:`MESSAGE_HEAD`, shape (n,)) of the message records at ``offsets``
    (sorted) of ``data``, checked: each is a Message of one of ``channel_ids`` that ends inside
    ``data``; :class:`ChunkError` naming the first that is not."""
    size = len(data)
    if offsets[0] < 0 or offsets[-1] + MESSAGE_HEAD_SIZE > size:
        raise ChunkError(f"a message index points outside its {size} bytes")
    heads = rows(data, offsets, MESSAGE_HEAD_SIZE).view(MESSAGE_HEAD)[:, 0]
    bad = heads["opcode"] != Opcode.MESSAGE
    if bad.any():
        i = int(np.argmax(bad))
        raise ChunkError(
            f"its message index points at byte {offsets[i]}, a record with opcode "
            f"0x{heads['opcode'][i]:02x}, not a Message (0x05)"
        )
    lengths = heads["length"]
    bad = (lengths < MESSAGE_FIELDS_SIZE) | (lengths > size)
    if not bad.any():
        bad = offsets + RECORD_PREFIX.size + lengths.astype(np.int64) > size
    if bad.any():
        i = int(np.argmax(bad))
        raise ChunkError(f"its message record at byte {offsets[i]} has an impossible length {lengths[i]}")
    channels = heads["channel_id"]
    if len(channel_ids) == 1:
        bad = channels != next(iter(channel_ids))
    else:
        bad = ~np.isin(channels, list(channel_ids))
    if bad.any():
        i = int(np.argmax(bad))
        raise ChunkError(
            f"its message index points at byte {offsets[i]}, a message of channel {channels[i]}, not of "
            f"channel {sorted(channel_ids)}"
        )
    return heads
