"""What the node asks of the axis, through one :class:`~axisflow.acquisition.bus.move_sender.MoveSender`:
trajectories (planned, sent as moves, followed), quick stops and fault resets.

**Trajectories are queued, not replaced.** A trajectory's moves are appended to the bridge's queue,
its first one starting where the axis will be: at the end of this node's moves still queued, or at
the axis's setpoint when none is. A trajectory received while another runs therefore runs after it
(a ROS 2 trajectory controller would replace it: call ``quick_stop`` first for that). Every move of
a trajectory is planned before the first is sent, so a refusal leaves the axis untouched.

**Followed by its statuses.** The bridge's statuses of this node's moves say how each trajectory
fares; :meth:`AxisCommands.on_status` turns them into one line for the motion diagnostics: moving to
point k, done, or failed with the bridge's reason (a rejection, a quick stop, a drive fault). A
failed trajectory's later moves fail too (each starts where the one before ends); their statuses
repeat the first reason.

One sender, one owner: the node calls every method from its executor's thread.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

from ...acquisition.bus.axis_state import AxisState
from ...acquisition.bus.move_sender import BRIDGE_TIMEOUT_S, MoveSender
from ...acquisition.wire.move_status import MoveState, MoveStatus
from ...acquisition.wire.quick_stop import STOP_MOVE_ID
from .axis_health import Level
from .errors import Ros2Error, TrajectoryRefusedError
from .trajectory_plan import PlannedMove, TrajectoryPlan, TrajectoryPlanner
from .trajectory_request import TrajectoryRequest

ANSWER_TIMEOUT_S = 10.0
"""how long a quick stop or a fault reset waits for the bridge's answer [s]"""
_FAILED = frozenset({MoveState.REJECTED, MoveState.DROPPED, MoveState.STOPPED})
_RESET_ANSWERS = frozenset({MoveState.ENABLED, MoveState.FAULT, MoveState.COMM_LOST})


@dataclass
class SentTrajectory:
    """A trajectory whose moves were sent: its plan, their move ids, how it fared."""

    number: int
    plan: TrajectoryPlan
    move_ids: tuple[int, ...]
    completed: int = 0
    """moves completed"""
    failure: str = ""
    """the first failure's reason (the bridge's text), empty while all goes well"""
    started_ns: int | None = None
    """drive time of its first move's start"""
    finished_ns: int | None = None
    """drive time of its arrival at the last way point"""
    moves: dict[int, PlannedMove] = field(default_factory=dict)
    """the planned move of each move id"""

    @property
    def done(self) -> bool:
        return self.completed == len(self.move_ids)


class AxisCommands:
    """Trajectories, quick stops and fault resets for one axis (see the module docstring)."""

    def __init__(self, sender: MoveSender, setpoint: AxisState, planner: TrajectoryPlanner) -> None:
        self.sender, self.setpoint, self.planner = sender, setpoint, planner
        self.trajectories: list[SentTrajectory] = []
        """every trajectory sent, in order"""
        self._pending: dict[int, SentTrajectory] = {}
        """move id → its trajectory, for the moves that have not ended"""
        self._queued_end_m: float | None = None
        """where this node's queued moves leave the axis (None: none queued)"""
        self._bridge_ready = False
        self._unread: list[MoveStatus] = []
        """statuses polled with an answer and after it: the next answer may be among them"""

    # ---- trajectories --------------------------------------------------------------------------------
    def submit(self, request: TrajectoryRequest) -> SentTrajectory:
        """Plan ``request`` from where the axis will be and send its moves; raises
        :class:`TrajectoryRefusedError` (nothing sent) naming why."""
        self._require_bridge()
        plan = self.planner.plan(request, self._start_position())
        number = len(self.trajectories) + 1
        ids: list[int] = []
        moves: dict[int, PlannedMove] = {}
        for move in plan.sent:
            start_ns = request.start_ns if not ids and request.start_ns else None
            cmd = self.sender.send(
                move.start_m, move.end_m, move.duration_s, self.planner.motion.law, start_ns
            )
            ids.append(cmd.move_id)
            moves[cmd.move_id] = move
        sent = SentTrajectory(number, plan, tuple(ids), moves=moves)
        self.trajectories.append(sent)
        for move_id in ids:
            self._pending[move_id] = sent
        if ids:
            self._queued_end_m = plan.end_position_m
        return sent

    def _require_bridge(self) -> None:
        if not self.sender.bridge_alive:
            self._bridge_ready = False
            raise TrajectoryRefusedError(
                f"no bridge runs axis {self.sender.keys.axis!r} ({self.sender.keys.alive}): start "
                "`axisflow bridge` with the same --axis and Zenoh flags"
            )
        if not self._bridge_ready:  # its first move must find this sender's token there
            if not self.sender.wait_for_bridge(BRIDGE_TIMEOUT_S):
                raise TrajectoryRefusedError(
                    f"the bridge of axis {self.sender.keys.axis!r} did not answer within "
                    f"{BRIDGE_TIMEOUT_S:g} s"
                )
            self._bridge_ready = True

    def _start_position(self) -> float:
        if self._pending and self._queued_end_m is not None:
            return self._queued_end_m
        sample = self.setpoint.latest()
        if sample is None:
            raise TrajectoryRefusedError(
                f"no setpoint of axis {self.sender.keys.axis!r} has arrived yet ({self.setpoint.key}): "
                "where the axis is, is not known"
            )
        return sample.position_m

    def bridge_lost(self) -> None:
        """The bridge's token went away: a bridge that comes back must see this sender again."""
        self._bridge_ready = False

    def on_status(self, status: MoveStatus) -> tuple[Level, str] | None:
        """The motion line for a status of one of this node's trajectory moves; None for any other."""
        sent = self._pending.get(status.move_id) if status.sender == self.sender.sender_id else None
        if sent is None:
            return None
        move = sent.moves[status.move_id]
        where = f"point {move.point} ({move.end_m:.6g} m)"
        if status.state in _FAILED:
            if not sent.failure:
                sent.failure = status.text or status.state.name.lower()
            self._end(status.move_id)
            return Level.WARN, f"trajectory {sent.number} failed before {where}: {sent.failure}"
        if sent.failure:
            return Level.WARN, f"trajectory {sent.number} failed: {sent.failure}"
        if status.state is MoveState.STARTED:
            if status.move_id == sent.move_ids[0]:
                sent.started_ns = status.stamp_ns
            return Level.OK, f"trajectory {sent.number}: moving to {where}"
        if status.state is MoveState.COMPLETED:
            sent.completed += 1
            self._end(status.move_id)
            if sent.done:
                sent.finished_ns = status.stamp_of(status.end_tick)
                line = f"trajectory {sent.number} done: at {where}"
                if sent.started_ns is not None:
                    line += f", {(sent.finished_ns - sent.started_ns) * 1e-9:.3f} s after its start"
                return Level.OK, line
            return Level.OK, f"trajectory {sent.number}: at {where}"
        return Level.OK, f"trajectory {sent.number}: {status.text}"  # accepted

    def _end(self, move_id: int) -> None:
        self._pending.pop(move_id, None)
        if not self._pending:
            self._queued_end_m = None

    def drain(self) -> None:
        """Empty the sender's own status queue (the node follows statuses through its event watch;
        an unread queue would fill and hold back the bridge's statuses)."""
        self.sender.poll_status()
        self.sender.statuses.clear()

    # ---- quick stop and fault reset ------------------------------------------------------------------
    def quick_stop(
        self, reason: str, poll: Callable[[], list[MoveStatus]], timeout_s: float = ANSWER_TIMEOUT_S
    ) -> MoveStatus:
        """Stop the axis (:meth:`MoveSender.stop`) and return the bridge's STOPPED status of move 0 for
        this sender (where and when the axis came to rest); ``poll`` gives the statuses that arrive."""
        self._require_live_bridge()
        poll()  # what arrived before the request is not its answer
        self._unread = []
        self.sender.stop(reason)
        return self._answer(poll, {MoveState.STOPPED}, "confirm the quick stop", timeout_s)

    def reset_fault(
        self, poll: Callable[[], list[MoveStatus]], timeout_s: float = ANSWER_TIMEOUT_S
    ) -> MoveStatus:
        """A quick stop with the drive's fault reset; the bridge's answer: ENABLED (the drive follows
        setpoints again), or FAULT / COMM_LOST (the reset did not clear it)."""
        self._require_live_bridge()
        poll()
        self._unread = []
        self.sender.stop("ROS 2 reset_fault", reset_fault=True)
        self._answer(poll, {MoveState.STOPPED}, "confirm the quick stop of the fault reset", timeout_s)
        return self._answer(poll, _RESET_ANSWERS, "answer the fault reset", timeout_s)

    def _require_live_bridge(self) -> None:
        if not self.sender.bridge_alive:
            raise Ros2Error(f"no bridge runs axis {self.sender.keys.axis!r} ({self.sender.keys.alive})")

    def _answer(
        self,
        poll: Callable[[], list[MoveStatus]],
        states: frozenset[MoveState] | set[MoveState],
        what: str,
        timeout_s: float,
    ) -> MoveStatus:
        deadline = time.monotonic() + timeout_s
        mine = self.sender.sender_id
        unread, self._unread = self._unread, []
        while time.monotonic() < deadline:
            batch = unread + poll()
            unread = []
            for k, status in enumerate(batch):
                if status.move_id == STOP_MOVE_ID and status.sender == mine and status.state in states:
                    self._unread = batch[k + 1 :]  # a reset's answer may come in one poll with its stop's
                    return status
            time.sleep(0.002)
        raise Ros2Error(f"the bridge of axis {self.sender.keys.axis!r} did not {what} within {timeout_s:g} s")
