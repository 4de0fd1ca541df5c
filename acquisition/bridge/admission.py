"""Which moves a bridge lets into its queue, and when.

The moves the intake validated since the last tick are taken in arrival order, at most
:data:`MOVES_PER_TICK` a tick (a burst is spread over ticks). A move is accepted only from a live sender,
one that holds its liveliness token ``<prefix>/<axis>/sender/*``: a move whose sender's token has not
arrived yet is held up to :data:`SENDER_GRACE_S` (the token and the move travel separately), and a
sender whose token goes drops its moves that have not started (and those queued after them). While the
drive follows no setpoints, every move is refused with the reason (:mod:`.supervision` says which).
Each decision is a move status (:class:`~.statuses.StatusOutbox`); rejections are counted, the first
:data:`MAX_REPORTED_REJECTIONS` kept in the report, and logged at most ten a second.
"""

from __future__ import annotations

import logging
import time
from collections import deque

from ..errors import AcquisitionError
from ..wire.keys import AxisKeys
from ..wire.move_status import MoveState
from .move_intake import MoveIntake, ReceivedMove
from .move_queue import MoveQueue
from .report import BridgeReport
from .statuses import StatusOutbox

log = logging.getLogger("axisflow.acquisition.bridge.bridge")  # the bridge's log

SENDER_GRACE_S = 0.5
"""how long [s of wall time] a move may wait for its sender's liveliness token to arrive"""
MOVES_PER_TICK = 4
"""moves the loop takes per tick from the intake, and from those waiting for their sender's token:
a burst of thousands (valid or not) is spread over ticks instead of stalling one, since each costs a
status message and a log line on the loop (~20–60 µs)"""
MAX_REPORTED_REJECTIONS = 100
"""rejection texts kept in the report (the first ones; all are counted and each has its status)"""


class _RateLimitedLog:
    """At most ``per_second`` log lines a second, then one line saying how many were left out: a flood
    of bad moves must not make the loop write thousands of lines (a stderr pipe nobody reads would
    block it once full)."""

    def __init__(self, logger: logging.Logger, per_second: int) -> None:
        self._log, self._per_second = logger, per_second
        self._window = -1
        self._count = self._skipped = 0

    def warning(self, text: str) -> None:
        window = int(time.monotonic())
        if window != self._window:
            if self._skipped:
                self._log.warning(
                    "… and %d more rejections in that second (each has its move status)", self._skipped
                )
            self._window, self._count, self._skipped = window, 0, 0
        self._count += 1
        if self._count <= self._per_second:
            self._log.warning("%s", text)
        else:
            self._skipped += 1


class MoveAdmission:
    """The admission of one bridge's moves: its live senders and the moves waiting for theirs."""

    def __init__(
        self, keys: AxisKeys, intake: MoveIntake, queue: MoveQueue, outbox: StatusOutbox, report: BridgeReport
    ) -> None:
        self.keys = keys
        self.intake = intake
        self.queue = queue
        self.outbox = outbox
        self.report = report
        self.alive: set[bytes] = set()
        """the senders whose liveliness token is up"""
        self._gone: set[bytes] = set()
        self._pending: deque[tuple[ReceivedMove, float]] = deque()
        """validated moves waiting for their sender's token, with the wall time they wait until"""
        self._reject_log = _RateLimitedLog(log, per_second=10)

    @property
    def pending(self) -> int:
        """Moves waiting for their sender's token."""
        return len(self._pending)

    def sender_token(self, gid: bytes, present: bool, tick: int) -> None:
        """A sender's token came (``present``) or went: a sender gone drops its moves that have not
        started, and every move queued after the first of them."""
        if present:
            self.alive.add(gid)
            self._gone.discard(gid)
            return
        self.alive.discard(gid)
        self._gone.add(gid)
        dropped = self.queue.drop_sender(gid, tick)
        self.outbox.dropped(
            dropped,
            tick,
            f"sender {gid.hex()} disappeared (its moves that had not started, and every move queued "
            "after the first of them, are dropped)",
        )
        if dropped:
            log.warning("sender %s disappeared: dropped %d queued moves", gid.hex(), len(dropped))

    def take_moves(self, tick: int, refusal: str | None) -> None:
        """Queue the moves validated since the last tick, in arrival order, at most
        :data:`MOVES_PER_TICK` a tick (the rest wait for the next ticks); a move whose sender's token
        has not arrived yet waits for it, at most :data:`SENDER_GRACE_S`. ``refusal``: why the drive
        takes no moves now (each is rejected with it), None when it does."""
        for received in self.intake.poll(MOVES_PER_TICK):
            if received.error:
                self.reject(received, received.error, tick)
            else:
                self._pending.append((received, time.monotonic() + SENDER_GRACE_S))
        for _ in range(MOVES_PER_TICK):
            if not self._pending:
                break
            received, deadline = self._pending[0]
            sender = received.sender
            if sender not in self.alive:
                if sender not in self._gone and time.monotonic() < deadline:
                    break
                self._pending.popleft()
                self.reject(
                    received,
                    f"its sender holds no liveliness token {self.keys.senders} (send moves with MoveSender "
                    "and keep it open while they run)",
                    tick,
                )
                continue
            self._pending.popleft()
            cmd, move = received.command, received.move
            assert cmd is not None and move is not None
            if refusal is not None:
                self.reject(received, refusal, tick)
                continue
            try:
                queued = self.queue.enqueue(cmd, move, tick, sender)
            except AcquisitionError as exc:
                self.reject(received, str(exc), tick)
                continue
            self.report.moves_accepted += 1
            log.info("accepted move %d: ticks %d..%d", cmd.move_id, queued.start_tick, queued.end_tick)
            self.outbox.move(
                MoveState.ACCEPTED,
                queued,
                tick,
                f"accepted move {cmd.move_id}: start tick {queued.start_tick}, end tick {queued.end_tick}",
            )

    def reject_pending(self, reason: str, tick: int) -> None:
        """Reject every move still waiting for its sender's token, with ``reason``."""
        for received, _deadline in self._pending:
            self.reject(received, reason, tick)
        self._pending.clear()

    def reject(self, received: ReceivedMove, reason: str, tick: int) -> None:
        """A REJECTED status of ``received`` saying ``reason``; counted, kept in the report, logged."""
        move_id = received.command.move_id if received.command is not None else 0
        text = reason if reason.startswith(f"move {move_id}") else f"move {move_id}: {reason}"
        self.report.moves_rejected += 1
        if len(self.report.rejections) < MAX_REPORTED_REJECTIONS:
            self.report.rejections.append(text)
        self._reject_log.warning(f"rejected {text}")
        self.outbox.rejected(move_id, tick, received.sender.hex(), f"rejected {text}")
