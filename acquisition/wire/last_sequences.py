"""The last sequence number each publisher of a session has put: what a receiver needs to count the tail.

A receiver counts what it missed from the gaps in the sequence numbers (:mod:`.sequence`), but a gap
shows only between two messages that arrived: the messages after the last one that arrived — dropped
by Zenoh on congestion (``put`` does not say it dropped one), or still in a transmit queue when the
session closed — leave no gap. Only the publisher knows its last number, so it says it: before its
session closes it asks every joined subscriber for a receipt
(:func:`~axisflow.acquisition.bus.readiness.confirm_delivery`) with a :class:`LastSequences` as the
query's payload, and the subscriber counts the numbers after the last one it received as missed. A
publisher answering a hello says its number too (:class:`.hello.Hello`), so a recorder that stops
while the publishers run knows what they had sent by then.

The record is JSON; it never lands in MCAP (it travels on the ``@axisflow/receipt`` keys).
"""

from __future__ import annotations

import json
from dataclasses import dataclass

from ..errors import WireError

LAST_SEQUENCES_ENCODING = "application/json"


@dataclass(frozen=True)
class LastSequence:
    """One publisher's last number."""

    key: str
    """the key it publishes on"""
    publisher: str
    """its publisher id (hex), as its messages' attachments carry it"""
    sequence: int
    """the number of the last message it put (0: none yet)"""

    @property
    def publisher_id(self) -> bytes:
        return bytes.fromhex(self.publisher)


@dataclass(frozen=True)
class LastSequences:
    """The last numbers of a session's publishers (see the module docstring)."""

    publishers: tuple[LastSequence, ...]

    def encode(self) -> bytes:
        rows = [[p.key, p.publisher, p.sequence] for p in self.publishers]
        return json.dumps({"last_sequences": rows}, separators=(",", ":")).encode()

    @classmethod
    def decode(cls, data: bytes) -> LastSequences:
        try:
            rows = json.loads(data)["last_sequences"]
            entries = tuple(LastSequence(key, publisher, sequence) for key, publisher, sequence in rows)
        except (ValueError, TypeError, KeyError) as exc:  # not JSON, not our object, rows of another shape
            raise WireError(f"undecodable last sequence numbers ({len(data)} bytes): {exc!r}") from None
        for entry in entries:
            if not isinstance(entry.key, str) or not entry.key:
                raise WireError(f"last sequence numbers: key {entry.key!r} is not a key")
            try:
                if len(entry.publisher_id) != 16:
                    raise ValueError
            except (ValueError, TypeError):
                raise WireError(
                    f"last sequence numbers: publisher {entry.publisher!r} is not a 16-byte id in hex"
                ) from None
            number = entry.sequence
            if not isinstance(number, int) or isinstance(number, bool) or number < 0:
                raise WireError(f"last sequence numbers: sequence {number!r} is not a count >= 0")
        return cls(entries)
