"""Readiness on the bus, from facts: a subscriber that joins without a gap, a publisher that knows it
is heard.

**Why a subscriber needs more than its declaration.** When two Zenoh 1.10 peers connect, each sends
the other an *initial interest* and, until the other answers it (its current declarations, then a
``DeclareFinal``), routes *all* its publications to it, declared or not. Once the answer is in, it
routes only to the subscribers it knows. A subscriber declared right after its session opened is
caught between the two: its session has already answered (without it), so the publisher first sends
it everything, then — having read the answer — nothing, until the subscriber's own declaration
arrives a few milliseconds later. The subscriber sees a few samples, then a run of tens to hundreds
missing (docs/acquisition.md counts how often, with ``axisflow bench joins``). Waiting a fixed time
before declaring hid it; a fact proves it gone:

1. **hello** — the joining session asks every publisher whose key matches its subscription
   (:func:`say_hello`; each :class:`~.publisher.SequencedPublisher` answers on
   :func:`~axisflow.acquisition.wire.keys.hello_key`). The query goes at ``Priority.DATA``, the
   priority of declarations, so it reaches each publisher's session *after* the answer to its initial
   interest; the reply comes back at the same priority, *after* everything that publisher sent
   before. Once every publisher has answered, none routes to this session any more unless it
   subscribed, and nothing sent earlier is still on the way.
2. **declare** the subscriber: its first sample from each publisher is one routed to it as a
   subscriber, and every later one follows.
3. **hello again**: the reply proves each publisher has read the declaration (declarations and the
   query travel in order), so from now on nothing it publishes is missed — the subscriber is
   *ready*. Had a new peer connected between 1 and 2 (its own initial-interest window open), the
   subscriber is declared again.

A peer that connects *after* the declaration receives it with the answer to its initial interest,
before it stops routing everything: no gap. On stop, one more hello (:meth:`JoinedSubscriber.flush`)
proves that nothing sent before it is still on the way, so draining the channel afterwards loses
nothing in flight. Publishers of other tools (no hello) cannot be proven; they are not waited for.

**A publisher** learns from Zenoh's matching status when a subscriber matches it (:class:`MatchWatch`:
a matching listener sets an event, so waiting costs nothing per message).

**A publisher that stops.** What ``put`` has accepted may still sit in the session's transmit queue,
and closing the session drops it: a bridge that ran its last ticks at full speed on a busy machine lost
the last 120–341 of 500 samples in 4 of 16 runs. Every joined subscriber answers receipt queries
(:class:`ReceiptResponder`, on :func:`~axisflow.acquisition.wire.keys.receipt_key`);
:func:`confirm_delivery` asks them all at each priority its publishers used, behind the samples in
the same transmit queue, so an answer proves that everything sent before it has reached that
subscriber's channel. A publisher calls it before it closes its session.

**What a publisher sent, counted.** Telemetry drops on congestion, and Zenoh does not tell the
publisher what it dropped; what the publisher does know is its sequence numbers. A receiver counts the
gaps between the messages that reached it, but the messages after the last one that did (dropped
while a starved recorder could not take them, say) leave no gap. So the receipt query carries each
publisher's last number (:class:`~axisflow.acquisition.wire.last_sequences.LastSequences`), and goes
first at ``Priority.REAL_TIME``, ahead of a backlog that may not drain before the publisher gives up
waiting; a subscriber hands it to its owner (``on_counts``), which counts the numbers after the last
one received as missed. A hello's answer carries the number too: a subscriber that joins is owed the
numbers after the one in the answer, and one that stops, those up to the one in its last hello's.
"""

from __future__ import annotations

import dataclasses
import itertools
import logging
import os
import socket
import threading
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any

import zenoh

from ..errors import AcquisitionError, WireError, zenoh_reason
from ..wire.hello import HELLO_ENCODING, Hello
from ..wire.keys import hello_key, hello_selector, receipt_key, receipt_selector
from ..wire.last_sequences import LAST_SEQUENCES_ENCODING, LastSequences

log = logging.getLogger(__name__)

HELLO_TIMEOUT_S = 5.0
"""how long a hello waits for every publisher's answer [s]"""
FLUSH_TIMEOUT_S = 1.0
"""how long the hello of a subscriber that stops waits [s] (within the 2 s a stop may take)"""
JOIN_ATTEMPTS = 5
"""declarations a join tries while new peers keep arriving between its hellos"""
_STOP_POLL_S = 0.05
"""how often a hello looks at its stop event while it waits [s]"""
_IDLE_S = 0.0005
"""the pause of a hello's wait when ``while_waiting`` found nothing to do [s]"""
_HELLO_PRIORITY = zenoh.Priority.DATA
"""the priority of Zenoh's declarations in 1.10 (``QoSType::DECLARE``): the hello must travel in
order with them (a hello of a higher priority overtakes them: docs/acquisition.md)"""
_COUNTS_PRIORITY = zenoh.Priority.REAL_TIME
"""the first receipt query, with the publishers' last numbers, overtakes the samples still queued"""


_RECEIPT_NUMBERS = itertools.count(1)
"""numbers the receipt queryables of the subscribers of one process"""


class NotReadyError(AcquisitionError):
    """A hello was not answered in time: the routes to some publishers are not proven."""


class HelloResponder:
    """The hello queryable of one publisher (declared and undeclared with it); ``sequence`` says the
    number of the last message it has put."""

    def __init__(
        self, session: zenoh.Session, key: str, publisher_id: bytes, sequence: Callable[[], int]
    ) -> None:
        zid = str(session.info.zid())
        self._hello = Hello(key, publisher_id.hex(), zid, socket.gethostname(), os.getpid(), 0)
        self._sequence = sequence
        self._key = hello_key(key, publisher_id)
        # replying from Zenoh's thread: a small payload, no Python work worth a queue
        self._queryable = session.declare_queryable(self._key, self._reply)

    def _reply(self, query: zenoh.Query) -> None:
        answer = dataclasses.replace(self._hello, sequence=self._sequence()).encode()
        try:
            query.reply(self._key, answer, encoding=HELLO_ENCODING)
        except zenoh.ZError as exc:  # the asker went away
            log.debug("hello to %s not answered: %s", self._key, zenoh_reason(exc))

    def undeclare(self) -> None:
        self._queryable.undeclare()


def _ask_all(
    session: zenoh.Session,
    selector: str,
    priority: zenoh.Priority,
    timeout_s: float,
    on_reply: Callable[[zenoh.Reply], None],
    payload: bytes | None = None,
) -> threading.Event:
    """Query every queryable on ``selector`` (all of them, answers not consolidated, blocking on
    congestion so that the query keeps its place behind what was sent before it) at ``priority``,
    with ``payload`` if given; ``on_reply`` runs on Zenoh's thread. The event is set once the query
    has ended: all answered, or ``timeout_s`` passed."""
    done = threading.Event()
    extra: dict[str, Any] = {}
    if payload is not None:
        extra = {"payload": payload, "encoding": LAST_SEQUENCES_ENCODING}
    session.get(
        selector,
        zenoh.handlers.Callback(on_reply, done.set),
        target=zenoh.QueryTarget.ALL,
        consolidation=zenoh.ConsolidationMode.NONE,
        priority=priority,
        congestion_control=zenoh.CongestionControl.BLOCK,
        timeout=max(timeout_s, 0.001),
        **extra,
    )
    return done


class ReceiptResponder:
    """The receipt queryable of one joined subscriber: it answers every query at once, so the answer
    leaves after everything the asker sent before its query has been taken by this session. A query
    that carries its publishers' last numbers is handed to ``on_counts`` first (on Zenoh's thread:
    keep it short)."""

    def __init__(
        self, session: zenoh.Session, on_counts: Callable[[LastSequences], None] | None = None
    ) -> None:
        self._on_counts = on_counts
        self._key = receipt_key(str(session.info.zid()), next(_RECEIPT_NUMBERS))
        self._queryable = session.declare_queryable(self._key, self._reply)

    def _reply(self, query: zenoh.Query) -> None:
        if self._on_counts is not None and query.payload is not None:
            try:
                self._on_counts(LastSequences.decode(query.payload.to_bytes()))
            except WireError as exc:  # an asker that is not ours
                log.warning("a receipt query on %s: %s", self._key, exc)
        try:
            query.reply(self._key, b"")
        except zenoh.ZError as exc:  # the asker went away
            log.debug("receipt on %s not answered: %s", self._key, zenoh_reason(exc))

    def undeclare(self) -> None:
        self._queryable.undeclare()


def confirm_delivery(
    session: zenoh.Session,
    priorities: Iterable[zenoh.Priority],
    timeout_s: float = FLUSH_TIMEOUT_S,
    counts: LastSequences | None = None,
) -> int:
    """Ask every joined subscriber for a receipt at each of ``priorities`` (those of the publishers
    whose samples must arrive) and wait for the answers, at most ``timeout_s``; returns the fewest
    answers any priority got (0 when no subscriber listens: then there is nothing to wait for).
    ``counts``: the publishers' last numbers, carried by every query, the first of them sent at
    ``REAL_TIME`` ahead of the samples still queued (see the module docstring)."""
    distinct: list[zenoh.Priority] = [] if counts is None else [_COUNTS_PRIORITY]
    for priority in priorities:  # (zenoh's priorities compare, but do not hash)
        if priority not in distinct:
            distinct.append(priority)
    payload = None if counts is None else counts.encode()
    rounds = []
    for priority in distinct:
        answers: list[int] = []
        on_reply = lambda reply, got=answers: got.append(reply.ok is not None)  # noqa: E731
        asked = _ask_all(session, receipt_selector(), priority, timeout_s, on_reply, payload)
        rounds.append((answers, asked))
    deadline = time.monotonic() + timeout_s + 0.1  # (Zenoh ends each query at its timeout)
    for _answers, done in rounds:
        done.wait(max(deadline - time.monotonic(), 0.0))
    return min((sum(answers) for answers, _done in rounds), default=0)


def tell_last_sequences(session: zenoh.Session, counts: LastSequences) -> None:
    """Say ``counts`` to every joined subscriber (a receipt query at ``REAL_TIME``) without waiting for
    an answer: what a publisher does as it is undeclared (:func:`confirm_delivery` also waits for the
    samples to arrive)."""
    ignore = lambda _reply: None  # noqa: E731
    _ask_all(session, receipt_selector(), _COUNTS_PRIORITY, FLUSH_TIMEOUT_S, ignore, counts.encode())


@dataclass(frozen=True)
class HelloRound:
    """One hello: the publishers that answered and the peers the session had when it asked."""

    selector: str
    hellos: tuple[Hello, ...]
    peers: frozenset[str]
    """Zenoh ids of the peers connected when the hello was sent"""
    seconds: float

    @property
    def answered(self) -> frozenset[str]:
        """Zenoh ids of the sessions that answered."""
        return frozenset(h.zid for h in self.hellos)


def _peers(session: zenoh.Session) -> frozenset[str]:
    return frozenset(str(z) for z in session.info.peers_zid())


def say_hello(
    session: zenoh.Session,
    key_expr: str,
    timeout_s: float = HELLO_TIMEOUT_S,
    stop: threading.Event | None = None,
    while_waiting: Callable[[], int] | None = None,
) -> HelloRound | None:
    """Ask every publisher on ``key_expr`` for a hello and wait for all answers (see the module
    docstring); a :class:`NotReadyError` naming the peers that did not answer after ``timeout_s``;
    None if ``stop`` was set first. ``while_waiting`` is called meanwhile (it returns how much work it
    did; 0: the wait sleeps a little) — a subscriber keeps draining its channel, so that a full channel
    does not hold back the answers queued behind its samples."""
    selector = str(zenoh.KeyExpr.autocanonize(hello_selector(key_expr)))
    peers = _peers(session)
    t0 = time.monotonic()
    answers: list[bytes] = []
    errors: list[str] = []

    def on_reply(reply: zenoh.Reply) -> None:  # on Zenoh's thread: keep the bytes, decode later
        if reply.ok is not None:
            answers.append(reply.ok.payload.to_bytes())
        else:
            errors.append(reply.err.payload.to_string() if reply.err is not None else "no reply")

    done = _ask_all(session, selector, _HELLO_PRIORITY, timeout_s, on_reply)
    while not done.is_set():
        if stop is not None and stop.is_set():
            return None
        if while_waiting is None or not while_waiting():
            done.wait(_STOP_POLL_S if while_waiting is None else _IDLE_S)
    hellos: list[Hello] = []
    for data in answers:
        try:
            hellos.append(Hello.decode(data))
        except WireError as exc:  # something else answers under our verbatim prefix
            log.warning("ignoring an answer to the hello on %s: %s", selector, exc)
    done_round = HelloRound(selector, tuple(hellos), peers, time.monotonic() - t0)
    if errors:
        silent = sorted(peers - done_round.answered)
        raise NotReadyError(
            f"the publishers on {key_expr} did not all answer the hello ({selector}) within "
            f"{timeout_s:g} s ({errors[0]}); answered: {_names(done_round.hellos) or 'none'}; connected "
            f"peers that did not answer: {', '.join(silent) or 'none'}"
        )
    return done_round


def _names(hellos: tuple[Hello, ...]) -> str:
    return ", ".join(f"{h.key} ({h.where})" for h in hellos)


@dataclass(frozen=True)
class JoinReport:
    """How a subscriber joined: the hellos before and after its declaration."""

    before: HelloRound
    after: HelloRound
    attempts: int

    @property
    def publishers(self) -> tuple[Hello, ...]:
        """The publishers proven to route to the subscriber."""
        return self.after.hellos


class JoinedSubscriber:
    """A subscriber on ``key_expr`` declared once its routes are proven (see the module docstring).

    Use as a context manager; ``handler`` makes a fresh Zenoh handler (e.g. ``lambda:
    zenoh.handlers.FifoChannel(n)``) for each declaration. On entry it is ready: nothing published on
    ``key_expr`` by an axisflow publisher from then on is missed on the way — unless ``stop`` was set
    while it joined, in which case :attr:`subscriber` is None. ``announce``: a liveliness token
    declared once ready (after the subscriber, so a session that sees it knows the subscriber too),
    held until exit. ``on_counts``: called (on Zenoh's thread) with the last numbers a closing
    publisher's receipt query carries."""

    def __init__(
        self,
        session: zenoh.Session,
        key_expr: str,
        handler: Callable[[], Any],
        timeout_s: float = HELLO_TIMEOUT_S,
        stop: threading.Event | None = None,
        announce: str | None = None,
        on_counts: Callable[[LastSequences], None] | None = None,
    ) -> None:
        self._session, self.key_expr, self._handler = session, key_expr, handler
        self.timeout_s, self._stop, self._announce = timeout_s, stop, announce
        self._on_counts = on_counts
        self.subscriber: zenoh.Subscriber | None = None
        self.report: JoinReport | None = None
        self._token: zenoh.LivelinessToken | None = None
        self._receipts: ReceiptResponder | None = None

    def __enter__(self) -> JoinedSubscriber:
        # the receipt queryable first: its declaration reaches a publisher before the subscriber's, so
        # a publisher that starts on seeing the subscriber can already ask it
        self._receipts = ReceiptResponder(self._session, self._on_counts)
        try:
            return self._join()
        except BaseException:
            self._receipts.undeclare()
            self._receipts = None
            raise

    def _join(self) -> JoinedSubscriber:
        deadline = time.monotonic() + self.timeout_s
        for attempt in range(1, JOIN_ATTEMPTS + 1):
            before = say_hello(self._session, self.key_expr, deadline - time.monotonic(), self._stop)
            if before is None:
                return self
            subscriber = self._session.declare_subscriber(self.key_expr, self._handler())
            peers_at_declaration = _peers(self._session)
            try:
                after = say_hello(self._session, self.key_expr, deadline - time.monotonic(), self._stop)
            except BaseException:
                subscriber.undeclare()
                raise
            if after is None:
                subscriber.undeclare()
                return self
            if peers_at_declaration <= before.peers:
                self.subscriber = subscriber
                self.report = JoinReport(before, after, attempt)
                if self._announce is not None:
                    self._token = self._session.liveliness().declare_token(self._announce)
                return self
            subscriber.undeclare()  # a peer arrived between the hellos: its first samples may gap
            log.debug("peers %s arrived while joining %s", peers_at_declaration - before.peers, self.key_expr)
        raise NotReadyError(
            f"the subscriber on {self.key_expr} could not join: new peers kept connecting during "
            f"{JOIN_ATTEMPTS} attempts"
        )

    def flush(
        self, timeout_s: float = FLUSH_TIMEOUT_S, while_waiting: Callable[[], int] | None = None
    ) -> HelloRound | None:
        """One hello: once answered, everything the publishers sent before it has arrived — in the
        channel, behind at most its capacity of samples (keep draining it with ``while_waiting``
        meanwhile, then take at most that many). Returns the round (each answer with the publisher's
        last number then); None (and a warning) if some did not answer within ``timeout_s``."""
        try:
            return say_hello(self._session, self.key_expr, timeout_s, while_waiting=while_waiting)
        except NotReadyError as exc:
            log.warning("%s", exc)
            return None

    def __exit__(self, *_exc: object) -> None:
        if self._token is not None:
            self._token.undeclare()
            self._token = None
        if self._receipts is not None:
            self._receipts.undeclare()
            self._receipts = None
        if self.subscriber is not None:
            self.subscriber.undeclare()
            self.subscriber = None


def wait_for_token(session: zenoh.Session, key: str, timeout_s: float) -> bool:
    """True once a liveliness token on ``key`` is known to ``session``; False after ``timeout_s``."""
    with session.liveliness().declare_subscriber(key, zenoh.handlers.FifoChannel(16), history=True) as sub:
        deadline = time.monotonic() + timeout_s
        while True:
            token = sub.try_recv()
            if token is not None and token.kind == zenoh.SampleKind.PUT:
                return True
            if time.monotonic() >= deadline:
                return False
            if token is None:
                time.sleep(0.005)


class MatchWatch:
    """Whether subscribers match one or more publishers, kept by Zenoh's matching listeners: reading
    :attr:`event` costs an attribute check, waiting on it costs nothing (use as a context manager)."""

    def __init__(self, publishers: list[zenoh.Publisher]) -> None:
        self.event = threading.Event()
        """set while at least one of the publishers has a matching subscriber"""
        self._matching = [False] * len(publishers)
        self._lock = threading.Lock()
        self._listeners = []
        for i, pub in enumerate(publishers):
            self._listeners.append(pub.declare_matching_listener(self._callback(i)))
            # zenoh 1.10 returns a MatchingStatus here (its stub says bool; the matching watch's test
            # holds this to the behaviour)
            self._set(i, pub.matching_status.matching)  # type: ignore[attr-defined]

    def _callback(self, index: int) -> Callable[[zenoh.MatchingStatus], None]:
        return lambda status: self._set(index, status.matching)

    def _set(self, index: int, matching: bool) -> None:
        with self._lock:
            self._matching[index] = matching
            if any(self._matching):
                self.event.set()
            else:
                self.event.clear()

    @property
    def matched(self) -> bool:
        return self.event.is_set()

    def wait(self, timeout_s: float) -> bool:
        """True once a subscriber matches (at once if one does), False after ``timeout_s``."""
        return self.event.wait(timeout_s)

    def close(self) -> None:
        for listener in self._listeners:
            listener.undeclare()
        self._listeners.clear()

    def __enter__(self) -> MatchWatch:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()
