"""``axisflow import`` as a library function: foreign logs (CSV, Parquet, MATLAB) → one JointState MCAP.

:func:`import_logs` reads each file (:func:`~.table.read_table`), maps its columns to one joint
(:func:`~.samples.joint_samples`), and only when every file has passed every check writes them, as the
recorder writes a log (:func:`~.recording.write_joint_states`), atomically (nothing is written on an
error or a signal, an existing output only with ``overwrite``, an input never).

**Several files** make one log in time order: each keeps its own stamps, and files whose time ranges
overlap are refused (naming both ranges): a log is one stretch of one joint's time. Files that follow
one another (a long capture exported in parts) become one recording, with any gap between them a
hole that the refit counts. Files that each start at 0 (separate runs) overlap: import each into its
own MCAP (``axisflow identify`` fits several logs together, and reads such files directly). All
files must map to the same joint (name and side).

:func:`import_for_reading` imports each file on its own into a folder and hands back
:class:`ImportedLog` paths: what ``axisflow identify`` reads when it is given foreign files (the same
import, the same reader: no second path for the data).
"""

from __future__ import annotations

import dataclasses
import itertools
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from ...model.files import InputError, OutputError, atomic_path, check_distinct_inputs, check_output_file
from .column_map import ColumnMap
from .errors import ForeignLogError
from .recording import DEFAULT_TOPIC, write_joint_states
from .samples import NS_PER_S, JointSamples, joint_samples
from .table import CsvOptions, read_table


@dataclass(frozen=True)
class ImportedFile:
    """What one file gave: its rows, the samples written, those dropped (a missing value each), its
    first and last stamp [ns] and the units its signals were read in."""

    source: Path
    rows: int
    samples: int
    dropped: int
    start_ns: int
    end_ns: int
    units: dict[str, str]

    @property
    def duration_s(self) -> float:
        return (self.end_ns - self.start_ns) / NS_PER_S


@dataclass(frozen=True)
class ImportResult:
    """The MCAP written: its path, topic, joint and side (``carriage``: m, m/s, N; ``motor``: rad,
    rad/s, N·m), messages, and each file's part in time order."""

    path: Path
    topic: str
    joint: str
    side: str
    messages: int
    files: tuple[ImportedFile, ...]

    def as_dict(self) -> dict:
        """The result as JSON-ready data (``axisflow import --json``)."""
        out = dataclasses.asdict(self)
        out["path"] = str(self.path)
        for f in out["files"]:
            f["source"] = str(f["source"])
        return out

    def describe(self) -> str:
        """One line per file, then what was written."""
        lines = []
        for f in self.files:
            units = ", ".join(f"{what} [{unit}]" for what, unit in f.units.items())
            dropped = f", {f.dropped} rows with a missing value dropped (lost samples)" if f.dropped else ""
            lines.append(f"{f.source}: {f.samples} samples over {f.duration_s:.3f} s from {units}{dropped}")
        lines.append(
            f"wrote {self.path}: {self.messages} JointState messages on {self.topic}, joint {self.joint!r} "
            f"({self.side} side)"
        )
        return "\n".join(lines)


def read_joint_samples(
    paths: Sequence[str | Path],
    cmap: ColumnMap,
    file_format: str | None = None,
    csv: CsvOptions | None = None,
) -> list[JointSamples]:
    """Each file's joint, checked, in time order; an error if two overlap or differ in joint or side."""
    try:
        check_distinct_inputs(paths, "log")
    except InputError as exc:
        raise ForeignLogError(str(exc)) from None
    logs = sorted(
        (joint_samples(read_table(p, file_format, csv), cmap) for p in paths), key=lambda s: s.start_ns
    )
    for a, b in itertools.pairwise(logs):
        if (a.joint, a.side) != (b.joint, b.side):
            raise ForeignLogError(
                f"{a.source} gives joint {a.joint!r} ({a.side} side) and {b.source} joint {b.joint!r} "
                f"({b.side} side): one log holds one joint"
            )
        if b.start_ns <= a.end_ns:
            raise ForeignLogError(
                f"{a.source} ({_span(a)}) and {b.source} ({_span(b)}) overlap in time: files of one log "
                "follow one another; import each into its own MCAP"
            )
    return logs


def _span(s: JointSamples) -> str:
    return f"{s.start_ns / NS_PER_S:.6f} s to {s.end_ns / NS_PER_S:.6f} s"


def import_logs(
    paths: Sequence[str | Path],
    cmap: ColumnMap,
    out: str | Path,
    *,
    topic: str = DEFAULT_TOPIC,
    overwrite: bool = False,
    file_format: str | None = None,
    csv: CsvOptions | None = None,
) -> ImportResult:
    """Import ``paths`` into the MCAP file ``out`` (see the module docstring)."""
    if not paths:
        raise ForeignLogError("no file to import")
    if not topic.startswith("/") or topic.endswith("/") or " " in topic:
        raise ForeignLogError(f"topic {topic!r} must be a ROS 2 topic name such as /joint_states")
    try:
        target = check_output_file(out, inputs=paths, overwrite=overwrite, suffix=".mcap")
    except OutputError as exc:
        raise ForeignLogError(str(exc)) from None
    logs = read_joint_samples(paths, cmap, file_format, csv)
    with atomic_path(target) as part:
        messages = write_joint_states(part, logs, topic)
    files = tuple(
        ImportedFile(s.source, s.rows, len(s), s.dropped, s.start_ns, s.end_ns, s.units) for s in logs
    )
    return ImportResult(target, topic, logs[0].joint, logs[0].side, messages, files)


@dataclass(frozen=True)
class ImportedLog(os.PathLike):
    """A foreign file imported for reading: as a path (``os.fspath``) it is the MCAP the import wrote;
    as text (``str``) it is the file the user named, so that whatever reads it names that file."""

    source: Path
    mcap: Path
    side: str
    joint: str

    def __fspath__(self) -> str:
        return str(self.mcap)

    def __str__(self) -> str:
        return str(self.source)


def import_for_reading(
    paths: Sequence[str | Path],
    cmap: ColumnMap,
    folder: str | Path,
    *,
    file_format: str | None = None,
    csv: CsvOptions | None = None,
) -> list[ImportedLog]:
    """Each of ``paths`` imported on its own into ``folder`` (e.g. a temporary one), in the order given."""
    out = []
    for k, path in enumerate(paths):
        target = Path(folder) / f"{k}-{Path(path).stem}.mcap"
        result = import_logs([path], cmap, target, file_format=file_format, csv=csv)
        out.append(ImportedLog(Path(path), result.path, result.side, result.joint))
    return out
