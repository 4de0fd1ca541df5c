"""The axis's health as ROS 2 diagnostics: two statuses, each with a level, as ROS 2 drivers report.

``<node>: drive`` — is the axis there and following setpoints?

=======  ====================================================================================
level    when
=======  ====================================================================================
STALE    no bridge holds the axis's liveliness token (``<prefix>/<axis>/alive``), or the bridge
         is there but no sample arrived for :data:`SAMPLES_STALE_S` (nothing is known)
ERROR    the drive's last event stops it: FAULT, COMM_LOST or DRIVE_STOPPED (``error_code``,
         ``error_register``, ``statusword`` among the values), until an ENABLED
WARN     the drive's last event is a WARNING (moves go on), until its next event
OK       otherwise (after ENABLED, or no drive event yet)
=======  ====================================================================================

``<node>: motion`` — what happened to the last move or trajectory (any sender's moves on the axis):
OK for accepted, started, completed and the rest after a quick stop; WARN for a move rejected,
dropped or stopped while running, and for a trajectory this node refused (with the reason).

The states come from the bridge's typed statuses (:class:`~axisflow.acquisition.wire.move_status.MoveStatus`),
never from their text; the text is the status's message. Plain data here: the ROS 2 message is made
by :mod:`.ros_messages`.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from enum import IntEnum

from ...acquisition.wire.move_status import DRIVE_EVENTS, MoveState, MoveStatus
from ...acquisition.wire.quick_stop import STOP_MOVE_ID

SAMPLES_STALE_S = 1.0
"""a bridge whose last sample is older than this (wall time) makes the drive status STALE [s]"""


class Level(IntEnum):
    """``diagnostic_msgs/msg/DiagnosticStatus`` levels."""

    OK = 0
    WARN = 1
    ERROR = 2
    STALE = 3


DRIVE_EVENT_LEVELS: dict[MoveState, Level] = {
    MoveState.FAULT: Level.ERROR,
    MoveState.COMM_LOST: Level.ERROR,
    MoveState.DRIVE_STOPPED: Level.ERROR,
    MoveState.WARNING: Level.WARN,
    MoveState.ENABLED: Level.OK,
}
MOVE_LEVELS: dict[MoveState, Level] = {
    MoveState.ACCEPTED: Level.OK,
    MoveState.STARTED: Level.OK,
    MoveState.COMPLETED: Level.OK,
    MoveState.REJECTED: Level.WARN,
    MoveState.DROPPED: Level.WARN,
    MoveState.STOPPED: Level.WARN,
}


@dataclass(frozen=True)
class HealthStatus:
    """One ``DiagnosticStatus``: name, level, message, hardware id and key–value pairs."""

    name: str
    level: Level
    message: str
    hardware_id: str
    values: tuple[tuple[str, str], ...] = ()


class AxisHealth:
    """The two statuses of one axis, kept from what the node sees (see the module docstring)."""

    def __init__(self, node_name: str, axis: str) -> None:
        self.node_name, self.axis = node_name, axis
        self._bridge_alive = False
        self._last_sample_s: float | None = None
        self._drive_event: MoveStatus | None = None
        self._motion = (Level.OK, "no move yet")
        self._last_move: MoveStatus | None = None
        self.refusals = 0
        """trajectories this node refused"""

    # ---- what the node sees ------------------------------------------------------------------------
    def bridge(self, alive: bool) -> bool:
        """The bridge's token is (not) held; True if that changed."""
        changed = alive != self._bridge_alive
        self._bridge_alive = alive
        return changed

    def sample_arrived(self, monotonic_s: float) -> None:
        self._last_sample_s = monotonic_s

    def on_status(self, status: MoveStatus, motion: tuple[Level, str] | None = None) -> None:
        """A status from the bridge's event key; ``motion``: the node's own line for it (a status of
        one of its trajectories' moves), instead of the status's level and text."""
        if status.state in DRIVE_EVENTS:
            self._drive_event = status
        elif status.move_id == STOP_MOVE_ID and status.state is MoveState.STOPPED:
            self._motion = (Level.OK, status.text)  # the quick stop's confirmation: at rest, holding
        else:
            self._last_move = status
            text = status.text or f"move {status.move_id} {status.state.name.lower()}"
            self._motion = motion or (MOVE_LEVELS[status.state], text)

    def on_motion(self, level: Level, message: str) -> None:
        """The node's own word on a trajectory (accepted, refused, done)."""
        self._motion = (level, message)

    def on_refusal(self, reason: str) -> None:
        self.refusals += 1
        self._motion = (Level.WARN, f"trajectory refused: {reason}")

    # ---- the statuses ------------------------------------------------------------------------------
    def drive_level(self, now_s: float | None = None) -> tuple[Level, str]:
        now_s = time.monotonic() if now_s is None else now_s
        if not self._bridge_alive:
            return Level.STALE, f"no bridge runs axis {self.axis!r}"
        event = self._drive_event
        if event is not None and DRIVE_EVENT_LEVELS[event.state] is Level.ERROR:
            return Level.ERROR, event.text
        if self._last_sample_s is None or now_s - self._last_sample_s > SAMPLES_STALE_S:
            return Level.STALE, f"the bridge of axis {self.axis!r} sent no sample for {SAMPLES_STALE_S:g} s"
        if event is not None and event.state is MoveState.WARNING:
            return Level.WARN, event.text
        return Level.OK, "the drive follows setpoints"

    def statuses(
        self, drive_values: tuple[tuple[str, str], ...] = (), now_s: float | None = None
    ) -> tuple[HealthStatus, HealthStatus]:
        """(drive, motion) now; ``drive_values``: more key–value pairs for the drive (the relay's counts)."""
        level, message = self.drive_level(now_s)
        event = self._drive_event
        values: list[tuple[str, str]] = [("bridge", "running" if self._bridge_alive else "absent")]
        if event is not None:
            values += [
                ("last drive event", event.state.name),
                ("error_code", f"0x{event.error_code:04X}"),
                ("error_register", f"0x{event.error_register:02X}"),
                ("statusword", f"0x{event.statusword:04X}"),
            ]
        drive = HealthStatus(f"{self.node_name}: drive", level, message, self.axis, (*values, *drive_values))
        motion_values: list[tuple[str, str]] = [("trajectories refused", str(self.refusals))]
        if self._last_move is not None:
            motion_values += [
                ("last move", str(self._last_move.move_id)),
                ("last move state", self._last_move.state.name),
            ]
        motion_level, motion_message = self._motion
        motion = HealthStatus(
            f"{self.node_name}: motion", motion_level, motion_message, self.axis, tuple(motion_values)
        )
        return drive, motion
