"""Running the identification excitation on an axis through its bridge, like any planner would.

The run: find the bridge (its liveliness token), read where the axis holds (the latest setpoint: the
position a new move must start from), move to the excitation's centre with a minimum-time poly5 move
(the exact planner), send every burst of the :class:`~axisflow.identification.excitation.ExcitationPlan`
as a sampled move (appended: no idle tick between them; the bridge validates each at every 1 kHz
sample) and wait, on the bridge's typed move status, until the last one has completed. A rejected,
dropped or stopped move, or a bridge that disappears, ends the run with the reason. Record the run
with ``axisflow record`` and refit with ``axisflow identify``.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import zenoh

from ..acquisition import AxisKeys, MoveCommand, MoveRejectedError, MoveState, MoveStatus
from ..acquisition.bus.axis_state import AxisState, DriveWatch
from ..acquisition.bus.move_sender import BRIDGE_TIMEOUT_S, MoveSender
from ..identification.excitation import ExcitationPlan
from ..identification.signals import TimeWindow
from ..model import AxisflowError, AxisParams, polynomial_law
from ..planner import Case, MoveProblem, solve_exact

_SLACK_S = 60.0
DRIVE_INFO_WAIT_S = 2.0
"""how long the run waits at its end for the bridge's DriveInfo, if none has come yet [s]"""
_SLOWEST_SPEED = 0.05
_STOP_SLICE_S = 0.1
"""how often waiting for a move looks at the stop event [s]"""
"""the waits assume the bridge runs at least this fraction of real time"""


@dataclass
class ExcitationReport:
    """What the run did: its moves in order (repositioning first, if any) and their last statuses."""

    axis: str
    center_m: float
    moves: list[MoveCommand] = field(default_factory=list)
    statuses: list[MoveStatus] = field(default_factory=list)
    wall_time_s: float = 0.0
    drive: str | None = None
    """what drove the axis, as its bridge said (the simulated axis's plant profile); None: it did not"""

    @property
    def drive_time_s(self) -> float:
        return sum(m.duration_s for m in self.moves)

    def to_dict(self) -> dict[str, object]:
        return {
            "axis": self.axis,
            "center_m": self.center_m,
            "moves": len(self.moves),
            "drive_time_s": self.drive_time_s,
            "wall_time_s": self.wall_time_s,
            "drive": self.drive,
            "first_tick": self.statuses[0].start_tick if self.statuses else None,
            "last_tick": self.statuses[-1].end_tick if self.statuses else None,
        }

    def window(self, margin_s: float = 0.2) -> TimeWindow:
        """The drive time of the run's moves, ``margin_s`` wider on each side: the part of a recording
        to refit from (a recorder that joined a running bridge may miss samples before it)."""
        if not self.statuses:
            return TimeWindow()
        first, last = self.statuses[0], self.statuses[-1]
        origin = first.stamp_of(first.start_tick)
        end_s = (last.stamp_of(last.end_tick) - origin) * 1e-9
        return TimeWindow(-margin_s, end_s + margin_s, origin)

    def format(self) -> str:
        drive = self.drive or "a drive that did not say what it is"
        return (
            f"excitation on axis {self.axis} ({drive}): {len(self.moves)} moves, {self.drive_time_s:.1f} s "
            f"of drive time in {self.wall_time_s:.1f} s, around {self.center_m:.3f} m"
        )


def run_excitation(
    session: zenoh.Session,
    keys: AxisKeys,
    params: AxisParams,
    plan: ExcitationPlan,
    progress: Callable[[str], None] | None = None,
    stop: threading.Event | None = None,
) -> ExcitationReport:
    """Run ``plan`` on the axis of ``keys`` (see the module docstring); ``progress`` gets one line per
    finished move. ``stop`` set (SIGINT/SIGTERM) ends the wait with a :class:`KeyboardInterrupt`;
    closing the sender then drops the moves that had not started."""
    say = progress or (lambda _line: None)
    report = ExcitationReport(keys.axis, plan.center_m)
    t0 = time.monotonic()
    with (
        MoveSender(session, keys) as sender,
        AxisState(session, keys, "setpoint", follow=False) as setpoint,
        DriveWatch(session, keys) as drive,
    ):
        sender.require_bridge(BRIDGE_TIMEOUT_S)
        x_now = setpoint.wait(BRIDGE_TIMEOUT_S).position_m
        if abs(x_now - plan.center_m) > 1e-9:
            problem = MoveProblem(x_now, plan.center_m, polynomial_law("poly5"), Case.MIN_TIME)
            duration = solve_exact(problem, params).duration_s
            report.moves.append(sender.send(x_now, plan.center_m, duration, law="poly5"))
        report.moves += [sender.send_trajectory(traj) for traj in plan.trajectories()]
        offset = len(report.moves) - len(plan.bursts)
        for k, cmd in enumerate(report.moves, start=1):
            # queued moves wait for the ones before them: the time-out covers all of those
            wait_s = _SLACK_S + sum(m.duration_s for m in report.moves[:k]) / _SLOWEST_SPEED
            status = _wait_completed(sender, cmd.move_id, wait_s, stop)
            if status is None:
                raise AxisflowError(
                    f"move {cmd.move_id} of the excitation did not complete within {wait_s:.0f} s"
                )
            if status.state is not MoveState.COMPLETED:
                raise MoveRejectedError(f"the excitation stopped: {status.text}")
            report.statuses.append(status)
            what = "move to the centre" if k <= offset else f"burst {k - offset}/{len(plan.bursts)}"
            say(f"  {what} done: ticks {status.start_tick}..{status.end_tick}")
        info = drive.wait(DRIVE_INFO_WAIT_S)  # the bridge sends it once a second: long since here
        report.drive = info.describe() if info is not None else None
    report.wall_time_s = time.monotonic() - t0
    return report


def _wait_completed(
    sender: MoveSender, move_id: int, timeout_s: float, stop: threading.Event | None
) -> MoveStatus | None:
    """:meth:`MoveSender.wait_status` for COMPLETED, in slices that look at ``stop``."""
    deadline = time.monotonic() + timeout_s
    while True:
        if stop is not None and stop.is_set():
            raise KeyboardInterrupt
        status = sender.wait_status(move_id, {MoveState.COMPLETED}, min(_STOP_SLICE_S, timeout_s))
        if status is not None or time.monotonic() >= deadline:
            return status
