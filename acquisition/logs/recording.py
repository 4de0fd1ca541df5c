"""Reading a recording, complete or truncated by a crash.

A complete MCAP file (with summary and footer) is read through its index. A file whose writer was
killed has no footer; :func:`iter_recording` then falls back to a streaming read, which returns every
message up to the last complete chunk (with the recorder's once-a-second flush: all but at most the
last second) and stops there.
"""

from __future__ import annotations

import logging
import struct
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

from mcap.exceptions import McapError
from mcap.reader import make_reader
from mcap.records import Channel, Message, Schema
from mcap.stream_reader import StreamReader
from mcap.summary import Summary

from ..errors import RecordingError

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class RecordedMessage:
    schema: Schema | None
    channel: Channel
    message: Message


MCAP_MAGIC = b"\x89MCAP0\r\n"


def check_mcap(path: str | Path) -> Path:
    """``path`` as a Path if it exists and starts with the MCAP magic; else a :class:`RecordingError`."""
    p = Path(path)
    if not p.is_file():
        raise RecordingError(f"recording {p} does not exist")
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
    except (McapError, OSError, ValueError, EOFError, struct.error):
        return False, None
    return True, summary


def is_complete(path: str | Path) -> bool:
    """True if the file has a readable summary/footer (what a clean finish writes)."""
    try:
        with open(path, "rb") as fh:
            return read_summary(fh)[0]
    except OSError:
        return False


def iter_recording(path: str | Path, complete_only: bool = False) -> Iterator[RecordedMessage]:
    """Messages of a recording in file order (truncated files: up to the last complete chunk)."""
    p = check_mcap(path)
    if is_complete(p):
        with open(p, "rb") as fh:
            for schema, channel, message in make_reader(fh).iter_messages(log_time_order=True):
                yield RecordedMessage(schema, channel, message)
        return
    if complete_only:
        raise RecordingError(f"recording {p} has no summary/footer (run `axisflow recover {p}`)")
    yield from _stream(p)


def _stream(path: Path) -> Iterator[RecordedMessage]:
    schemas: dict[int, Schema] = {}
    channels: dict[int, Channel] = {}
    with open(path, "rb") as fh:
        reader = StreamReader(fh, emit_chunks=False)
        try:
            for record in reader.records:
                if isinstance(record, Schema):
                    schemas[record.id] = record
                elif isinstance(record, Channel):
                    channels[record.id] = record
                elif isinstance(record, Message):
                    channel = channels.get(record.channel_id)
                    if channel is None:
                        continue
                    yield RecordedMessage(schemas.get(channel.schema_id), channel, record)
        except (McapError, EOFError, ValueError) as exc:
            log.info("%s: streaming read stopped at the truncation: %s", path, exc)
        except Exception as exc:  # the stream reader may fail in other ways on a cut-off record
            log.info("%s: streaming read stopped at the truncation (%s: %s)", path, type(exc).__name__, exc)
