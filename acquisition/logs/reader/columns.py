"""The top layer of reading a log: one JointState topic's messages as numpy columns, fast.

:func:`read_joint_states` returns a topic's ``sensor_msgs/msg/JointState`` messages as a
:class:`JointStateColumns` (stamps, MCAP times and sequence numbers as int64, position/velocity/effort
as float64 arrays of shape (n, joints)). It reads complete files, files without summary, files cut off
by a crash (up to the last complete chunk), and files with chunks that cannot be read: those are
skipped, and where they lie among the rows is kept (:attr:`JointStateColumns.holes`) so that a user of
the columns never takes the rows on both sides of one for neighbours.

Rows are in **file order** of the topic's messages — the order in which the recorder wrote them, i.e.
arrival order for ``axisflow record`` — and are never sorted: check ``stamp_ns`` if you need it
monotonic.

Decoding a batch (a chunk's messages of the topic, from :class:`~.messages.MessageScan`): when the
records all have the same length and their payloads the same bytes outside the stamp and the float
arrays (frame_id, joint names, sequence counts, padding: see :mod:`..joint_state_layout`) as the first
one, the stamps and arrays are read at fixed offsets for the whole chunk at once (the *vectorised*
path; the records' heads are a strided view when they are evenly spaced — two topics interleaved at
one rate are). Anything else — different lengths, big-endian CDR, messages of other layouts — goes
through :meth:`JointState.decode` one message at a time (the *per-message* path); both give identical
columns (tested bit for bit).

Memory: the result (3.6 M rows × 2 joints = ~290 MB for an hour) is preallocated from the summary's
message counts (grown when there is none) and filled chunk by chunk; one decompressed chunk is held at
a time. docs/acquisition.md gives the speed, with the command that measures it.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from mcap.records import Channel

from ...errors import RecordingError, WireError
from ...wire.messages import JOINT_STATE_TYPE, JointState
from ..joint_state_layout import DecodedJointStates, JointStateLayout
from .framing import MESSAGE_FIELDS_SIZE, MESSAGE_HEAD_SIZE, McapFile, rows
from .messages import (
    Catalog,
    MessageBatch,
    MessageScan,
    Selection,
    SkipHandler,
    SkippedChunk,
    report_skipped,
    skipped_note,
)

# ---- results ---------------------------------------------------------------------------------------


@dataclass(frozen=True)
class JointColumns:
    """One joint of a :class:`JointStateColumns` (views into its arrays, shape (n,)). For the axis
    contract: ``carriage`` in m, m/s, N; ``motor`` in rad, rad/s, N·m."""

    name: str
    stamp_ns: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    effort: np.ndarray


@dataclass(frozen=True)
class Hole:
    """Rows missing from the columns because a chunk could not be read: they lay just before row
    ``row`` (file order; ``row`` = the number of rows for a hole at the end)."""

    row: int
    skipped: SkippedChunk

    @property
    def messages(self) -> int | None:
        """messages of the topic lost (None: not known)"""
        return self.skipped.messages


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
    holes: tuple[Hole, ...] = ()
    """where chunks that could not be read took rows away, in row order"""

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


# ---- decoding --------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class _KnownLayout:
    """The layout of the last batch decoded vectorised and a payload it was found in."""

    layout: JointStateLayout
    payload: np.ndarray


def _decode_vectorised(
    data: np.ndarray, offsets: np.ndarray, heads: np.ndarray, known: _KnownLayout | None
) -> tuple[_KnownLayout, DecodedJointStates] | None:
    """The payloads decoded at fixed offsets, or None if they do not all share one layout: the
    ``known`` one (checked against its payload's constant bytes, which spares finding it again in
    every chunk), else the first payload's."""
    lengths = heads["length"]
    length = int(lengths[0])
    if bool((lengths != length).any()):
        return None
    payloads = rows(data, offsets + MESSAGE_HEAD_SIZE, length - MESSAGE_FIELDS_SIZE)
    if known is None or not known.layout.matches(payloads, known.payload):
        layout = JointStateLayout.of(payloads[0].tobytes())
        if layout is None or not layout.matches(payloads):
            return None
        known = _KnownLayout(layout, payloads[0].copy())
    try:
        return known, known.layout.decode(payloads)
    except WireError:  # a bad stamp: the per-message path names the message
        return None


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


class _ColumnsRead:
    """Decodes the message batches of one topic into a :class:`_ColumnBuilder`, keeping the rows whose
    stamp is in [start_ns, end_ns), and notes the holes skipped chunks leave."""

    def __init__(
        self, path: Path, topic: str, start_ns: int | None, end_ns: int | None, per_message: bool
    ) -> None:
        self.path, self.topic = path, topic
        self.start_ns, self.end_ns = start_ns, end_ns
        self.per_message = per_message
        self.joint_names: tuple[str, ...] | None = None
        self.frame_ids: dict[str, None] = {}
        self.decoded = {"vectorised": 0, "per_message": 0}
        self.stamp_range: tuple[int, int] | None = None
        self.builder = _ColumnBuilder(0)
        self.holes: list[Hole] = []
        self._known: _KnownLayout | None = None

    def reserve(self, rows: int) -> None:
        """Preallocate the result for ``rows`` rows (e.g. the summary's message count)."""
        if self.builder.n == 0:
            self.builder = _ColumnBuilder(rows)

    def check_channel(self, channel: Channel, catalog: Catalog) -> None:
        """The topic's ``channel`` must be JointState in CDR."""
        schema = catalog.schema_of(channel)
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

    def skip(self, skipped: SkippedChunk) -> None:
        self.holes.append(Hole(self.builder.n, skipped))

    def decode(self, batch: MessageBatch) -> None:
        """Decode a batch of the topic's message records and keep the rows in the time range."""
        data = np.frombuffer(batch.buffer, np.uint8)
        heads = batch.heads
        fast = None if self.per_message else _decode_vectorised(data, batch.offsets, heads, self._known)
        if fast is not None:
            self._known, decoded = fast
            layout = self._known.layout
            self._check_joints(layout.joint_names, heads, 0)
            frame_ids = [layout.frame_id]
            self.decoded["vectorised"] += len(heads)
        else:
            decoded, frame_ids = self._decode_each(batch)
            self.decoded["per_message"] += len(heads)
        keep = self._in_range(decoded.stamp_ns)
        if keep is None or keep.any():
            if keep is not None and len(frame_ids) > 1:
                frame_ids = [f for f, k in zip(frame_ids, keep.tolist(), strict=True) if k]
            self.frame_ids.update(dict.fromkeys(frame_ids))
            self.builder.append(heads, decoded, keep)

    def _decode_each(self, batch: MessageBatch) -> tuple[DecodedJointStates, list[str]]:
        """The per-message path: :meth:`JointState.decode` on each payload."""
        view = memoryview(batch.buffer)
        heads = batch.heads
        starts, ends = batch.payload_bounds()
        n = len(heads)
        stamp_ns = np.empty(n, np.int64)
        arrays: list[np.ndarray] = []
        frame_ids: list[str] = []
        for i, (start, end) in enumerate(zip(starts.tolist(), ends.tolist(), strict=True)):
            try:
                message = JointState.decode(view[start:end])
            except WireError as exc:
                raise WireError(f"{self._message_name(heads, i)} in {batch.where}: {exc}") from None
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
            holes=tuple(self.holes),
            **arrays,
        )

    def _empty_reason(self) -> str:
        skipped = skipped_note(h.skipped for h in self.holes)
        if self.stamp_range is None:
            return f"{self.path}: topic {self.topic} holds no message{skipped}"
        low, high = self.stamp_range
        return (
            f"{self.path}: no message of topic {self.topic} has a header stamp in "
            f"[{self.start_ns}, {self.end_ns}) ns; its stamps span [{low}, {high}] ns{skipped}"
        )

    def topic_missing(self, catalog: Catalog, truncated: bool) -> RecordingError:
        present = [t.topic for t in catalog.topics(None) if t.is_joint_state]
        cut = (
            " (it has no footer: cut off by a crash, read up to its last complete chunk)" if truncated else ""
        )
        listed = ", ".join(present) or "none"
        skipped = skipped_note(h.skipped for h in self.holes)
        return RecordingError(
            f"{self.path} has no topic {self.topic}; its JointState topics: {listed}{cut}{skipped}"
        )


def read_joint_states(
    path: str | Path,
    topic: str,
    *,
    start_ns: int | None = None,
    end_ns: int | None = None,
    per_message: bool = False,
    on_skip: SkipHandler | None = None,
) -> JointStateColumns:
    """The ``sensor_msgs/msg/JointState`` messages of ``topic`` as columns, rows in file order.

    ``start_ns``/``end_ns`` keep the rows whose header stamp is in [start_ns, end_ns) (either may be
    None: unbounded). ``per_message=True`` decodes every message with :meth:`JointState.decode` (the
    reference the vectorised path is tested against; ~18× slower). A file cut off by a crash is read
    up to its last complete chunk (``truncated`` is then True). A chunk that cannot be read is
    skipped: it leaves a :class:`Hole` in the columns and is handed to ``on_skip`` (default: a
    :class:`~axisflow.acquisition.errors.DamagedLogWarning`) once the read has succeeded.

    Raises :class:`RecordingError` for a missing or non-MCAP file, a topic that is not in the file
    (naming the JointState topics it has), a topic that is not ROS 2 CDR JointState (naming its schema),
    joints that change between messages, and an empty result (naming the chunks skipped, if any);
    :class:`WireError` for a payload that does not decode (naming the message).
    """
    with McapFile.open(path) as file:
        catalog = Catalog(file.summary)
        reader = _ColumnsRead(file.path, topic, start_ns, end_ns, per_message)
        selection = Selection(catalog, topic, lambda channel: reader.check_channel(channel, catalog))
        if file.summary is not None and file.summary.channels:
            wanted = selection.wanted_ids()
            if not wanted:
                raise reader.topic_missing(catalog, truncated=False)
            if file.summary.statistics is not None:
                counts = file.summary.statistics.channel_message_counts
                reader.reserve(sum(counts.get(cid, 0) for cid in wanted))
        for event in MessageScan(file, catalog, selection).events():
            if isinstance(event, MessageBatch):
                reader.decode(event)
            else:
                reader.skip(event)
        if not selection.wanted_ids():
            raise reader.topic_missing(catalog, file.truncated)
        columns = reader.result(file.truncated)
    report_skipped((h.skipped for h in columns.holes), on_skip)
    return columns
