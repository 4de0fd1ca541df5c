"""Moves arriving for a drive: received on Zenoh's thread, decoded and validated on a thread of their
own, handed to the 1 kHz loop in arrival order.

Validating a move samples it at 1 kHz (a one-hour move: 3.6 million samples), which must not stall the
drive's loop. So a worker thread owns the subscriber (a Zenoh FIFO channel: no Python callback runs on
Zenoh's threads, and only this thread touches the channel, from declaration to undeclaration). It waits
in the channel's blocking receive, which holds no interpreter lock: an idle intake never takes the lock
the loop's ticks need (a thread that polled took it 500 times a second, and one preempted while holding
it held up a real-time tick for as long as the scheduler kept it off a core); closing it wakes the
receive with an empty sample put only inside this session. It decodes
each :class:`~axisflow.acquisition.wire.messages.MoveCommand`, counts the sequence numbers its sender skipped
and runs the stateless part of the validation
(:func:`~axisflow.acquisition.bridge.move_queue.validate_move`); the loop collects the results with
:meth:`MoveIntake.poll` and queues them (cheap checks only).
"""

from __future__ import annotations

import logging
import queue
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

import zenoh

from ...model import Move
from ...model.trajectory import MAX_KNOTS
from ..errors import AcquisitionError
from ..wire.attachment import unpack_attachment
from ..wire.messages import MoveCommand
from ..wire.sequence import SequenceTracker

log = logging.getLogger(__name__)

INBOX_CAPACITY = 1024
"""moves waiting for validation in the Zenoh channel (when it is full, the sender's blocking
publication waits: moves are commands and are never dropped on the way)"""
MAX_PAYLOAD_BYTES = 32 * MAX_KNOTS + 65536
"""the largest move payload taken [bytes]: four float64 knot arrays of MAX_KNOTS knots and the fixed
fields. A larger one is rejected before it is copied out of Zenoh's buffer (that copy holds the
interpreter lock, ~0.45 ms per MB, stalling the 1 kHz loop)"""
_STOP_TIMEOUT_S = 5.0
"""how long closing the intake waits for its thread (it undeclares its subscriber) [s]"""
_START_TIMEOUT_S = 10.0


@dataclass(frozen=True)
class ReceivedMove:
    """One move as received: validated (``move`` set) or rejected (``error`` set)."""

    command: MoveCommand | None
    move: Move | None
    sender: bytes
    """the sender's publisher id (from the attachment), b"" when there is none"""
    error: str = ""


class MoveIntake:
    """Receives and validates the moves sent to one key (use as a context manager)."""

    def __init__(self, session: zenoh.Session, key: str, validate: Callable[[MoveCommand], Move]) -> None:
        self._session = session
        self._key = key
        self._validate = validate
        self._results: queue.SimpleQueue[ReceivedMove] = queue.SimpleQueue()
        self._stop = threading.Event()
        self._ready = threading.Event()
        self._failure: BaseException | None = None
        self._thread = threading.Thread(target=self._work, name=f"move intake {key}", daemon=True)
        self._sequences = SequenceTracker()
        self._arrived = threading.Event()
        """set when a result is put (cleared by :meth:`wait` before it waits)"""

    @property
    def missed(self) -> int:
        """Moves lost on the way, from gaps in each sender's sequence numbers."""
        return self._sequences.missed

    def __enter__(self) -> MoveIntake:
        self._thread.start()
        self._ready.wait(_START_TIMEOUT_S)
        if self._failure is not None or not self._ready.is_set():
            self._stop.set()
            self._thread.join()
            raise AcquisitionError(f"cannot subscribe to {self._key}: {self._failure}")
        return self

    def __exit__(self, *_exc: object) -> None:
        self._stop.set()
        try:  # wake the receive: delivered to this session's subscribers only, never sent anywhere
            self._session.put(self._key, b"", allowed_destination=zenoh.Locality.SESSION_LOCAL)
        except zenoh.ZError as exc:  # the session is closing: so is the channel
            log.debug("the move intake of %s not woken: %s", self._key, exc)
        self._thread.join(_STOP_TIMEOUT_S)
        if self._thread.is_alive():  # its subscriber's undeclaration hangs: the daemon thread is left
            log.warning(
                "the move intake of %s did not stop within %.0f s; left behind", self._key, _STOP_TIMEOUT_S
            )

    def _work(self) -> None:
        try:
            subscriber = self._session.declare_subscriber(
                self._key, zenoh.handlers.FifoChannel(INBOX_CAPACITY)
            )
        except Exception as exc:  # reported by __enter__
            self._failure = exc
            self._ready.set()
            return
        self._ready.set()
        with subscriber:
            while True:
                try:
                    sample = subscriber.recv()
                except zenoh.ZError:  # the channel closed with the session
                    return
                if self._stop.is_set():
                    return
                self._results.put(self._receive(sample))
                self._arrived.set()
                time.sleep(0)  # hand the interpreter lock to the 1 kHz loop if it waits for it

    def _receive(self, sample: zenoh.Sample) -> ReceivedMove:
        att = sample.attachment
        sender = self._count(att.to_bytes()) if att is not None else b""
        size = len(sample.payload)
        if size > MAX_PAYLOAD_BYTES:
            return ReceivedMove(
                None,
                None,
                sender,
                f"undecodable move: payload of {size} bytes exceeds the largest move, {MAX_PAYLOAD_BYTES} "
                f"bytes ({MAX_KNOTS} knots)",
            )
        return self._decode(sample.payload.to_bytes(), sender)

    def _count(self, attachment: bytes) -> bytes:
        """The sender named by ``attachment`` (b"" if it is not ours); counts the moves it skipped."""
        parsed = unpack_attachment(attachment)
        if parsed is None:
            return b""
        seq, _stamp, sender = parsed
        self._sequences.add(sender, seq)
        return sender

    def _decode(self, payload: bytes, sender: bytes) -> ReceivedMove:
        try:
            cmd = MoveCommand.decode(payload)
        except AcquisitionError as exc:
            return ReceivedMove(None, None, sender, f"undecodable move: {exc}")
        try:
            return ReceivedMove(cmd, self._validate(cmd), sender)
        except AcquisitionError as exc:
            return ReceivedMove(cmd, None, sender, str(exc))
        except Exception as exc:  # a bug in validation must not kill the intake silently
            log.exception("validating move %d failed", cmd.move_id)
            return ReceivedMove(cmd, None, sender, f"move {cmd.move_id}: validation failed: {exc}")

    @property
    def waiting(self) -> int:
        """Moves received and validated, not yet taken by :meth:`poll`."""
        return self._results.qsize()

    def wait(self, timeout_s: float) -> bool:
        """Whether a received (and validated) move is waiting, or arrives within ``timeout_s``."""
        if not self._results.empty():
            return True
        self._arrived.clear()
        if not self._results.empty():
            return True
        return self._arrived.wait(timeout_s)

    def poll(self, limit: int | None = None) -> list[ReceivedMove]:
        """The moves received and validated since the last call, in arrival order (at most ``limit``;
        the rest stay for the next call)."""
        out: list[ReceivedMove] = []
        while limit is None or len(out) < limit:
            try:
                out.append(self._results.get_nowait())
            except queue.Empty:
                break
        return out
