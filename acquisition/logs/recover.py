"""Rebuilding a complete MCAP file from one whose writer was killed.

A killed recorder leaves a file without summary and footer; seeking readers, rosbags and rerun refuse
it. :func:`recover` reads it with a streaming reader up to the last complete chunk and rewrites its
schemas, channels (with metadata) and messages (log/publish time, sequence, bytes unchanged) into a new
file with chunk compression, summary and footer, which every tool opens.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from pathlib import Path

from ..errors import RecordingError
from .mcap_writer import Ros2McapWriter
from .recording import check_mcap, is_complete, iter_recording


@dataclass(frozen=True)
class RecoverReport:
    source: Path
    output: Path
    messages: int
    channels: int
    was_complete: bool
    first_log_ns: int
    last_log_ns: int

    def format(self) -> str:
        span = (self.last_log_ns - self.first_log_ns) * 1e-9 if self.messages else 0.0
        state = "complete already" if self.was_complete else "truncated"
        return (
            f"recovered {self.messages} messages on {self.channels} channels ({span:.3f} s) "
            f"from {self.source} ({state}) into {self.output}"
        )


def default_output(source: Path) -> Path:
    return source.with_name(f"{source.stem}.recovered{source.suffix}")


def recover(
    source: str | Path, output: str | Path | None = None, compression: str = "zstd", overwrite: bool = False
) -> RecoverReport:
    """Rewrite ``source`` (possibly truncated) into a complete file ``output``.

    Refuses an ``output`` that is not ``.mcap``, is the source, or exists (unless ``overwrite``). When
    the source holds no complete message, nothing is written and a :class:`RecordingError` says so.
    """
    src = Path(source)
    dst = Path(output) if output is not None else default_output(src)
    check_mcap(src)  # before the output is created: nothing written for a missing or non-MCAP file
    if dst.suffix != ".mcap":
        raise RecordingError(f"output {dst} must end in .mcap")
    if dst.resolve() == src.resolve():
        raise RecordingError(f"output {dst} must differ from the source {src}")
    if dst.exists() and not overwrite:
        raise RecordingError(f"output {dst} already exists: choose another name or pass --overwrite")
    was_complete = is_complete(src)
    records = iter_recording(src)
    first_record = next(records, None)
    if first_record is None:
        raise RecordingError(
            f"{src} holds no complete message to recover (its first chunk was never written)"
        )
    writer = Ros2McapWriter(dst, compression)
    channel_ids: dict[int, int] = {}
    n, first, last = 0, 0, 0
    try:
        for rec in itertools.chain([first_record], records):
            ch = rec.channel
            out_channel = channel_ids.get(ch.id)
            if out_channel is None:
                schema_id = 0
                if rec.schema is not None:
                    schema_id = writer.register_schema(rec.schema.name, rec.schema.encoding, rec.schema.data)
                out_channel = writer.register_channel(
                    ch.topic, ch.message_encoding, schema_id, dict(ch.metadata)
                )
                channel_ids[ch.id] = out_channel
            m = rec.message
            writer.add(out_channel, m.log_time, m.publish_time, m.sequence, m.data)
            if n == 0:
                first = m.log_time
            last = max(last, m.log_time)
            n += 1
    finally:
        writer.finish()
    return RecoverReport(src, dst, n, len(channel_ids), was_complete, first, last)
