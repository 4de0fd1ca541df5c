"""A minimal OMG CDR (XCDR1, little endian) writer and reader for the ROS 2 messages we use.

A ROS 2 payload starts with a 4-byte encapsulation header ``00 01 00 00`` (CDR_LE). Primitives are
aligned to their own size relative to the first byte *after* that header; strings are a ``uint32``
length (including the terminating NUL) followed by the bytes and the NUL; sequences are a ``uint32``
count followed by the elements.

Why a codec of our own: mcap-ros2-support and rosbags decode at about the speed of this one (~40 k
messages/s per core), so they buy no speed; this module is small, has no dependency, writes exactly
the bytes the recorder stores and the bridge publishes, and is tested byte for byte against
mcap-ros2-support's independent codec (tests/acquisition/test_messages.py), which is therefore only a
test dependency. Fixed-layout payloads read in bulk go through :mod:`..logs.reader.columns`' vectorised
decoder instead.
"""

from __future__ import annotations

import struct

import numpy as np

from ..errors import WireError

CDR_LE_HEADER = b"\x00\x01\x00\x00"

_UINT8 = struct.Struct("<B")
_UINT16 = struct.Struct("<H")
_INT32 = struct.Struct("<i")
_INT64 = struct.Struct("<q")
_UINT32 = struct.Struct("<I")
_UINT64 = struct.Struct("<Q")
_FLOAT64 = struct.Struct("<d")


class CdrWriter:
    """Appends CDR-encoded primitives to a buffer that starts with the CDR_LE header."""

    def __init__(self) -> None:
        self._buf = bytearray(CDR_LE_HEADER)

    def _align(self, size: int) -> None:
        pad = (-(len(self._buf) - 4)) % size
        if pad:
            self._buf.extend(b"\x00" * pad)

    def uint8(self, value: int) -> None:
        self._buf += _UINT8.pack(value)

    def uint16(self, value: int) -> None:
        self._align(2)
        self._buf += _UINT16.pack(value)

    def int32(self, value: int) -> None:
        self._align(4)
        self._buf += _INT32.pack(value)

    def int64(self, value: int) -> None:
        self._align(8)
        self._buf += _INT64.pack(value)

    def uint32(self, value: int) -> None:
        self._align(4)
        self._buf += _UINT32.pack(value)

    def uint64(self, value: int) -> None:
        self._align(8)
        self._buf += _UINT64.pack(value)

    def float64(self, value: float) -> None:
        self._align(8)
        self._buf += _FLOAT64.pack(value)

    def string(self, value: str) -> None:
        data = value.encode("utf-8")
        self.uint32(len(data) + 1)
        self._buf += data
        self._buf.append(0)

    def string_sequence(self, values: tuple[str, ...]) -> None:
        self.uint32(len(values))
        for v in values:
            self.string(v)

    def float64_sequence(self, values: tuple[float, ...]) -> None:
        self.uint32(len(values))
        if values:
            self._align(8)
            self._buf += struct.pack(f"<{len(values)}d", *values)

    def float64_array(self, values: np.ndarray) -> None:
        """A ``float64[]`` from a numpy array, in one copy."""
        a = np.ascontiguousarray(values, dtype="<f8")
        self.uint32(a.size)
        if a.size:
            self._align(8)
            self._buf += a.tobytes()

    def to_bytes(self) -> bytes:
        return bytes(self._buf)


class CdrReader:
    """Reads CDR primitives from a payload that starts with the CDR_LE header."""

    def __init__(self, data: bytes | bytearray | memoryview, type_name: str) -> None:
        self._data = bytes(data)
        self._type = type_name
        if len(self._data) < 4 or self._data[:2] != CDR_LE_HEADER[:2]:
            head = self._data[:4].hex()
            raise WireError(f"{type_name}: payload does not start with the CDR_LE header 0001, got {head!r}")
        self._pos = 4

    @property
    def position(self) -> int:
        """The byte offset of the next field (in the payload, header included)."""
        return self._pos

    @property
    def at_end(self) -> bool:
        """Whether every byte has been read (a record that grew fields at its end reads the older,
        shorter form by checking this before its new fields)."""
        return self._pos >= len(self._data)

    def _need(self, size: int) -> None:
        if self._pos + size > len(self._data):
            raise WireError(
                f"{self._type}: payload truncated at byte {self._pos}: needs {size} more bytes, "
                f"has {len(self._data) - self._pos}"
            )

    def _align(self, size: int) -> None:
        self._pos += (-(self._pos - 4)) % size

    def _unpack(self, st: struct.Struct) -> int | float:
        self._align(st.size)
        self._need(st.size)
        (value,) = st.unpack_from(self._data, self._pos)
        self._pos += st.size
        return value

    def uint8(self) -> int:
        return int(self._unpack(_UINT8))

    def uint16(self) -> int:
        return int(self._unpack(_UINT16))

    def int32(self) -> int:
        return int(self._unpack(_INT32))

    def int64(self) -> int:
        return int(self._unpack(_INT64))

    def uint32(self) -> int:
        return int(self._unpack(_UINT32))

    def uint64(self) -> int:
        return int(self._unpack(_UINT64))

    def float64(self) -> float:
        return float(self._unpack(_FLOAT64))

    def string(self) -> str:
        n = self.uint32()
        self._need(n)
        if n == 0:
            return ""
        raw = self._data[self._pos : self._pos + n - 1]
        self._pos += n
        try:
            return raw.decode("utf-8")
        except UnicodeDecodeError:
            raise WireError(f"{self._type}: string at byte {self._pos - n} is not UTF-8") from None

    def _count(self, element_size: int) -> int:
        n = self.uint32()
        if n * element_size > len(self._data) - self._pos:
            raise WireError(
                f"{self._type}: sequence length {n} exceeds the {len(self._data) - self._pos} bytes left"
            )
        return n

    def string_sequence(self) -> tuple[str, ...]:
        n = self._count(4)
        return tuple(self.string() for _ in range(n))

    def float64_array(self) -> np.ndarray:
        """A ``float64[]`` as a numpy array (a copy, native byte order)."""
        n = self._count(8)
        if n == 0:
            return np.empty(0)
        self._align(8)
        self._need(8 * n)
        values = np.frombuffer(self._data, dtype="<f8", count=n, offset=self._pos).astype(float)
        self._pos += 8 * n
        return values

    def float64_sequence(self) -> tuple[float, ...]:
        n = self._count(8)
        if n == 0:
            return ()
        self._align(8)
        self._need(8 * n)
        values = struct.unpack_from(f"<{n}d", self._data, self._pos)
        self._pos += 8 * n
        return tuple(values)


# ---- builtin_interfaces/Time and ros2msg schema text, shared by every message type ----------------

NS_PER_S = 1_000_000_000
TIME_DEFINITION = "int32 sec\nuint32 nanosec\n"
HEADER_DEFINITION = "builtin_interfaces/Time stamp\nstring frame_id\n"
_SEPARATOR = "=" * 80


def write_time(w: CdrWriter, t_ns: int) -> None:
    """``builtin_interfaces/Time`` from integer nanoseconds since the Unix epoch."""
    sec, nanosec = divmod(t_ns, NS_PER_S)
    if not -(2**31) <= sec < 2**31:
        raise WireError(f"time stamp {t_ns} ns is outside the int32 seconds range of builtin_interfaces/Time")
    w.int32(sec)
    w.uint32(nanosec)


def read_time(r: CdrReader) -> int:
    """Integer nanoseconds from a ``builtin_interfaces/Time``."""
    sec = r.int32()
    nanosec = r.uint32()
    if nanosec >= NS_PER_S:
        raise WireError(f"builtin_interfaces/Time nanosec = {nanosec} must be < {NS_PER_S}")
    return sec * NS_PER_S + nanosec


def schema_with_dependencies(main: str, *deps: tuple[str, str]) -> str:
    """A ros2msg schema as rosbag2 stores it: the definition, then each dependency after a separator."""
    parts = [main.rstrip("\n")]
    for name, text in deps:
        parts.append(f"{_SEPARATOR}\nMSG: {name}\n{text.rstrip(chr(10))}")
    return "\n".join(parts) + "\n"


HEADER_DEPENDENCIES: tuple[tuple[str, str], ...] = (
    ("std_msgs/Header", HEADER_DEFINITION),
    ("builtin_interfaces/Time", TIME_DEFINITION),
)
"""the dependencies of a message with a ``std_msgs/Header``"""
