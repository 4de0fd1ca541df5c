"""What a recording is to be (:class:`RecorderConfig`, validated data) and the check of its outputs before
anything is opened. No Zenoh here: the command line builds it before it loads Zenoh; the
:class:`~.recorder.Recorder` runs it."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from ...model.files import OutputError, check_output_file
from ..errors import RecordingError
from ..wire.keys import all_keys
from .chunking import COMPRESSION_NAMES, DEFAULT_BACKLOG_BYTES, DEFAULT_CHUNK_SIZE

DEFAULT_QUEUE_CAPACITY = 1 << 16
"""samples Zenoh's receive channel holds before it applies back-pressure (a JointState sample held
there costs ~0.5 kB: ~35 MB when full; docs/performance.md)"""
LIVE_STAMP_WINDOW_NS = 1_000_000_000
"""a stamp further than this from the wall clock is not live (e.g. a replay): no latency from it"""


@dataclass(frozen=True)
class RecorderConfig:
    output: Path
    keys: str = field(default_factory=all_keys)
    duration_s: float | None = None
    compression: str = "zstd"
    flush_interval_s: float = 1.0
    split_bytes: int | None = None
    split_duration_s: float | None = None
    chunk_size: int = DEFAULT_CHUNK_SIZE
    queue_capacity: int = DEFAULT_QUEUE_CAPACITY
    backlog_bytes: int = DEFAULT_BACKLOG_BYTES
    """received and not yet written (the writer's chunks in memory): past it, messages are dropped whole,
    counted per topic, reported once a second and recorded in the file (RecordingWriter)"""
    join_timeout_s: float | None = None
    """how long the publishers on ``keys`` may take to answer the join's hellos [s] (None: the default of
    :mod:`~axisflow.acquisition.bus.readiness`)"""
    overwrite: bool = False
    """replace existing recordings (``output`` or its split files) instead of refusing to start"""

    def __post_init__(self) -> None:
        if self.compression not in COMPRESSION_NAMES:
            raise RecordingError(
                f"compression {self.compression!r} is not one of {', '.join(COMPRESSION_NAMES)}"
            )
        for name, value, unit in (
            ("duration", self.duration_s, "s"),
            ("flush interval", self.flush_interval_s, "s"),
            ("split size", self.split_bytes, "bytes"),
            ("split duration", self.split_duration_s, "s"),
            ("join timeout", self.join_timeout_s, "s"),
            ("backlog", self.backlog_bytes, "bytes"),
        ):
            if value is not None and not value > 0:
                raise RecordingError(f"recorder {name} = {value} {unit} must be > 0 {unit}")
        if not self.backlog_bytes >= self.chunk_size:
            raise RecordingError(
                f"recorder backlog = {self.backlog_bytes} bytes must be >= the chunk size, "
                f"{self.chunk_size} bytes"
            )
        if Path(self.output).suffix != ".mcap":
            raise RecordingError(f"output {self.output} must end in .mcap")


def check_outputs(config: RecorderConfig) -> None:
    """Refuse to start when the output cannot be written (its folder missing or unwritable, its name
    too long, a directory) or (without ``overwrite``) the output, or one of its split files, exists
    already."""
    out = Path(config.output)
    split = config.split_bytes is not None or config.split_duration_s is not None
    try:
        check_output_file(split_path(out, 0) if split else out, overwrite=True)
    except OutputError as exc:
        raise RecordingError(str(exc)) from None
    if config.overwrite:
        return
    existing = sorted(out.parent.glob(f"{out.stem}_[0-9][0-9][0-9][0-9]{out.suffix}")) if split else []
    if not split and out.exists():
        existing = [out]
    if existing:
        raise RecordingError(
            f"output {existing[0]} already exists"
            + (f" (and {len(existing) - 1} more split files)" if len(existing) > 1 else "")
            + ": choose another name or pass --overwrite"
        )


def split_path(output: Path, index: int) -> Path:
    return output.with_name(f"{output.stem}_{index:04d}{output.suffix}")
