"""Counting what was lost on the way from the attachments' sequence numbers.

Every axisflow publisher numbers its messages 1, 2, 3, … and names itself with a 16-byte publisher id
(:mod:`.attachment`). A receiver feeds each message's (publisher id, sequence number) to a
:class:`SequenceTracker`, which keeps, per publisher id, the first and last number and the messages
seen, and counts:

* **missed** — numbers skipped: a message numbered ``last + k`` (k > 1) means k − 1 were lost;
* **duplicates** — a number not above the last one (a message delivered twice, or out of order),
  except 1, which is a restart;
* **restarts** — a publisher id whose numbering starts again at 1 (the same id reused by a sender
  that restarted); its count goes on, its span starts afresh.

A sender that restarts with a new id (what :class:`~axisflow.acquisition.bus.publisher.SequencedPublisher`
does) is a second publisher: :attr:`SequenceTracker.publishers` lists them in the order they first
appeared. One tracker per stream (the recorder: per topic; the live view: per key; the bridge: per
trajectory key). Zenoh-free: it is part of the wire contract.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(slots=True)
class PublisherSequence:
    """What one publisher id's numbers said so far."""

    first: int
    """the first number of its current span (1 for a publisher seen from its start)"""
    last: int
    """the highest number of its current span"""
    messages: int = 1
    missed: int = 0
    duplicates: int = 0
    restarts: int = 0


class SequenceTracker:
    """Gaps, duplicates and restarts of one stream, per publisher id (see the module docstring)."""

    __slots__ = ("duplicates", "missed", "publishers", "restarts")

    def __init__(self) -> None:
        self.publishers: dict[bytes, PublisherSequence] = {}
        """per publisher id, in the order they first appeared"""
        self.missed = 0
        self.duplicates = 0
        self.restarts = 0

    def add(self, publisher: bytes, sequence: int) -> int:
        """Count one message; returns how many were missed just before it (0 when in order)."""
        seen = self.publishers.get(publisher)
        if seen is None:
            self.publishers[publisher] = PublisherSequence(sequence, sequence)
            return 0
        seen.messages += 1
        if sequence == seen.last + 1:
            seen.last = sequence
            return 0
        if sequence > seen.last:
            skipped = sequence - seen.last - 1
            seen.last = sequence
            seen.missed += skipped
            self.missed += skipped
            return skipped
        if sequence == 1:
            seen.first = seen.last = 1
            seen.restarts += 1
            self.restarts += 1
            return 0
        seen.duplicates += 1
        self.duplicates += 1
        return 0

    @property
    def messages(self) -> int:
        return sum(p.messages for p in self.publishers.values())

    def __len__(self) -> int:
        """How many publisher ids were seen."""
        return len(self.publishers)
