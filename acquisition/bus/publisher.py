"""A Zenoh publisher that numbers its messages and attaches their source time stamp.

Commands (moves) and telemetry (samples, setpoints) use different Zenoh priorities so that blocking
command traffic never stalls telemetry and vice versa. Every publisher answers hellos
(:mod:`.readiness`): a subscriber that joins proves its route to it before it counts on it.
"""

from __future__ import annotations

import logging
import os
import time
from collections.abc import Iterable
from enum import Enum

import zenoh

from ..errors import zenoh_reason
from ..wire.attachment import pack_attachment
from ..wire.last_sequences import LastSequence, LastSequences
from ..wire.messages import SCHEMAS
from .readiness import FLUSH_TIMEOUT_S, HelloResponder, MatchWatch, confirm_delivery, tell_last_sequences

log = logging.getLogger(__name__)


class Traffic(Enum):
    """What a publisher carries; sets its Zenoh priority and congestion control."""

    TELEMETRY = "telemetry"
    """1 kHz samples/setpoints: priority DATA_HIGH; drop on congestion (a drive never waits)"""
    COMMAND = "command"
    """moves: priority INTERACTIVE_HIGH; block on congestion (never lost to a full queue)"""
    BULK = "bulk"
    """as fast as the consumers allow (--speed 0, replay): priority DATA; block on congestion"""


_QOS = {
    Traffic.TELEMETRY: (zenoh.Priority.DATA_HIGH, zenoh.CongestionControl.DROP),
    Traffic.COMMAND: (zenoh.Priority.INTERACTIVE_HIGH, zenoh.CongestionControl.BLOCK),
    Traffic.BULK: (zenoh.Priority.DATA, zenoh.CongestionControl.BLOCK),
}


def encoding_for(type_name: str) -> zenoh.Encoding:
    """Zenoh encoding ``application/cdr;<ROS 2 type>`` (the recorder reads the type from it)."""
    return zenoh.Encoding.APPLICATION_CDR.with_schema(type_name)


def type_of_encoding(encoding: zenoh.Encoding | str) -> str | None:
    """The ROS 2 type named by an ``application/cdr;<type>`` encoding, or None."""
    text = str(encoding)
    head, _, schema = text.partition(";")
    return schema if head == "application/cdr" and schema in SCHEMAS else None


_MCAP_ENCODINGS = {"application/cdr": "cdr", "application/json": "json", "application/protobuf": "protobuf"}


def mcap_encoding_of(encoding: zenoh.Encoding | str) -> tuple[str, str | None]:
    """(MCAP message encoding, ROS 2 type or None) for a Zenoh encoding.

    ``application/cdr;<known type>`` → ("cdr", type); other CDR, JSON and protobuf payloads → the MCAP
    well-known name with no schema; anything else keeps its Zenoh encoding as the message encoding
    (e.g. ``zenoh/bytes``, ``text/plain``), so no reader mistakes it for CDR.
    """
    text = str(encoding)
    head = text.partition(";")[0]
    return _MCAP_ENCODINGS.get(head, head or "zenoh/bytes"), type_of_encoding(text)


class SequencedPublisher:
    """Declares a publisher on ``key``; :meth:`put` adds the rmw_zenoh-style attachment."""

    def __init__(
        self, session: zenoh.Session, key: str, type_name: str, traffic: Traffic, gid: bytes | None = None
    ) -> None:
        """``gid``: the publisher id of the attachments (default: a new random one; publishers of one
        sender share theirs, so the bridge knows them as one)."""
        priority, congestion = _QOS[traffic]
        self.priority = priority
        """the Zenoh priority its samples travel at"""
        self.key = key
        self._session = session
        self.gid = os.urandom(16) if gid is None else gid
        self.sequence = 0
        self._pub = session.declare_publisher(
            key, encoding=encoding_for(type_name), priority=priority, congestion_control=congestion
        )
        try:
            self._hello = HelloResponder(session, key, self.gid, lambda: self.sequence)
        except BaseException:
            self._pub.undeclare()
            raise

    def put(self, payload: bytes, source_stamp_ns: int | None = None) -> int:
        """Publish one message; returns its sequence number (1, 2, …). :attr:`sequence` counts it once
        ``put`` has handed it to Zenoh (a hello answered meanwhile says only what has left)."""
        sequence = self.sequence + 1
        stamp = time.time_ns() if source_stamp_ns is None else source_stamp_ns
        self._pub.put(payload, attachment=pack_attachment(sequence, stamp, self.gid))
        self.sequence = sequence
        return sequence

    def last_sequence(self) -> LastSequence:
        """Its key, its id and the number of the last message it put."""
        return LastSequence(self.key, self.gid.hex(), self.sequence)

    @property
    def has_subscribers(self) -> bool:
        return self._pub.matching_status.matching

    def watch_matching(self) -> MatchWatch:
        """A :class:`~.readiness.MatchWatch` of this publisher (close it, or use it as a context
        manager)."""
        return MatchWatch([self._pub])

    def undeclare(self) -> None:
        """Undeclare it, saying its last number to the joined subscribers (they count what of it did not
        arrive: :func:`~.readiness.tell_last_sequences`)."""
        self._hello.undeclare()
        try:
            if self.sequence:
                tell_last_sequences(self._session, LastSequences((self.last_sequence(),)))
        except zenoh.ZError as exc:  # the session is going
            log.debug("the last number of %s not said: %s", self.key, zenoh_reason(exc))
        self._pub.undeclare()

    def __enter__(self) -> SequencedPublisher:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.undeclare()


def confirm_delivered(
    session: zenoh.Session, publishers: Iterable[SequencedPublisher], timeout_s: float = FLUSH_TIMEOUT_S
) -> int:
    """Before ``session`` closes: wait (at most ``timeout_s``) until every joined subscriber, a recorder
    for one, has taken what ``publishers`` sent — closing drops what still waits to be sent
    (:func:`~.readiness.confirm_delivery`) — and tell each their last sequence numbers, so that what
    did not arrive is counted. Returns how many confirmed; 0 at once when none listens, and 0 when the
    session is already going."""
    publishers = list(publishers)
    counts = LastSequences(tuple(p.last_sequence() for p in publishers))
    try:
        return confirm_delivery(session, [p.priority for p in publishers], timeout_s, counts)
    except zenoh.ZError as exc:
        log.debug("delivery of the last messages not confirmed: %s", zenoh_reason(exc))
        return 0


def watch_consumers(publishers: list[SequencedPublisher]) -> MatchWatch:
    """A :class:`~.readiness.MatchWatch` set while any of ``publishers`` has a matching subscriber."""
    return MatchWatch([p._pub for p in publishers])


def wait_for_subscribers(publishers: list[SequencedPublisher], timeout_s: float) -> bool:
    """Wait until every publisher has a matching subscriber (True) or ``timeout_s`` passes (False).

    Zenoh's matching listener says so as soon as the subscriber's declaration has reached this
    session: what is published from then on is routed to it (no settling time)."""
    deadline = time.monotonic() + timeout_s
    for pub in publishers:
        with pub.watch_matching() as watch:
            if not watch.wait(max(deadline - time.monotonic(), 0.0)):
                return False
    return True
