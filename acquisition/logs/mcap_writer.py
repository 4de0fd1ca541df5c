"""An MCAP file in the ROS 2 profile, flushed and fsynced on demand.

Header profile ``ros2``; schemas in ``ros2msg`` encoding; channels with message encoding ``cdr`` and
the ``offered_qos_profiles`` metadata ROS 2 tools expect; chunk compression zstd (default), lz4 or
none. :meth:`Ros2McapWriter.flush` closes the open chunk, writes it and fsyncs, so after a crash the
file holds everything up to the last flush (read it with a streaming reader or
:func:`axisflow.acquisition.logs.recover.recover`).
"""

from __future__ import annotations

import fcntl
import logging
import os
import stat
import tempfile
from importlib.metadata import version as package_version
from pathlib import Path
from typing import BinaryIO

from mcap.data_stream import RecordBuilder
from mcap.writer import CompressionType, Writer

from ..errors import RecordingError
from ..wire.messages import SCHEMAS
from .chunking import COMPRESSION_NAMES, DEFAULT_CHUNK_SIZE

log = logging.getLogger(__name__)

COMPRESSIONS: dict[str, CompressionType] = {name: CompressionType[name.upper()] for name in COMPRESSION_NAMES}
"""mcap's compression of each name of :data:`~.chunking.COMPRESSION_NAMES`"""
LIBRARY = f"axisflow {package_version('axisflow')}"

# rosbag2's default QoS for a reliable, volatile, keep-last publisher, as YAML
OFFERED_QOS_PROFILES = """- history: 3
  depth: 0
  reliability: 1
  durability: 2
  deadline:
    sec: 2147483647
    nsec: 4294967295
  lifespan:
    sec: 2147483647
    nsec: 4294967295
  liveliness: 1
  liveliness_lease_duration:
    sec: 2147483647
    nsec: 4294967295
  avoid_ros_namespace_conventions: false"""


class Ros2McapWriter:
    """Writes one MCAP file; channels are registered the first time a topic is seen."""

    def __init__(
        self, path: str | Path, compression: str = "zstd", chunk_size: int = DEFAULT_CHUNK_SIZE
    ) -> None:
        if compression not in COMPRESSIONS:
            raise RecordingError(f"compression {compression!r} is not one of {', '.join(COMPRESSIONS)}")
        self.path = Path(path)
        self._fh: BinaryIO = _open_exclusive(self.path)
        # message and chunk indexes are written (rerun's importer needs the message indexes)
        self._writer = Writer(self._fh, chunk_size=chunk_size, compression=COMPRESSIONS[compression])
        self._spill = _ChunkIndexSpill(self._writer, self.path.parent)
        self._writer.start(profile="ros2", library=LIBRARY)
        self._schemas: dict[tuple[str, str, bytes], int] = {}
        self.channels: dict[str, int] = {}
        self.messages = 0
        self._closed = False

    def register_schema(self, name: str, encoding: str, data: bytes) -> int:
        key = (name, encoding, data)
        if key not in self._schemas:
            self._schemas[key] = self._writer.register_schema(name=name, encoding=encoding, data=data)
        return self._schemas[key]

    def register_channel(
        self, topic: str, message_encoding: str, schema_id: int, metadata: dict[str, str] | None = None
    ) -> int:
        channel_id = self._writer.register_channel(
            topic=topic, message_encoding=message_encoding, schema_id=schema_id, metadata=metadata or {}
        )
        self.channels[topic] = channel_id
        return channel_id

    def channel_for(self, topic: str, type_name: str | None, message_encoding: str = "cdr") -> int:
        """The channel of ``topic``, registered with the ros2msg schema of ``type_name`` if known."""
        channel_id = self.channels.get(topic)
        if channel_id is None:
            schema_id = 0
            metadata = {}
            if type_name in SCHEMAS:
                schema_id = self.register_schema(type_name, "ros2msg", SCHEMAS[type_name].encode())
            if message_encoding == "cdr":
                metadata = {"offered_qos_profiles": OFFERED_QOS_PROFILES}
            channel_id = self.register_channel(topic, message_encoding, schema_id, metadata)
        return channel_id

    def add(
        self, channel_id: int, log_time_ns: int, publish_time_ns: int, sequence: int, data: bytes
    ) -> None:
        self._writer.add_message(channel_id, log_time_ns, data, publish_time_ns, sequence & 0xFFFFFFFF)
        self.messages += 1

    def flush(self) -> None:
        """Write the open chunk and fsync: a crash after this loses nothing written so far."""
        self._writer.flush()
        os.fsync(self._fh.fileno())
        self._spill.spill()

    @property
    def bytes_written(self) -> int:
        return self._fh.tell()

    def finish(self) -> None:
        """Write the summary and footer, fsync and close (idempotent)."""
        if self._closed:
            return
        self._closed = True
        self._spill.restore()
        self._writer.finish()
        self._spill.close()
        self._fh.flush()
        os.fsync(self._fh.fileno())
        self._fh.close()


def _open_exclusive(path: Path) -> BinaryIO:
    """``path`` opened for writing from its start, holding an exclusive advisory lock (``flock``) for as
    long as it is open: a second recorder on the same file (even with --overwrite) is refused before it
    truncates a recording in progress."""
    try:
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o666)
    except OSError as exc:
        raise RecordingError(f"cannot write {path}: {exc.strerror}") from None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(fd)
        raise RecordingError(f"{path} is being recorded by another process: choose another name") from None
    if stat.S_ISREG(os.fstat(fd).st_mode):  # (a device, e.g. /dev/full in a test, has no length)
        os.ftruncate(fd, 0)
    return os.fdopen(fd, "wb")


class _SerializedRecords:
    """Already-serialized MCAP records that a ``Writer`` writes like record objects."""

    def __init__(self, data: bytes) -> None:
        self.data = data

    def write(self, builder: RecordBuilder) -> None:
        builder.write(self.data)


class _ChunkIndexSpill:
    """Keeps the writer's chunk indexes on disk instead of in memory until the summary is written.

    mcap's ``Writer`` holds one ``ChunkIndex`` object per chunk (with a dict of message-index offsets
    per channel, ~2.5 kB with 32 channels) until ``finish()`` writes the summary, so a recorder's memory
    would grow with the session (~1.5 MB/min at 32 axes, measured). After each flush the indexes are
    serialized to an anonymous temporary file (deleted by the OS even on SIGKILL) and dropped; at
    ``finish()`` they come back as one block of bytes, written into the summary unchanged.
    This needs one private attribute of mcap's ``Writer``, its list of chunk indexes (there is no public
    way to hand the summary pre-serialized indexes): mcap is pinned to 1.6.x in pyproject.toml, a
    writer without the list logs a warning (the recording stays correct, only its memory grows), and
    tests/acquisition/test_mcap_writer.py fails on an mcap whose writer no longer has it.
    """

    _ATTR = "_Writer__chunk_indices"

    def __init__(self, writer: Writer, directory: Path) -> None:
        self._writer = writer
        self._file: BinaryIO | None = None
        if isinstance(getattr(writer, self._ATTR, None), list):
            self._file = tempfile.TemporaryFile(dir=directory, prefix=".axisflow-chunk-index-")  # noqa: SIM115
        else:
            log.warning(
                "this mcap version's Writer has no %s list: chunk indexes stay in memory until the "
                "recording ends (axisflow is tested with mcap 1.6)",
                self._ATTR,
            )

    def spill(self) -> None:
        if self._file is None:
            return
        indexes = getattr(self._writer, self._ATTR)
        if not indexes:
            return
        builder = RecordBuilder()
        for index in indexes:
            index.write(builder)
        self._file.write(builder.end())
        indexes.clear()

    def restore(self) -> None:
        if self._file is None:
            return
        self.spill()
        self._file.seek(0)
        data = self._file.read()
        if data:
            getattr(self._writer, self._ATTR).insert(0, _SerializedRecords(data))

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None
