"""The byte layout of a ``sensor_msgs/msg/JointState`` CDR payload, for decoding and encoding in bulk.

A JointState payload (ROS 2 CDR, little endian, see :mod:`.cdr` for the rules) is, byte for byte::

    0   encapsulation header 00 01 xx xx (CDR_LE)
    4   int32  header.stamp.sec
    8   uint32 header.stamp.nanosec
    12  string header.frame_id          uint32 length n (incl. NUL), n bytes
        string[] name                   uint32 count J, then J strings, each aligned to 4
        float64[] position              uint32 count, then (aligned to 8) count float64
        float64[] velocity              the same
        float64[] effort                the same

Alignment is relative to byte 4 (the first byte after the encapsulation header). So once the
frame_id and the joint names are fixed, every field lies at a fixed offset: the stamp at bytes 4–12
always, the three arrays at offsets that depend only on the lengths of the strings before them. A
:class:`JointStateLayout` records those offsets for one shape of payload (one frame_id, one list of
joint names, arrays of J or 0 values) and decodes or encodes many payloads of that shape at once with
numpy.

A layout is found once per shape by walking one payload with :class:`.cdr.CdrReader`; the bulk
decode and encode are tested against :meth:`.messages.JointState.decode` and ``encode`` bit for bit
(tests/acquisition/logs/test_log_reader.py), and anything this module cannot lay out (big-endian CDR,
malformed or inconsistent payloads) is left to ``JointState.decode``, which names the problem.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..errors import WireError
from ..wire.cdr import NS_PER_S, CdrReader
from ..wire.messages import JOINT_STATE_TYPE, JointState

STAMP_SEC_OFFSET = 4
"""byte offset of ``header.stamp.sec`` (int32) in every JointState payload"""
STAMP_NANOSEC_OFFSET = 8
"""byte offset of ``header.stamp.nanosec`` (uint32)"""
ARRAY_FIELDS = ("position", "velocity", "effort")


@dataclass(frozen=True)
class JointStateLayout:
    """Where the fields of one shape of JointState payload lie.

    ``array_offsets`` holds the byte offset of the first float64 of position, velocity and effort, or
    None for an array that is empty in this shape (decoded as NaN columns). Every array is either
    empty or has one value per joint.
    """

    size: int
    """payload length [bytes]"""
    frame_id: str
    joint_names: tuple[str, ...]
    array_offsets: tuple[int | None, int | None, int | None]

    @classmethod
    def of(cls, payload: bytes | bytearray | memoryview) -> JointStateLayout | None:
        """The layout of ``payload``, or None if it is not a little-endian JointState this module lays
        out (big-endian CDR, a truncated or malformed payload, an array whose length is neither the
        number of joints nor 0). Decode such payloads with :meth:`JointState.decode`."""
        data = bytes(payload)
        try:
            reader = CdrReader(data, JOINT_STATE_TYPE)
            reader.int32(), reader.uint32()  # the stamp, at STAMP_SEC_OFFSET and STAMP_NANOSEC_OFFSET
            frame_id = reader.string()
            names = reader.string_sequence()
            offsets: list[int | None] = []
            for _field in ARRAY_FIELDS:
                values = reader.float64_array()
                if values.size not in (0, len(names)):
                    return None
                offsets.append(reader.position - 8 * values.size if values.size else None)
        except WireError:
            return None
        return cls(len(data), frame_id, names, (offsets[0], offsets[1], offsets[2]))

    @property
    def joints(self) -> int:
        return len(self.joint_names)

    @cached_property
    def dtype(self) -> np.dtype:
        """A structured dtype of one payload: ``sec`` (<i4), ``nanosec`` (<u4) and the non-empty arrays
        (<f8, shape (joints,)) at their offsets; itemsize = the payload length."""
        names = ["sec", "nanosec"]
        formats: list[object] = ["<i4", "<u4"]
        offsets = [STAMP_SEC_OFFSET, STAMP_NANOSEC_OFFSET]
        for field, offset in zip(ARRAY_FIELDS, self.array_offsets, strict=True):
            if offset is not None:
                names.append(field)
                formats.append(("<f8", (self.joints,)))
                offsets.append(offset)
        return np.dtype({"names": names, "formats": formats, "offsets": offsets, "itemsize": self.size})

    @cached_property
    def variable_ranges(self) -> tuple[tuple[int, int], ...]:
        """Byte ranges [start, end) that differ between payloads of this shape: the stamp and the
        values of the non-empty arrays, in increasing order."""
        ranges = [(STAMP_SEC_OFFSET, STAMP_NANOSEC_OFFSET + 4)]
        for offset in self.array_offsets:
            if offset is not None:
                ranges.append((offset, offset + 8 * self.joints))
        return tuple(ranges)

    @cached_property
    def constant_ranges(self) -> tuple[tuple[int, int], ...]:
        """Byte ranges [start, end) that payloads of this shape share: the CDR header, frame_id,
        joint names, array counts, padding (and any trailing bytes)."""
        out, start = [], 0
        for a, b in self.variable_ranges:
            if a > start:
                out.append((start, a))
            start = b
        if start < self.size:
            out.append((start, self.size))
        return tuple(out)

    def matches(self, rows: np.ndarray, reference: np.ndarray | None = None) -> bool:
        """True if every row of ``rows`` (uint8, shape (n, size)) has this layout's constant bytes as
        ``reference`` (a payload this layout was found in, uint8 (size,); default: the first row)
        has them."""
        if rows.ndim != 2 or rows.shape[1] != self.size:
            return False
        first = rows[0] if reference is None else reference
        return all(bool((rows[:, a:b] == first[a:b]).all()) for a, b in self.constant_ranges)

    def decode(self, rows: np.ndarray) -> DecodedJointStates:
        """Stamps and arrays of payloads of this shape (uint8 rows, shape (n, size), e.g. a strided
        view of the messages of a chunk). The arrays are views into ``rows``; an array that is empty
        in this shape decodes as NaN. Raises :class:`WireError` if a nanosec field is ≥ 10⁹ (the same
        check as :func:`.cdr.read_time`)."""
        fields = rows.view(self.dtype)[:, 0]
        nanosec = fields["nanosec"]
        if (nanosec >= NS_PER_S).any():
            bad = int(nanosec[np.argmax(nanosec >= NS_PER_S)])
            raise WireError(f"builtin_interfaces/Time nanosec = {bad} must be < {NS_PER_S}")
        stamp_ns = fields["sec"].astype(np.int64) * NS_PER_S + nanosec
        n = len(rows)
        arrays = []
        for field, offset in zip(ARRAY_FIELDS, self.array_offsets, strict=True):
            if offset is None:
                arrays.append(np.full((n, self.joints), np.nan))
            else:
                arrays.append(fields[field])
        return DecodedJointStates(stamp_ns, arrays[0], arrays[1], arrays[2])

    def encode(
        self,
        template: bytes,
        stamp_ns: np.ndarray,
        position: np.ndarray,
        velocity: np.ndarray,
        effort: np.ndarray,
    ) -> np.ndarray:
        """Payloads of this shape as uint8 rows (n, size): ``template`` (one payload of the shape,
        e.g. ``JointState(...).encode()``) with the stamps (int64 ns) and arrays (float64, (n, joints))
        written in. Raises :class:`WireError` for a stamp outside the int32 seconds range."""
        stamp_ns = np.asarray(stamp_ns, dtype=np.int64)
        sec, nanosec = np.divmod(stamp_ns, NS_PER_S)
        if len(sec) and (sec.min() < -(2**31) or sec.max() >= 2**31):
            raise WireError(
                f"time stamps {stamp_ns.min()}..{stamp_ns.max()} ns are outside the int32 seconds "
                "range of builtin_interfaces/Time"
            )
        rows = np.tile(np.frombuffer(template, dtype=np.uint8), (len(stamp_ns), 1))
        fields = rows.view(self.dtype)[:, 0]
        fields["sec"] = sec
        fields["nanosec"] = nanosec
        for field, offset, values in zip(
            ARRAY_FIELDS, self.array_offsets, (position, velocity, effort), strict=True
        ):
            if offset is not None:
                fields[field] = values
        return rows

    @classmethod
    def for_message(cls, message: JointState) -> tuple[JointStateLayout, bytes]:
        """The layout of ``message``'s shape and its encoding (to use as a template for :meth:`encode`)."""
        template = message.encode()
        layout = cls.of(template)
        if layout is None:
            raise WireError(
                f"JointState with {len(message.name)} joints and arrays of "
                f"{len(message.position)}/{len(message.velocity)}/{len(message.effort)} values has no "
                "fixed layout: each array needs one value per joint or none"
            )
        return layout, template


@dataclass(frozen=True)
class DecodedJointStates:
    """Columns decoded from n payloads: ``stamp_ns`` (int64, (n,)) and float64 arrays (n, joints)."""

    stamp_ns: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    effort: np.ndarray
