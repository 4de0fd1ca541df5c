"""The per-message Zenoh attachment: sequence number, source time stamp and publisher id.

The layout is rmw_zenoh's 33 bytes, so ROS 2 tooling can read it: ``int64`` sequence number,
``int64`` source time stamp [ns since the Unix epoch], a ``uint8`` length (16) and the 16-byte
publisher id, all little endian. Sequence numbers start at 1 and increase by 1 per message of one
publisher, so a receiver counts what it missed per (key, publisher id).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

from ..errors import WireError

_LAYOUT = struct.Struct("<qqB16s")
ATTACHMENT_SIZE = _LAYOUT.size  # 33
GID_SIZE = 16


@dataclass(frozen=True)
class Attachment:
    sequence: int
    source_stamp_ns: int
    publisher_gid: bytes

    def __post_init__(self) -> None:
        if len(self.publisher_gid) != GID_SIZE:
            raise WireError(f"publisher id has {len(self.publisher_gid)} bytes, expected {GID_SIZE}")

    def encode(self) -> bytes:
        return _LAYOUT.pack(self.sequence, self.source_stamp_ns, GID_SIZE, self.publisher_gid)

    @classmethod
    def decode(cls, data: bytes | bytearray | memoryview) -> Attachment:
        if len(data) != ATTACHMENT_SIZE:
            raise WireError(f"attachment has {len(data)} bytes, expected {ATTACHMENT_SIZE}")
        seq, stamp, n, gid = _LAYOUT.unpack(data)
        if n != GID_SIZE:
            raise WireError(f"attachment publisher-id length {n}, expected {GID_SIZE}")
        return cls(seq, stamp, gid)


def pack_attachment(sequence: int, source_stamp_ns: int, publisher_gid: bytes) -> bytes:
    """Hot-path form of ``Attachment(...).encode()`` (no validation)."""
    return _LAYOUT.pack(sequence, source_stamp_ns, GID_SIZE, publisher_gid)


def unpack_attachment(data: bytes) -> tuple[int, int, bytes] | None:
    """Hot-path decode: ``(sequence, source_stamp_ns, publisher_gid)``, or None if not ours."""
    if len(data) != ATTACHMENT_SIZE:
        return None
    seq, stamp, _n, gid = _LAYOUT.unpack(data)
    return seq, stamp, gid
