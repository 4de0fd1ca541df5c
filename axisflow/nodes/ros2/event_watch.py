"""The bridge's move statuses and drive events as they arrive: every
:class:`~axisflow.acquisition.wire.move_status.MoveStatus` on ``<prefix>/<axis>/event``, whoever's move
it is about (the node's own, a planner's, the drive's own events of move 0).

The Zenoh subscriber queues them (a FIFO: statuses are few, each one matters); :meth:`EventWatch.poll`
decodes what arrived, on the caller's thread. Declare the watch before
:meth:`~axisflow.acquisition.bus.move_sender.MoveSender.wait_for_bridge`: its hello proves the bridge
has read this session's declarations made before it, this subscriber's included.
"""

from __future__ import annotations

import zenoh

from ...acquisition.errors import WireError
from ...acquisition.wire.keys import AxisKeys
from ...acquisition.wire.move_status import MoveStatus

EVENT_BACKLOG = 1 << 14
"""statuses held before the bridge's publication waits (the node polls every few ms)"""


class EventWatch:
    """Every status on an axis's event key (use as a context manager)."""

    def __init__(self, session: zenoh.Session, keys: AxisKeys) -> None:
        self.keys = keys
        self._sub = session.declare_subscriber(keys.event, zenoh.handlers.FifoChannel(EVENT_BACKLOG))
        self.undecodable = 0
        """payloads on the event key that are not a MoveStatus (skipped)"""

    def poll(self) -> list[MoveStatus]:
        """The statuses that arrived since the last call, in arrival order."""
        new = []
        while (sample := self._sub.try_recv()) is not None:
            try:
                new.append(MoveStatus.decode(sample.payload.to_bytes()))
            except WireError:
                self.undecodable += 1
        return new

    def close(self) -> None:
        self._sub.undeclare()

    def __enter__(self) -> EventWatch:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()
