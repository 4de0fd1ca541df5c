"""Fault 3: the planner SIGKILLed with moves queued → its queued moves dropped, the axis at rest within
[0, L] (the test, with a restart, is tests/nodes/test_planner_restart.py)."""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...acquisition import MoveState, open_session
from ...deploy.processes import Launcher, wait_until
from ...model import default_params
from .outcome import FaultResult, Outcome
from .rig import KEYS, Rig, RunEnd, StatusWatch, require_bridge, stop_rig


@dataclass(frozen=True)
class PlannerKillResult(FaultResult):
    counts: dict[str, int]
    """the bridge's statuses about the planner's moves, by state"""
    drop_after_s: float
    """from the kill to the bridge's first DROPPED status [s]"""
    rest_setpoint: tuple[float, float]
    """the last setpoint (x [m], v [m/s])"""
    last_completed_end_m: float
    """the end point of the last move that completed"""
    rest_speed_m_s: float
    """the largest measured speed over the last 0.3 s"""
    end: RunEnd
    L: float

    @property
    def passed(self) -> bool:
        c = self.counts
        x, v = self.rest_setpoint
        return (
            c["accepted"] >= 2
            and c["dropped"] == c["accepted"] - c["started"] >= 1
            and c["completed"] == c["started"]
            and c["rejected"] == 0
            and x == self.last_completed_end_m
            and v == 0.0
            and 0.0 <= x <= self.L
            and self.rest_speed_m_s < 0.005
            and self.end.telemetry_intact
        )

    def outcome(self) -> Outcome:
        c = self.counts
        return Outcome(
            "planner SIGKILL with moves queued",
            self.passed,
            f"{c['accepted']} accepted, {c['started']} started and completed, {c['dropped']} dropped "
            f"{self.drop_after_s * 1e3:.0f} ms after the kill; at rest at {self.rest_setpoint[0]:.4f} m (the "
            f"last completed move's end), measured speed ≤ {self.rest_speed_m_s * 1e3:.2f} mm/s; telemetry "
            "complete (test: tests/nodes/test_planner_restart.py, which also restarts the planner)",
            "axisflow bench faults --only planner_kill",
            {
                "counts": self.counts,
                "drop_after_s": self.drop_after_s,
                "rest_setpoint": self.rest_setpoint,
                "last_completed_end_m": self.last_completed_end_m,
                "rest_speed_m_s": self.rest_speed_m_s,
            },
        )


def planner_kill(work: Path) -> PlannerKillResult:
    """Fault 3: ``axisflow planner`` (lookahead 2) driving a bridge at 1× real time, SIGKILLed once it
    has three moves accepted; the bridge drops the queued ones and the running one ends at rest."""
    from axisflow.acquisition import MoveCommand, read_messages

    points = work / "points.txt"
    points.write_text("0.1\n0.7\n0.2\n0.6\n0.3\n0.5\n")
    names = ("accepted", "started", "completed", "dropped", "rejected")
    with Launcher(work, cwd=work) as launcher:
        rig = Rig(launcher, "planner-kill")
        recorder = rig.start_recorder()
        bridge = rig.start_bridge()
        with open_session(rig.options()) as session:
            require_bridge(session)
            watch = StatusWatch(session)
            args = ("--waypoints", str(points), "--case", "min-time-energy", "--lookahead", "2")
            planner = launcher.start("planner", "planner", *args, "--connect", rig.recorder_endpoint)
            if not watch.wait(MoveState.ACCEPTED, 3, 60.0):
                stderr = launcher.wait(planner, 1).stderr
                raise RuntimeError(f"the planner's moves were not accepted: {stderr}")
            planner.kill()
            killed = time.monotonic()
            launcher.wait(planner)
            watch.wait(MoveState.DROPPED, 1, 30.0)
            drop_after_s = time.monotonic() - killed
            wait_until(lambda: watch.count(MoveState.COMPLETED) == watch.count(MoveState.STARTED), 30.0)
            watch.settled()  # and nothing more came
            counts = {name: watch.count(MoveState[name.upper()]) for name in names}
            completed = [s.move_id for s in watch.statuses if s.state is MoveState.COMPLETED]
            watch.close()
        end = stop_rig(rig, bridge, recorder)
    moves = {
        m.move_id: m
        for m in (MoveCommand.decode(r.data) for r in read_messages(rig.recording, "/" + KEYS.trajectory))
    }
    setpoint, state = end.setpoint, end.state
    return PlannerKillResult(
        counts=counts,
        drop_after_s=drop_after_s,
        rest_setpoint=(float(setpoint.position_m[-1]), float(setpoint.velocity_m_s[-1])),
        last_completed_end_m=moves[completed[-1]].end_position_m if completed else float("nan"),
        rest_speed_m_s=float(np.abs(state.velocity_m_s[-300:]).max()),
        end=end,
        L=default_params().L,
    )
