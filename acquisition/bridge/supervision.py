"""What stops a bridge's axis: quick stops, and the drive's own faults.

A quick stop (``<prefix>/<axis>/stop``) drops the queue and brakes the running move to rest within the
torque limit (:meth:`~.move_queue.MoveQueue.quick_stop`); with ``reset_fault`` it also asks the drive to
leave a fault. A drive that can fault (:mod:`axisflow.acquisition.drives.canopen`) reports events
(:meth:`Drive.events`); each becomes a status of move 0 with the drive's codes. When the drive stops
following setpoints (a fault, comm loss, its own stop) the axis is stopped — the running move STOPPED,
the queue DROPPED — and moves are refused (:meth:`Supervision.refusal`) until a quick stop with
``reset_fault`` (``axisflow stop --reset-fault``) has brought the drive back (ENABLED).
"""

from __future__ import annotations

import logging
from collections.abc import Callable

from ...model import AxisParams, stop_profile
from ..drives.drive import STOPPING_EVENTS, Drive, DriveEvent, DriveEventKind
from ..errors import WireError
from ..wire.move_status import MoveState
from ..wire.quick_stop import QuickStop
from .move_queue import MoveQueue, QueuedMove
from .report import BridgeReport
from .statuses import StatusOutbox

log = logging.getLogger("axisflow.acquisition.bridge.bridge")  # the bridge's log

_EVENT_STATES = {
    DriveEventKind.FAULT: MoveState.FAULT,
    DriveEventKind.COMM_LOST: MoveState.COMM_LOST,
    DriveEventKind.DRIVE_STOPPED: MoveState.DRIVE_STOPPED,
    DriveEventKind.WARNING: MoveState.WARNING,
    DriveEventKind.ENABLED: MoveState.ENABLED,
}


class Supervision:
    """The stops of one bridge's axis: its quick stops and its drive's faults. ``reject_pending(reason,
    tick)`` rejects the moves admitted but not queued yet."""

    def __init__(
        self,
        drive: Drive,
        params: AxisParams,
        queue: MoveQueue,
        reject_pending: Callable[[str, int], None],
        outbox: StatusOutbox,
        report: BridgeReport,
    ) -> None:
        self.drive = drive
        self.params = params
        self.queue = queue
        self.reject_pending = reject_pending
        """rejects the moves not queued yet, with a reason, at a tick (``MoveAdmission.reject_pending``)"""
        self.outbox = outbox
        self.report = report
        self.drive_down: str | None = None
        """why the drive follows no setpoints (None: it follows); moves are refused meanwhile"""
        self._reset_sender = ""
        """the hex id of whoever asked for the running fault reset (its answer carries it)"""

    def refusal(self) -> str | None:
        """Why moves are refused now (None: they are not)."""
        if self.drive_down is None:
            return None
        return f"the drive follows no setpoints ({self.drive_down}): reset it (axisflow stop --reset-fault)"

    # ---- quick stops ------------------------------------------------------------------------------------
    def quick_stop(self, payload: bytes, sender: bytes, tick: int) -> None:
        """A quick stop request (its payload, and the sender's id from its attachment), answered with
        statuses (see quick_stop.py)."""
        try:
            request = QuickStop.decode(payload)
            reason, reset = request.reason, request.reset_fault
        except WireError as exc:
            reason, reset = f"(undecodable request: {exc})", False
        self.report.quick_stops += 1
        log.warning("quick stop at tick %d: %s", tick, reason or "no reason given")
        self.reject_pending("a quick stop was requested before it was queued", tick)
        if self.drive_down is not None:
            why = f"quick stop: the drive follows no setpoints ({self.drive_down}); it stops on its own"
            self.outbox.axis_status(MoveState.STOPPED, tick, sender.hex(), why)
            if reset:
                self._reset_fault(sender, tick)
            return
        outcome = self.queue.quick_stop(tick, sender)
        self.outbox.dropped(outcome.dropped, tick, "quick stop")
        if outcome.interrupted is not None:
            q = outcome.interrupted
            self.outbox.move(
                MoveState.STOPPED,
                q,
                tick,
                f"stopped move {q.command.move_id} at {outcome.speed_m_s:+.4g} m/s: quick stop",
            )
        if outcome.braking is None:
            ends = outcome.kept.end_tick if outcome.kept is not None else tick
            text = (
                f"quick stop: move {outcome.kept.command.move_id} reaches rest sooner on its own course "
                f"(at tick {ends}, {outcome.kept.move.x1_m:.6g} m)"
                if outcome.kept is not None
                else "quick stop: the axis was at rest"
            )
            self.outbox.stopped_in_place(tick, ends, sender.hex(), text)
        if reset:
            self._reset_fault(sender, tick)

    def stopped(self, braking: QueuedMove, tick: int) -> None:
        """The braking profile of a quick stop has brought the axis to rest."""
        profile = braking.stop
        assert profile is not None
        fastest = stop_profile(braking.move.x0_m, float(braking.move.sample(0.0).velocity_m_s), self.params)
        self.outbox.move(
            MoveState.STOPPED,
            braking,
            tick,
            f"quick stop: at rest at {braking.move.x1_m:.6g} m after {profile.distance_m * 1e3:.2f} mm and "
            f"{profile.time_s * 1e3:.1f} ms (the axis's physical minimum with the nominal parameters: "
            f"{fastest.distance_m * 1e3:.2f} mm, {fastest.time_s * 1e3:.1f} ms)",
        )

    # ---- the drive's events -----------------------------------------------------------------------------
    def take_drive_events(self, position_m: float, tick: int) -> None:
        """The drive's events since the last tick, as statuses of move 0; a stopping one stops the axis
        (the queue abandoned where the drive measured it), an enabled one lets moves in again."""
        for event in self.drive.events():
            sender = ""
            if event.kind in STOPPING_EVENTS:
                self._drive_stopped(event, position_m, tick)
            elif event.kind is DriveEventKind.ENABLED:
                self.queue.abandon(tick, position_m)
                self.drive_down = None
                sender, self._reset_sender = self._reset_sender, ""
                log.warning("%s", event.text)
            else:
                log.warning("%s", event.text)
            if event.kind is DriveEventKind.FAULT and self._reset_sender:
                sender, self._reset_sender = self._reset_sender, ""  # the answer to the reset: it failed
            self.outbox.axis_status(_EVENT_STATES[event.kind], tick, sender, event.text, event)

    def _drive_stopped(self, event: DriveEvent, position_m: float, tick: int) -> None:
        first = self.drive_down is None
        self.drive_down = event.text
        if not first:
            return
        self.report.drive_faults += 1
        log.error("%s: the axis is stopped, moves are refused until the fault is reset", event.text)
        refusal = self.refusal()
        assert refusal is not None
        self.reject_pending(refusal, tick)
        running, dropped = self.queue.abandon(tick, position_m)
        if running is not None:
            self.outbox.move(
                MoveState.STOPPED, running, tick, f"stopped move {running.command.move_id}: {event.text}"
            )
        self.outbox.dropped(dropped, tick, event.text)

    def _reset_fault(self, sender: bytes, tick: int) -> None:
        """A quick stop asked for a fault reset: start it, or answer at once that nothing needs it."""
        if self.drive_down is None:
            self.outbox.axis_status(
                MoveState.ENABLED, tick, sender.hex(), "no fault to reset; the drive follows"
            )
            return
        self._reset_sender = sender.hex()
        log.warning("fault reset requested at tick %d", tick)
        self.drive.reset_fault()
