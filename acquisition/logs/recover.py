"""Rebuilding a complete MCAP file from a damaged one: a recording whose writer was killed (no summary,
no footer: seeking readers, rosbags and rerun refuse it) or one with chunks that cannot be read.

:func:`recover` reads the source through the log reader (:func:`.reader.iter_recording`: up to the
last complete chunk, every chunk that cannot be read skipped and counted) and rewrites its schemas,
channels (with metadata) and messages (log/publish time, sequence, bytes unchanged) into a new file
with chunk compression, summary and footer, which every tool opens. The new file is written beside the
output under a temporary name and becomes the output only once complete (:func:`atomic_path`): a
failure or a signal leaves nothing; so does a source without one readable message. The output is
never the source (nor a link to it), and an existing output is replaced only with ``overwrite``.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from ...model.files import atomic_path, check_output_file
from ..errors import RecordingError
from .mcap_writer import Ros2McapWriter
from .reader import SkippedChunk, check_mcap, is_complete, iter_recording
from .reader.messages import skipped_summary, why_nothing

PROGRESS_EVERY = 100_000
"""messages between two calls of ``progress``"""


@dataclass(frozen=True)
class RecoverReport:
    source: Path
    output: Path
    messages: int
    channels: int
    was_complete: bool
    first_log_ns: int
    last_log_ns: int
    skipped: tuple[SkippedChunk, ...] = ()
    """chunks of the source that could not be read (their messages are not in the output)"""

    def format(self) -> str:
        span = (self.last_log_ns - self.first_log_ns) * 1e-9 if self.messages else 0.0
        state = "complete already" if self.was_complete else "truncated"
        text = (
            f"recovered {self.messages} messages on {self.channels} channels ({span:.3f} s) "
            f"from {self.source} ({state}) into {self.output}"
        )
        if self.skipped:
            text += "; " + skipped_summary(self.skipped)
        return text


def default_output(source: Path) -> Path:
    return source.with_name(f"{source.stem}.recovered{source.suffix}")


def recover(
    source: str | Path,
    output: str | Path | None = None,
    compression: str = "zstd",
    overwrite: bool = False,
    progress: Callable[[int], None] | None = None,
) -> RecoverReport:
    """Rewrite ``source`` (truncated, or with chunks that cannot be read) into a complete file
    ``output`` (default: SOURCE.recovered.mcap), atomically.

    Refuses, before anything is written, an ``output`` that is not ``.mcap``, is the source (the same
    file under any name), or exists (unless ``overwrite``). When the source holds no readable message,
    nothing is written and a :class:`RecordingError` says so. ``progress`` is called with the number
    of messages copied so far, every :data:`PROGRESS_EVERY`.
    """
    src = check_mcap(source)  # before the output is created: nothing written for a bad source
    dst = Path(output) if output is not None else default_output(src)
    check_output_file(dst, inputs=[src], overwrite=overwrite, suffix=".mcap")
    was_complete = is_complete(src)
    skipped: list[SkippedChunk] = []
    records = iter_recording(src, on_skip=skipped.append)
    first_record = next(records, None)
    if first_record is None:
        raise RecordingError(f"{src} holds no complete message to recover ({why_nothing(skipped)})")
    channel_ids: dict[int, int] = {}
    n, first, last = 0, 0, 0
    with atomic_path(dst) as part:
        writer = Ros2McapWriter(part, compression)
        try:
            for rec in itertools.chain([first_record], records):
                ch = rec.channel
                out_channel = channel_ids.get(ch.id)
                if out_channel is None:
                    schema_id = 0
                    if rec.schema is not None:
                        schema = rec.schema
                        schema_id = writer.register_schema(schema.name, schema.encoding, schema.data)
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
                if progress is not None and n % PROGRESS_EVERY == 0:
                    progress(n)
        finally:
            writer.finish()
    return RecoverReport(src, dst, n, len(channel_ids), was_complete, first, last, tuple(skipped))
