"""The bridge's move statuses, queued: each a typed
:class:`~axisflow.acquisition.wire.move_status.MoveStatus` stamped with the drive time of the tick it
happened at, published in order after the tick's setpoint, at most a given number a tick
(:meth:`StatusOutbox.send`)."""

from __future__ import annotations

from collections import deque
from collections.abc import Callable

from ..drives.drive import DriveEvent
from ..wire.move_status import NO_TICK, MoveState, MoveStatus
from ..wire.quick_stop import STOP_MOVE_ID
from .move_queue import QueuedMove
from .report import BridgeReport


class StatusOutbox:
    """The statuses of one axis not published yet. ``stamp_of(tick)`` is the drive time of a tick [ns];
    dropped moves are counted in ``report``."""

    def __init__(self, axis: str, report: BridgeReport, stamp_of: Callable[[int], int]) -> None:
        self.axis = axis
        self.report = report
        self.stamp_of = stamp_of
        self._waiting: deque[MoveStatus] = deque()

    def __len__(self) -> int:
        return len(self._waiting)

    def move(self, state: MoveState, q: QueuedMove, tick: int, text: str) -> None:
        """A status of the queued move ``q``."""
        self._waiting.append(MoveStatus(self.stamp_of(tick), self.axis, state, q.command.move_id, tick,
                                        q.start_tick, q.end_tick, q.sender.hex(), text))  # fmt: skip

    def dropped(self, moves: list[QueuedMove], tick: int, why: str) -> None:
        """A DROPPED status for each of ``moves`` (taken out of the queue), saying ``why``; counted."""
        for q in moves:
            self.move(MoveState.DROPPED, q, tick, f"dropped move {q.command.move_id}: {why}")
        self.report.moves_dropped += len(moves)

    def rejected(self, move_id: int, tick: int, sender: str, text: str) -> None:
        """A REJECTED status of a move that never entered the queue."""
        self._waiting.append(MoveStatus(self.stamp_of(tick), self.axis, MoveState.REJECTED, move_id, tick,
                                        NO_TICK, NO_TICK, sender, text))  # fmt: skip

    def axis_status(
        self, state: MoveState, tick: int, sender: str, text: str, event: DriveEvent | None = None
    ) -> None:
        """A status of move 0 (about the axis, not a move), with the drive's codes of ``event``."""
        codes = (event.error_code, event.error_register, event.statusword) if event is not None else (0, 0, 0)
        self._waiting.append(MoveStatus(self.stamp_of(tick), self.axis, state, STOP_MOVE_ID, tick, NO_TICK,
                                        NO_TICK, sender, text, *codes))  # fmt: skip

    def stopped_in_place(self, tick: int, ends: int, sender: str, text: str) -> None:
        """The STOPPED status of a quick stop that needs no braking (the axis at rest, or its move reaching
        rest sooner on its own course, at tick ``ends``)."""
        self._waiting.append(MoveStatus(self.stamp_of(tick), self.axis, MoveState.STOPPED, STOP_MOVE_ID,
                                        tick, tick, ends, sender, text))  # fmt: skip

    def send(self, put: Callable[[bytes], object], limit: int) -> None:
        """Publish (``put``) the first ``limit`` waiting statuses, in order."""
        for _ in range(min(limit, len(self._waiting))):
            put(self._waiting.popleft().encode())
