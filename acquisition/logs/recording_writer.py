"""The recorder's MCAP writer: chunks built where the messages arrive, compressed and written by a
thread of their own, behind a bounded backlog.

The file is the same as :class:`~.mcap_writer.Ros2McapWriter` writes (ROS 2 profile, ``ros2msg``
schemas, ``cdr`` channels with ``offered_qos_profiles``, chunk compression zstd, lz4 or none, message
and chunk indexes, statistics, summary offsets, CRCs), and any MCAP reader reads it; the work is split
differently, for speed:

* :meth:`RecordingWriter.add` (the receiving thread) appends the Message record, packed by one
  ``struct`` call, to the open chunk's buffer and its offset to the chunk's list of message offsets:
  nothing per channel, no index entry (~0.4 µs, against ~2.5 µs for ``mcap.writer.Writer.add_message``).
  Schema and Channel records go into the open chunk too, so they precede their messages in the file
  (as mcap's writer does).
* A full chunk (``chunk_size`` bytes of records), or the open one at :meth:`flush`, is handed to the
  writer thread, which reads each message's channel and log time back from the records at their
  offsets (numpy, for the whole chunk at once) to build the MessageIndex records, the counts and the
  time span, compresses the chunk (zstd and lz4 release the GIL), computes its CRC, writes the Chunk
  and MessageIndex records and keeps the ChunkIndex (serialized, on an anonymous temporary file:
  memory stays flat over a long session) for the summary. :meth:`flush` also asks for an fsync.
* **Backlog.** The bytes of the chunks not yet written plus the open chunk are the backlog; a message
  that would take it past ``backlog_bytes`` is dropped whole (nothing of it is written) and counted per
  topic (:attr:`dropped`). So a writer that falls behind (a stalled disk, a starved CPU) costs a
  bounded amount of memory, and the recording says what it lost: :meth:`finish` writes a Metadata
  record :data:`LOSS_METADATA` with the count per topic.

An error of the writer thread (a full disk) is raised by the next :meth:`add`, :meth:`flush` or
:meth:`finish` as the ``OSError`` it was. tests/acquisition/logs/test_recording_writer.py reads the
files with mcap's reader, rosbags and our own, and checks the bound.
"""

from __future__ import annotations

import os
import queue
import struct
import tempfile
import threading
from array import array
from pathlib import Path
from typing import BinaryIO

import lz4.frame
import numpy as np
import zstandard
from mcap.data_stream import RecordBuilder
from mcap.opcode import Opcode
from mcap.records import (
    Channel,
    Chunk,
    ChunkIndex,
    DataEnd,
    Footer,
    Header,
    Metadata,
    MetadataIndex,
    Schema,
    Statistics,
    SummaryOffset,
)
from zlib_ng.zlib_ng import crc32

from ..errors import RecordingError
from ..wire.messages import SCHEMAS
from .chunking import DEFAULT_BACKLOG_BYTES, DEFAULT_CHUNK_SIZE
from .mcap_writer import COMPRESSIONS, LIBRARY, OFFERED_QOS_PROFILES, _open_exclusive

MAGIC = b"\x89MCAP0\r\n"
LOSS_METADATA = "axisflow.recording_loss"
"""name of the Metadata record with what the recording lost: ``dropped_messages`` (total dropped by the
writer), ``backlog_bytes`` (its bound), ``dropped <topic>`` per topic that lost any, and ``missed
<topic>`` (lost on the way, from the sequence numbers) when the recorder says"""
_MESSAGE = struct.Struct("<BQHIQQ")
"""opcode, record length, channel id, sequence, log time, publish time (then the data)"""
_MESSAGE_OPCODE = int(Opcode.MESSAGE)
_MESSAGE_FIXED = 2 + 4 + 8 + 8
_CHANNEL_AT = 1 + 8
"""a Message record's channel id (uint16) is this many bytes past its start, ..."""
_LOG_TIME_AT = 1 + 8 + 2 + 4
"""... and its log time (uint64) this many"""
_U16_U32 = struct.Struct("<HI")
_FINISH = object()


class _Chunk:
    """The open chunk: its records and the offset of each Message record among them."""

    __slots__ = ("buf", "offsets")

    def __init__(self) -> None:
        self.buf = bytearray()
        self.offsets = array("Q")


class _ChunkMessages:
    """What the Message records of a closed chunk say, read back from its bytes at their offsets: the
    message index entries of each channel, in order of their offsets (the order they were added)."""

    def __init__(self, chunk: _Chunk) -> None:
        offsets = np.frombuffer(chunk.offsets, dtype=np.uint64).astype(np.int64)
        raw = np.frombuffer(chunk.buf, dtype=np.uint8)
        channels = raw[offsets[:, None] + np.arange(_CHANNEL_AT, _CHANNEL_AT + 2)].view("<u2")[:, 0]
        times = raw[offsets[:, None] + np.arange(_LOG_TIME_AT, _LOG_TIME_AT + 8)].view("<u8")[:, 0]
        self.start = int(times.min())
        self.end = int(times.max())
        self.index: dict[int, bytes] = {}
        """per channel id: its (log time, offset) entries, as the MessageIndex record holds them"""
        self.counts: dict[int, int] = {}
        entries = np.empty((len(offsets), 2), dtype="<u8")
        entries[:, 0] = times
        entries[:, 1] = offsets
        for channel_id in np.unique(channels).tolist():
            mine = entries[channels == channel_id]
            self.index[channel_id] = mine.tobytes()
            self.counts[channel_id] = len(mine)


class RecordingWriter:
    """Writes one MCAP file (see the module docstring); channels are registered the first time a topic
    is seen. Not thread-safe: one thread adds, flushes and finishes."""

    def __init__(
        self,
        path: str | Path,
        compression: str = "zstd",
        chunk_size: int = DEFAULT_CHUNK_SIZE,
        backlog_bytes: int = DEFAULT_BACKLOG_BYTES,
    ) -> None:
        if compression not in COMPRESSIONS:
            raise RecordingError(f"compression {compression!r} is not one of {', '.join(COMPRESSIONS)}")
        if not backlog_bytes >= chunk_size:
            raise RecordingError(
                f"backlog = {backlog_bytes} bytes must be >= the chunk size, {chunk_size} bytes"
            )
        self.path = Path(path)
        self.compression = compression
        self.chunk_size = chunk_size
        self.backlog_bytes = backlog_bytes
        self._fh: BinaryIO = _open_exclusive(self.path)
        # the chunk indexes until the summary (deleted by the OS even on SIGKILL)
        self._index_file: BinaryIO = tempfile.TemporaryFile(  # noqa: SIM115
            dir=self.path.parent, prefix=".axisflow-chunk-index-"
        )
        self.channels: dict[str, int] = {}
        self._topics: dict[int, str] = {}
        self._schemas: dict[tuple[str, str, bytes], Schema] = {}
        self._channel_records: list[Channel] = []
        self._messages = 0
        """messages in the chunks closed so far"""
        self.dropped: dict[str, int] = {}
        """messages dropped because the backlog was full, per topic"""
        self._chunk = _Chunk()
        self._queued = 0
        """bytes of the chunks handed to the writer thread and not yet written (shared with it)"""
        self._lock = threading.Lock()
        self._work: queue.SimpleQueue = queue.SimpleQueue()
        self._failure: Exception | None = None
        self._closed = False
        # state of the writer thread (read by this thread only after joining it)
        self._counts: dict[int, int] = {}
        self._start_time: int | None = None
        self._end_time = 0
        self._chunk_count = 0
        self._written = 0
        self._data_crc = 0
        self._write(MAGIC + _record(Header(profile="ros2", library=LIBRARY)))
        self._thread = threading.Thread(target=self._writer, name="mcap-writer", daemon=True)
        self._thread.start()

    # ---- the receiving thread -----------------------------------------------------------------------
    def channel_for(self, topic: str, type_name: str | None, message_encoding: str = "cdr") -> int:
        """The channel of ``topic``, registered with the ros2msg schema of ``type_name`` if known."""
        channel_id = self.channels.get(topic)
        if channel_id is not None:
            return channel_id
        schema_id = 0
        if type_name in SCHEMAS:
            key = (type_name, "ros2msg", SCHEMAS[type_name].encode())
            schema = self._schemas.get(key)
            if schema is None:
                schema = self._schemas[key] = Schema(len(self._schemas) + 1, key[2], key[1], key[0])
                self._chunk.buf += _record(schema)
            schema_id = schema.id
        metadata = {"offered_qos_profiles": OFFERED_QOS_PROFILES} if message_encoding == "cdr" else {}
        channel = Channel(len(self.channels) + 1, topic, message_encoding, metadata, schema_id)
        self._chunk.buf += _record(channel)
        self._channel_records.append(channel)
        self.channels[topic] = channel.id
        self._topics[channel.id] = topic
        return channel.id

    def add(
        self, channel_id: int, log_time_ns: int, publish_time_ns: int, sequence: int, data: bytes
    ) -> bool:
        """Add one message; False if the backlog was full and it was dropped (counted in
        :attr:`dropped`)."""
        chunk = self._chunk
        buf = chunk.buf
        offset = len(buf)
        size = len(data)
        if self._queued + offset + _MESSAGE.size + size > self.backlog_bytes:
            topic = self._topics[channel_id]
            self.dropped[topic] = self.dropped.get(topic, 0) + 1
            return False
        if self._failure is not None:
            raise self._failure
        buf += _MESSAGE.pack(
            _MESSAGE_OPCODE,
            _MESSAGE_FIXED + size,
            channel_id,
            sequence & 0xFFFFFFFF,
            log_time_ns,
            publish_time_ns,
        )
        buf += data
        chunk.offsets.append(offset)
        if len(buf) >= self.chunk_size:
            self._close_chunk()
        return True

    @property
    def messages(self) -> int:
        """Messages written (added and not dropped)."""
        return self._messages + len(self._chunk.offsets)

    @property
    def backlog(self) -> int:
        """Bytes not written yet (chunks waiting for the writer thread and the open chunk)."""
        return self._queued + len(self._chunk.buf)

    @property
    def bytes_written(self) -> int:
        """Bytes in the file, and in chunks on their way to it (uncompressed)."""
        return self._written + self.backlog

    def _close_chunk(self) -> None:
        chunk = self._chunk
        if chunk.buf:
            with self._lock:
                self._queued += len(chunk.buf)
            self._messages += len(chunk.offsets)
            self._work.put(chunk)
            self._chunk = _Chunk()
        if self._failure is not None:
            raise self._failure

    def flush(self, wait: bool = True) -> None:
        """Write the open chunk and fsync. ``wait``: return once it is on disk, so a crash after this
        loses nothing added so far; else return at once (the writer thread writes and fsyncs it next,
        and the caller goes on receiving meanwhile)."""
        self._close_chunk()
        synced = threading.Event()
        self._work.put(synced)
        if wait:
            synced.wait()
            if self._failure is not None:
                raise self._failure

    def finish(self, missed: dict[str, int] | None = None) -> None:
        """Write what is left, the loss record (with ``missed``: messages lost on the way, per topic,
        from the sequence numbers), the summary and footer; fsync and close (idempotent)."""
        if self._closed:
            return
        self._closed = True
        try:
            self._close_chunk()
        finally:
            self._work.put(_FINISH)
            self._thread.join()
        try:
            if self._failure is not None:
                raise self._failure
            self._finish_file(missed or {})
        finally:
            self._index_file.close()
            self._fh.close()

    # ---- the writer thread --------------------------------------------------------------------------
    def _writer(self) -> None:
        while True:
            item = self._work.get()
            if item is _FINISH:
                return
            try:
                if self._failure is not None:
                    continue  # the file is broken: what follows is not written (the error is raised)
                if isinstance(item, threading.Event):
                    self._fh.flush()
                    os.fsync(self._fh.fileno())
                else:
                    self._write_chunk(item)
            except Exception as exc:  # raised by the next add/flush/finish, never lost with the thread
                self._failure = exc
            finally:
                if isinstance(item, threading.Event):
                    item.set()
                else:
                    with self._lock:
                        self._queued -= len(item.buf)

    def _write(self, data: bytes | bytearray) -> None:
        self._fh.write(data)
        self._data_crc = crc32(data, self._data_crc)
        self._written += len(data)

    def _write_chunk(self, chunk: _Chunk) -> None:
        data = bytes(chunk.buf)
        if not chunk.offsets:  # only schemas and channels: write them as they are
            self._write(data)
            return
        messages = _ChunkMessages(chunk)
        for channel_id, n in messages.counts.items():
            self._counts[channel_id] = self._counts.get(channel_id, 0) + n
        self._start_time = (
            messages.start if self._start_time is None else min(self._start_time, messages.start)
        )
        self._end_time = max(self._end_time, messages.end)
        compressed = _compress(self.compression, data)
        record = _record(
            Chunk(
                compression="" if self.compression == "none" else self.compression,
                data=compressed,
                message_start_time=messages.start,
                message_end_time=messages.end,
                uncompressed_crc=crc32(data),
                uncompressed_size=len(data),
            )
        )
        chunk_start = self._written
        self._write(record)
        index_start = self._written
        offsets = {}
        indexes = bytearray()
        for channel_id, entries in messages.index.items():
            offsets[channel_id] = index_start + len(indexes)
            # MessageIndex: channel id, then the (log time, offset) array with its byte length
            body = _U16_U32.pack(channel_id, len(entries)) + entries
            indexes += struct.pack("<BQ", Opcode.MESSAGE_INDEX, len(body)) + body
        self._write(indexes)
        self._chunk_count += 1
        self._index_file.write(
            _record(
                ChunkIndex(
                    message_start_time=messages.start,
                    message_end_time=messages.end,
                    chunk_start_offset=chunk_start,
                    chunk_length=len(record),
                    message_index_offsets=offsets,
                    message_index_length=len(indexes),
                    compression="" if self.compression == "none" else self.compression,
                    compressed_size=len(compressed),
                    uncompressed_size=len(data),
                )
            )
        )

    # ---- the end ------------------------------------------------------------------------------------
    def _finish_file(self, missed: dict[str, int]) -> None:
        """Loss record, DataEnd, summary (schemas, channels, statistics, chunk and metadata indexes,
        summary offsets) and footer, as mcap's writer lays them out."""
        loss = {"dropped_messages": str(sum(self.dropped.values())), "backlog_bytes": str(self.backlog_bytes)}
        loss.update({f"dropped {topic}": str(n) for topic, n in sorted(self.dropped.items())})
        loss.update({f"missed {topic}": str(n) for topic, n in sorted(missed.items()) if n})
        metadata = _record(Metadata(name=LOSS_METADATA, metadata=loss))
        metadata_offset = self._written
        self._write(metadata)
        self._fh.write(_record(DataEnd(data_section_crc=self._data_crc)))
        summary_start = self._fh.tell()
        self._index_file.seek(0)
        chunk_indexes = self._index_file.read()
        statistics = Statistics(
            message_count=self._messages,
            schema_count=len(self._schemas),
            channel_count=len(self._channel_records),
            attachment_count=0,
            metadata_count=1,
            chunk_count=self._chunk_count,
            message_start_time=self._start_time or 0,
            message_end_time=self._end_time,
            channel_message_counts={c.id: self._counts.get(c.id, 0) for c in self._channel_records},
        )
        groups = [
            (Opcode.SCHEMA, b"".join(_record(s) for s in self._schemas.values())),
            (Opcode.CHANNEL, b"".join(_record(c) for c in self._channel_records)),
            (Opcode.STATISTICS, _record(statistics)),
            (Opcode.CHUNK_INDEX, chunk_indexes),
            (Opcode.METADATA_INDEX, _record(MetadataIndex(metadata_offset, len(metadata), LOSS_METADATA))),
        ]
        summary = bytearray()
        offsets = bytearray()
        for opcode, data in groups:
            offsets += _record(SummaryOffset(opcode, summary_start + len(summary), len(data)))
            summary += data
        summary_offset_start = summary_start + len(summary)
        summary += offsets
        crc = crc32(summary)
        crc = crc32(struct.pack("<BQQQ", Opcode.FOOTER, 20, summary_start, summary_offset_start), crc)
        self._fh.write(summary)
        self._fh.write(_record(Footer(summary_start, summary_offset_start, crc)) + MAGIC)
        self._fh.flush()
        os.fsync(self._fh.fileno())


def _record(record: object) -> bytes:
    builder = RecordBuilder()
    record.write(builder)  # type: ignore[attr-defined]
    return builder.end()


def _compress(compression: str, data: bytes) -> bytes:
    if compression == "zstd":
        return zstandard.compress(data)
    if compression == "lz4":
        return lz4.frame.compress(data)
    return data
