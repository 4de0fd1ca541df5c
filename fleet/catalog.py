"""The fleet's catalog: one row per log file and axis, in ``DIR/catalog.parquet``.

``axisflow fleet index PATH… --catalog DIR`` scans MCAP logs (files, or folders searched for
``*.mcap``) and records, per file and axis (:class:`CatalogEntry`): the file's size, modification time
and content hash (BLAKE2b-128 of its bytes), the joint's time span, samples and holes, and how much of
it excites friction — the speed range covered (5th and 99th percentile of |ẋ| while moving), the
reversals of the motion and the time spent moving. Speeds come from the position (a log may carry no
velocity), differentiated over :data:`SPEED_SPAN_S` so that encoder steps do not count as motion.

Which axis: in our recordings, each axis that has a state topic (a cell's log holds several:
:func:`~axisflow.acquisition.logs.recorded_axes.recorded_axes`); in a foreign log (JointState topics
but no axis of ours), the folder holding it, or the group ``axis`` (else the first group) of
``--axis-pattern`` matched against its path; its first JointState topic unless ``--topic`` names one.

Incremental: a file whose path, size and modification time match its row is not read again; a changed
file is read, and its hash says whether its content changed. A file that cannot be read is a row with
status ``unreadable`` and the reason (a warning names it); the others are indexed all the same.

The table is plain Parquet (pyarrow), readable by pandas, polars and duckdb; its schema carries
:data:`CATALOG_FORMAT` in the file's key-value metadata, which is how a catalog is recognised.
"""

from __future__ import annotations

import hashlib
import math
import re
import time
import warnings
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

import numpy as np

from ..model import AxisflowError, AxisParams
from ..model.files import atomic_path, ensure_dir
from .errors import FleetError, FleetValueError, FleetWarning

CATALOG_FILE = "catalog.parquet"
CATALOG_FORMAT = "axisflow.fleet.catalog/1"
"""the value of the key ``axisflow`` in a catalog's Parquet metadata"""
FORMAT_KEY = b"axisflow"
MOVING_M_S = 0.005
"""a sample moves when |ẋ| exceeds this [m/s] (above the encoder's step noise)"""
SPEED_SPAN_S = 0.01
"""the span of the position difference a speed is taken over [s]"""
HASH_BLOCK = 1 << 20
OK, UNREADABLE = "ok", "unreadable"


@dataclass(frozen=True)
class CatalogEntry:
    """One file and axis of the catalog (see the module docstring). Times are integer nanoseconds since
    the Unix epoch; speeds m/s; NaN or 0 where a file could not be read."""

    path: str
    """the file's absolute path"""
    axis: str
    topic: str
    joint: str
    joint_kind: str
    """motor or carriage"""
    size_bytes: int
    mtime_ns: int
    content_hash: str
    start_ns: int
    end_ns: int
    samples: int
    holes: int
    missing: int
    """samples missing in the holes"""
    speed_low_m_s: float
    speed_high_m_s: float
    reversals: int
    moving_s: float
    status: str
    reason: str

    @property
    def ok(self) -> bool:
        return self.status == OK


_ARROW_TYPES = {int: "int64", float: "float64", str: "string"}


def _schema() -> Any:
    import pyarrow as pa

    types = {"int64": pa.int64(), "float64": pa.float64(), "string": pa.string()}
    hints = {f.name: f.type for f in fields(CatalogEntry)}
    cols = [pa.field(name, types[_ARROW_TYPES[_py(hint)]], nullable=False) for name, hint in hints.items()]
    return pa.schema(cols, metadata={FORMAT_KEY: CATALOG_FORMAT.encode()})


def _py(hint: Any) -> type:
    """The Python type of a field's annotation (``from __future__ import annotations``: a string)."""
    return {"int": int, "float": float, "str": str}[hint] if isinstance(hint, str) else hint


def write_catalog(folder: Path, entries: Sequence[CatalogEntry]) -> Path:
    """``folder/catalog.parquet`` (replaced atomically), rows sorted by axis, start and path."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    rows = sorted(entries, key=lambda e: (e.axis, e.start_ns, e.path))
    columns = {f.name: [getattr(e, f.name) for e in rows] for f in fields(CatalogEntry)}
    table = pa.table(columns, schema=_schema())
    path = folder / CATALOG_FILE
    with atomic_path(path) as part:
        pq.write_table(table, part)
    return path


def read_parquet_table(path: Path, fmt: str, what: str) -> Any:
    """A Parquet file of ours (its metadata says ``fmt``) as a pyarrow table; a :class:`FleetError`
    naming the path for a missing file, a file that is not Parquet or one of another kind."""
    import pyarrow.lib
    import pyarrow.parquet as pq

    try:
        table = pq.read_table(path)
    except FileNotFoundError:
        raise FleetError(f"{path.parent} is not a fleet catalog: it has no {path.name}") from None
    except (pyarrow.lib.ArrowException, OSError) as exc:
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise FleetError(f"{path} is not a {what} (not a Parquet file: {first})") from None
    found = (table.schema.metadata or {}).get(FORMAT_KEY, b"").decode(errors="replace")
    if found != fmt:
        seen = f"its format is {found!r}" if found else "it has no axisflow format mark"
        raise FleetError(f"{path} is not a {what} ({seen}; expected {fmt!r})")
    return table


def read_catalog(folder: str | Path) -> list[CatalogEntry]:
    """The entries of the catalog in ``folder`` (a :class:`FleetError` if it is not a catalog)."""
    base = Path(folder)
    if not base.is_dir():
        raise FleetError(f"catalog {base} is not a folder (give the --catalog DIR of `axisflow fleet index`)")
    table = read_parquet_table(base / CATALOG_FILE, CATALOG_FORMAT, "fleet catalog")
    names = [f.name for f in fields(CatalogEntry)]
    missing = [n for n in names if n not in table.column_names]
    if missing:
        raise FleetError(f"{base / CATALOG_FILE} lacks the column(s) {', '.join(missing)}")
    data = table.select(names).to_pydict()
    return [CatalogEntry(**{n: data[n][i] for n in names}) for i in range(table.num_rows)]


def content_hash(path: str | Path) -> str:
    """BLAKE2b-128 of the file's bytes, hex."""
    digest = hashlib.blake2b(digest_size=16)
    with open(path, "rb") as fh:
        while block := fh.read(HASH_BLOCK):
            digest.update(block)
    return digest.hexdigest()


@dataclass(frozen=True)
class IndexSettings:
    """How ``fleet index`` names axes and reads foreign logs."""

    axis_pattern: str | None = None
    """a regular expression matched (searched) against a foreign log's path: its group ``axis`` (else
    its first group, else the whole match) names the axis"""
    topic: str | None = None
    """the JointState topic of foreign logs (default: their first)"""
    joint: str = "motor"
    """the joint read (ours have ``motor`` and ``carriage``)"""
    joint_kind: str | None = None
    """what a joint of another name measures: motor or carriage"""

    def __post_init__(self) -> None:
        if self.axis_pattern is not None:
            try:
                re.compile(self.axis_pattern)
            except re.error as exc:
                raise FleetValueError(
                    f"--axis-pattern {self.axis_pattern!r} is not a regular expression: {exc}"
                ) from None

    def foreign_axis(self, path: Path) -> str:
        if self.axis_pattern is None:
            return path.parent.name or "unnamed"
        m = re.search(self.axis_pattern, str(path))
        if m is None:
            raise FleetError(f"--axis-pattern {self.axis_pattern!r} does not match {path}")
        if "axis" in m.re.groupindex:
            return m["axis"]
        return m[1] if m.re.groups else m[0]


@dataclass(frozen=True)
class IndexResult:
    """What :func:`index_logs` did."""

    entries: tuple[CatalogEntry, ...]
    read: int
    """files read (new or changed)"""
    unchanged: int
    """files kept from the catalog without reading them"""
    removed: int
    """rows dropped: their files are gone"""
    unreadable: int
    wall_s: float
    path: Path


def find_logs(paths: Iterable[str | Path]) -> list[Path]:
    """The ``.mcap`` files among ``paths`` (folders searched recursively), absolute, sorted, once each."""
    found: set[Path] = set()
    for p in paths:
        path = Path(p)
        if path.is_dir():
            found.update(q.resolve() for q in path.rglob("*.mcap") if q.is_file())
        elif path.exists():
            found.add(path.resolve())
        else:
            raise FleetValueError(f"log path {path} does not exist")
    return sorted(found)


def index_logs(
    paths: Sequence[str | Path],
    catalog: str | Path,
    nominal: AxisParams,
    settings: IndexSettings | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> IndexResult:
    """Index ``paths`` into the catalog folder ``catalog`` (created if missing; see the module
    docstring). ``progress(done, total)`` is called after each file read."""
    t0 = time.perf_counter()
    s = settings or IndexSettings()
    logs = find_logs(paths)
    if not logs:
        raise FleetValueError(f"no MCAP log (*.mcap) under {', '.join(str(p) for p in paths)}")
    folder = Path(catalog)
    previous = read_catalog(folder) if (folder / CATALOG_FILE).exists() else []
    ensure_dir(folder)
    by_path: dict[str, list[CatalogEntry]] = {}
    for e in previous:
        by_path.setdefault(e.path, []).append(e)
    scanned = {str(p) for p in logs}
    # rows of files that are gone, outside this scan's folders, stay only if this scan did not cover them
    kept = [e for path, rows in by_path.items() if path not in scanned and Path(path).exists() for e in rows]
    removed = sum(
        len(rows) for path, rows in by_path.items() if path not in scanned and not Path(path).exists()
    )
    entries: list[CatalogEntry] = list(kept)
    todo: list[Path] = []
    unchanged = 0
    for log in logs:
        rows = by_path.get(str(log))
        st = log.stat()
        if rows and all(r.size_bytes == st.st_size and r.mtime_ns == st.st_mtime_ns for r in rows):
            entries += rows
            unchanged += 1
        else:
            todo.append(log)
    unreadable = 0
    for i, log in enumerate(todo):
        rows = index_file(log, nominal, s)
        unreadable += sum(not r.ok for r in rows)
        entries += rows
        if progress is not None:
            progress(i + 1, len(todo))
    path = folder / CATALOG_FILE
    if todo or removed or not path.exists():  # an unchanged catalog is not written again
        write_catalog(folder, entries)
    return IndexResult(
        tuple(entries), len(todo), unchanged, removed, unreadable, time.perf_counter() - t0, path
    )


def index_file(path: Path, nominal: AxisParams, settings: IndexSettings) -> list[CatalogEntry]:
    """The rows of one file: one per axis, or one ``unreadable`` row with the reason."""
    st = path.stat()
    base = {"path": str(path), "size_bytes": st.st_size, "mtime_ns": st.st_mtime_ns}
    try:
        digest = content_hash(path)
        targets = _targets(path, settings)
    except (AxisflowError, OSError) as exc:
        return [_unreadable(base, "", "", settings, "", exc)]
    rows = []
    for axis, topic in targets:
        try:
            rows.append(_entry(path, axis, topic, nominal, settings, base, digest))
        except (AxisflowError, OSError) as exc:
            rows.append(_unreadable(base, axis, topic, settings, digest, exc))
    return rows


def _unreadable(
    base: dict[str, Any], axis: str, topic: str, s: IndexSettings, digest: str, exc: BaseException
) -> CatalogEntry:
    reason = (
        str(exc) if not isinstance(exc, OSError) else f"{exc.filename or base['path']}: {exc.strerror or exc}"
    )
    warnings.warn(f"{base['path']}: cannot be indexed: {reason}", FleetWarning, stacklevel=3)
    return CatalogEntry(
        **base,
        axis=axis,
        topic=topic,
        joint=s.joint,
        joint_kind=s.joint_kind or "",
        content_hash=digest,
        start_ns=0,
        end_ns=0,
        samples=0,
        holes=0,
        missing=0,
        speed_low_m_s=math.nan,
        speed_high_m_s=math.nan,
        reversals=0,
        moving_s=0.0,
        status=UNREADABLE,
        reason=reason,
    )


def _targets(path: Path, s: IndexSettings) -> list[tuple[str, str]]:
    """(axis, topic) of each axis the file holds."""
    from ..acquisition.logs.reader import list_topics
    from ..acquisition.logs.recorded_axes import find_axes

    topics = list_topics(path)
    ours = [(a.label, a.state) for a in find_axes(topics) if a.state is not None]
    if ours and s.topic is None:
        return ours
    joint_topics = [t.topic for t in topics if t.is_joint_state]
    if s.topic is not None:
        if s.topic not in joint_topics:
            raise FleetError(
                f"{path} has no JointState topic {s.topic}; it has {', '.join(joint_topics) or 'none'}"
            )
        return [(s.foreign_axis(path), s.topic)]
    if not joint_topics:
        raise FleetError(f"{path} holds no sensor_msgs/msg/JointState topic")
    return [(s.foreign_axis(path), joint_topics[0])]


def _entry(
    path: Path,
    axis: str,
    topic: str,
    nominal: AxisParams,
    s: IndexSettings,
    base: dict[str, Any],
    digest: str,
) -> CatalogEntry:
    from ..acquisition.logs.reader import read_joint_states
    from ..identification.signals import joint_kind

    columns = read_joint_states(path, topic)
    joint = columns.joint(s.joint)
    kind = joint_kind(s.joint, s.joint_kind)
    stamps = np.asarray(joint.stamp_ns, dtype=np.int64)
    if stamps.size < 2:
        raise FleetError(f"{path}: topic {topic} has {stamps.size} sample(s); at least 2 are needed")
    scale = nominal.r / nominal.i_r if kind.value == "motor" else 1.0
    x = np.asarray(joint.position, dtype=float) * scale
    holes, missing = _holes(stamps)
    low, high, reversals, moving_s = motion_summary(stamps, x)
    return CatalogEntry(
        **base,
        axis=axis,
        topic=topic,
        joint=s.joint,
        joint_kind=kind.value,
        content_hash=digest,
        start_ns=int(stamps[0]),
        end_ns=int(stamps[-1]),
        samples=int(stamps.size),
        holes=holes,
        missing=missing,
        speed_low_m_s=low,
        speed_high_m_s=high,
        reversals=reversals,
        moving_s=moving_s,
        status=OK,
        reason="",
    )


def _holes(stamps: np.ndarray) -> tuple[int, int]:
    """(holes, samples missing in them): steps of more than 1.5 median steps."""
    step = np.diff(stamps)
    period = float(np.median(step))
    if period <= 0:
        return 0, 0
    gaps = step[step > 1.5 * period]
    return int(gaps.size), int(np.sum(np.round(gaps / period) - 1))


def motion_summary(stamps_ns: np.ndarray, position_m: np.ndarray) -> tuple[float, float, int, float]:
    """(speed low, speed high [m/s], reversals, time moving [s]) of a position trace (see the module
    docstring): speeds over :data:`SPEED_SPAN_S`; a reversal is a change of the direction between two
    stretches that move faster than :data:`MOVING_M_S`."""
    t = (stamps_ns - stamps_ns[0]) * 1e-9
    period = float(np.median(np.diff(t)))
    lag = max(1, round(SPEED_SPAN_S / period)) if period > 0 else 1
    if t.size <= lag:
        return 0.0, 0.0, 0, 0.0
    dt = t[lag:] - t[:-lag]
    v = np.divide(position_m[lag:] - position_m[:-lag], dt, out=np.zeros_like(dt), where=dt > 0)
    moving = np.abs(v) > MOVING_M_S
    if not moving.any():
        return 0.0, float(np.max(np.abs(v))), 0, 0.0
    speeds = np.abs(v[moving])
    direction = np.sign(v[moving])
    reversals = int(np.count_nonzero(np.diff(direction) != 0))
    moving_s = float(np.sum(np.diff(t[lag:])[moving[:-1]]))
    return float(np.percentile(speeds, 5)), float(np.percentile(speeds, 99)), reversals, moving_s
