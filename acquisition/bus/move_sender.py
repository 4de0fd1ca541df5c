"""Sending moves to a drive bridge: the small typed API the planner (or anyone) calls.

    with open_session(ZenohOptions()) as session, MoveSender(session, AxisKeys("a0")) as sender:
        sender.send(0.1, 0.5, 0.8, law="poly5")            # appended after the queued moves
        sender.send(0.5, 0.2, 0.6, start_ns=t_ns)          # starts at drive time t_ns
        sender.send_trajectory(path)                       # a SampledTrajectory, appended

Moves go out on ``<prefix>/<axis>/trajectory`` as ``axisflow_msgs/msg/Move`` with command priority and
blocking congestion control, numbered so the bridge counts any that were lost. The bridge answers each
step of a move's life with a typed :class:`~axisflow.acquisition.wire.move_status.MoveStatus` on
``<prefix>/<axis>/event``; the sender keeps those about its own moves (:meth:`MoveSender.poll_status`,
:meth:`MoveSender.wait_status`)::

    status = sender.wait_status(cmd.move_id, {MoveState.COMPLETED}, timeout_s=5.0)

While the sender is open it holds the liveliness token ``<prefix>/<axis>/sender/<id>``. A bridge runs
only moves whose sender is alive: when the sender closes (or its process dies), the bridge finishes the
move that is running and drops the sender's moves that have not started. Keep the sender open until
its moves have run.
"""

from __future__ import annotations

import time
from collections.abc import Collection

import zenoh

from ...model import SampledTrajectory
from ..errors import AcquisitionError, BridgeLostError, WireError
from ..wire.keys import AxisKeys
from ..wire.messages import APPEND, MOVE_TYPE, SAMPLED_LAW, Knots, MoveCommand
from ..wire.move_status import MoveState, MoveStatus
from ..wire.quick_stop import QUICK_STOP_TYPE, QuickStop
from .publisher import SequencedPublisher, Traffic
from .readiness import say_hello

TERMINAL_STATES = frozenset({MoveState.REJECTED, MoveState.DROPPED, MoveState.STOPPED, MoveState.COMPLETED})
"""the states after which a move has nothing more to say"""
STATUS_BACKLOG = 1 << 16
"""move statuses the sender's subscriber holds before the bridge's publication waits"""

BRIDGE_TIMEOUT_S = 20.0
"""how long a program waits for the bridge of its axis (its token and its move subscriber) [s]"""


class MoveSender:
    """Publishes :class:`MoveCommand` s for one axis."""

    def __init__(self, session: zenoh.Session, keys: AxisKeys) -> None:
        self.keys = keys
        self._session = session
        self._pub = SequencedPublisher(session, keys.trajectory, MOVE_TYPE, Traffic.COMMAND)
        self._status_sub = session.declare_subscriber(keys.event, zenoh.handlers.FifoChannel(STATUS_BACKLOG))
        self._bridge_tokens = session.liveliness().declare_subscriber(
            keys.alive, zenoh.handlers.FifoChannel(64), history=True
        )
        self._bridge_seen = False
        self._bridge_up = False
        self._token = session.liveliness().declare_token(keys.sender(self._pub.gid))
        self._next_id = 1
        self._stop_pub: SequencedPublisher | None = None
        self.statuses: list[MoveStatus] = []
        """every status the bridge published about this sender's moves, in arrival order"""

    @property
    def next_move_id(self) -> int:
        """The id :meth:`send` gives the next move when none is passed."""
        return self._next_id

    @property
    def sender_id(self) -> str:
        """This sender's publisher id (hex), as the bridge names it in :attr:`MoveStatus.sender`."""
        return self._pub.gid.hex()

    def poll_status(self) -> list[MoveStatus]:
        """The statuses of this sender's moves that arrived since the last call (also appended to
        :attr:`statuses`)."""
        new = []
        while (sample := self._status_sub.try_recv()) is not None:
            try:
                status = MoveStatus.decode(sample.payload.to_bytes())
            except WireError:
                continue  # not a status of the contract: nothing a sender can act on
            if status.sender == self.sender_id:
                new.append(status)
        self.statuses.extend(new)
        return new

    @property
    def bridge_alive(self) -> bool:
        """Whether the axis's bridge holds its liveliness token now (as far as this session knows)."""
        while (token := self._bridge_tokens.try_recv()) is not None:
            self._bridge_up = token.kind == zenoh.SampleKind.PUT
            self._bridge_seen = self._bridge_seen or self._bridge_up
        return self._bridge_up

    def wait_status(
        self, move_id: int, states: Collection[MoveState], timeout_s: float, poll_s: float = 0.001
    ) -> MoveStatus | None:
        """The first status of move ``move_id`` in one of ``states`` (already received or arriving
        within ``timeout_s``), or None on time-out. A move's last word ends the wait too (rejected,
        dropped, stopped: check the returned state). Raises :class:`BridgeLostError` when the bridge,
        once seen, disappears while waiting: the move will never finish."""
        wanted = {*states, *TERMINAL_STATES}
        deadline = time.monotonic() + timeout_s
        seen = 0
        while True:
            for status in self.statuses[seen:]:
                if status.move_id == move_id and status.state in wanted:
                    return status
            seen = len(self.statuses)
            if time.monotonic() >= deadline:
                return None
            if not self.poll_status():
                if self._bridge_seen and not self.bridge_alive:
                    raise BridgeLostError(
                        f"the bridge of axis {self.keys.axis!r} disappeared ({self.keys.alive}) while move "
                        f"{move_id} was waiting to be {' or '.join(s.name.lower() for s in states)}"
                    )
                time.sleep(poll_s)

    def require_bridge(self, timeout_s: float = BRIDGE_TIMEOUT_S) -> None:
        """:meth:`wait_for_bridge`, or an :class:`AcquisitionError` saying how to start a bridge."""
        if not self.wait_for_bridge(timeout_s):
            raise AcquisitionError(
                f"no bridge for axis {self.keys.axis!r} answered within {timeout_s:g} s ({self.keys.alive}): "
                "start `axisflow bridge` first, with the same --axis and Zenoh flags"
            )

    def wait_for_bridge(self, timeout_s: float) -> bool:
        """True once the bridge is ready for this sender's moves; False after ``timeout_s``.

        Two facts make it ready. Its liveliness token is seen: the bridge declares the token last, after
        its move subscriber, so this session knows that subscriber too (declarations arrive in order).
        And a hello round trip to the publishers on the axis's event key has come back: the hello
        travels behind this sender's own declarations (its status subscriber, its token), so the bridge
        has read them — its statuses reach this sender, and its first move finds the token there
        (:mod:`.readiness`)."""
        deadline = time.monotonic() + timeout_s
        while not self.bridge_alive:
            if time.monotonic() >= deadline:
                return False
            time.sleep(0.01)
        try:
            say_hello(self._session, self.keys.event, max(deadline - time.monotonic(), 0.001))
        except AcquisitionError:
            return False
        return True

    def send(
        self,
        start_position_m: float,
        end_position_m: float,
        duration_s: float,
        law: str = "poly5",
        start_ns: int | None = None,
        move_id: int | None = None,
    ) -> MoveCommand:
        """Publish one move; ``start_ns`` None appends it after the moves already queued."""
        x0, x1, duration = float(start_position_m), float(end_position_m), float(duration_s)
        return self._publish(law, x0, x1, duration, None, start_ns, move_id)

    def send_trajectory(
        self, trajectory: SampledTrajectory, start_ns: int | None = None, move_id: int | None = None
    ) -> MoveCommand:
        """Publish a sampled move (law ``sampled``: the trajectory's knots); ``start_ns`` None appends
        it. The bridge validates it at every 1 kHz sample and knot, like any move."""
        t = trajectory
        return self._publish(SAMPLED_LAW, t.x0_m, t.x1_m, t.duration_s, Knots.of(t), start_ns, move_id)

    def _publish(
        self,
        law: str,
        x0_m: float,
        x1_m: float,
        duration_s: float,
        knots: Knots | None,
        start_ns: int | None,
        move_id: int | None,
    ) -> MoveCommand:
        if move_id is None:
            move_id = self._next_id
        self._next_id = move_id + 1
        start = APPEND if start_ns is None else start_ns
        cmd = MoveCommand(time.time_ns(), self.keys.axis, move_id, start, law, x0_m, x1_m, duration_s, knots)
        self._pub.put(cmd.encode(), cmd.stamp_ns)
        return cmd

    def stop(self, reason: str = "", reset_fault: bool = False) -> None:
        """Request a quick stop (:mod:`.quick_stop`): the bridge abandons the queue, brakes the running
        move to rest and holds. Its STOPPED status of move :data:`STOP_MOVE_ID` (this sender's) says
        where and how fast the axis stopped: ``wait_status(STOP_MOVE_ID, {MoveState.STOPPED}, …)``.
        ``reset_fault``: also reset the drive's fault; an ENABLED (or FAULT) status of move 0 follows."""
        if self._stop_pub is None:
            self._stop_pub = SequencedPublisher(
                self._session, self.keys.stop, QUICK_STOP_TYPE, Traffic.COMMAND, gid=self._pub.gid
            )
        request = QuickStop(time.time_ns(), self.keys.axis, reason, reset_fault)
        self._stop_pub.put(request.encode(), request.stamp_ns)

    def close(self) -> None:
        if self._stop_pub is not None:
            self._stop_pub.undeclare()
        self._token.undeclare()
        self._bridge_tokens.undeclare()
        self._status_sub.undeclare()
        self._pub.undeclare()

    def __enter__(self) -> MoveSender:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()
