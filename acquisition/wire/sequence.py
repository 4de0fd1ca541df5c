"""Counting what was lost on the way from the attachments' sequence numbers.

Every axisflow publisher numbers its messages 1, 2, 3, … and names itself with a 16-byte publisher id
(:mod:`.attachment`). A receiver feeds each message's (publisher id, sequence number) to a
:class:`SequenceTracker`, which keeps, per publisher id, the first and last number and the messages
seen, and counts:

* **missed** — numbers skipped: a message numbered ``last + k`` (k > 1) means k − 1 were lost; and,
  where the publisher said so, the numbers it sent that no message after them reveals
  (:mod:`.last_sequences`): those *after* the last one received (the **tail**, :meth:`SequenceTracker.said`,
  from its last number) and those *before* the first one received (the **head**,
  :meth:`SequenceTracker.expect`, from its number when the receiver joined);
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
    """the highest number of its current span (first − 1 while none has arrived)"""
    messages: int = 1
    gaps: int = 0
    """numbers skipped between the messages received"""
    duplicates: int = 0
    restarts: int = 0
    head: int = 0
    """numbers owed before the first one received (:meth:`SequenceTracker.expect`)"""
    said: int = 0
    """the last number the publisher said it had sent (:meth:`SequenceTracker.said`; 0: it did not say)"""

    @property
    def tail(self) -> int:
        """numbers it said it had sent after the last one received"""
        return max(self.said - self.last, 0)

    @property
    def missed(self) -> int:
        """every number it sent to this receiver that did not arrive: gaps, head and tail"""
        return self.gaps + self.head + self.tail


class SequenceTracker:
    """Gaps, duplicates and restarts of one stream, per publisher id (see the module docstring)."""

    __slots__ = ("duplicates", "gaps", "publishers", "restarts")

    def __init__(self) -> None:
        self.publishers: dict[bytes, PublisherSequence] = {}
        """per publisher id, in the order they first appeared"""
        self.gaps = 0
        """numbers skipped between the messages received, all publishers"""
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
            seen.gaps += skipped
            self.gaps += skipped
            return skipped
        if sequence == 1:
            seen.first = seen.last = 1
            seen.restarts += 1
            self.restarts += 1
            return 0
        seen.duplicates += 1
        self.duplicates += 1
        return 0

    def expect(self, publisher: bytes, first: int) -> None:
        """The receiver is owed the publisher's numbers from ``first`` on (its number was ``first`` − 1
        when the receiver joined): numbers before the first one received are missed (the head). Call it
        once the stream has ended; a publisher that restarted since is not held to it."""
        seen = self.publishers.get(publisher)
        if seen is None:
            self.publishers[publisher] = PublisherSequence(first, first - 1, messages=0)
        elif seen.restarts == 0 and seen.first > first:
            seen.head = seen.first - first

    def said(self, publisher: bytes, last: int) -> None:
        """The publisher says it had sent every number up to ``last``: those after the last one
        received are missed (the tail). Call it once the stream has ended (its last messages may
        still be on the way when it says so). A publisher neither received nor expected is left out:
        where its due began is not known (it may have sent all it said before the receiver came)."""
        seen = self.publishers.get(publisher)
        if seen is not None:
            seen.said = max(seen.said, last)

    @property
    def missed(self) -> int:
        """every number sent to this receiver that did not arrive: gaps, heads and tails"""
        return self.gaps + sum(p.head + p.tail for p in self.publishers.values())

    @property
    def untold(self) -> int:
        """publishers that did not say their last number: what they sent after their last message that
        arrived is not known"""
        return sum(1 for p in self.publishers.values() if not p.said)

    @property
    def messages(self) -> int:
        return sum(p.messages for p in self.publishers.values())

    def __len__(self) -> int:
        """How many publisher ids were seen."""
        return len(self.publishers)
