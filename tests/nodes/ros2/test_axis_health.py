"""The axis's health as diagnostic levels: every state of the wire contract has a level, and the drive
and motion statuses follow the bridge's typed statuses (no text parsed)."""

from __future__ import annotations

import pytest
from axisflow.acquisition.wire.move_status import DRIVE_EVENTS, MoveState, MoveStatus

from axisflow.nodes.ros2.axis_health import (
    DRIVE_EVENT_LEVELS,
    MOVE_LEVELS,
    SAMPLES_STALE_S,
    AxisHealth,
    Level,
)


def status(state: MoveState, move_id: int = 0, text: str = "", **codes) -> MoveStatus:
    return MoveStatus(1_700_000_000_000_000_000, "a0", state, move_id, 10, text=text, **codes)


def test_every_state_has_one_level():
    assert set(DRIVE_EVENT_LEVELS) == DRIVE_EVENTS
    assert set(MOVE_LEVELS) == set(MoveState) - DRIVE_EVENTS


def running(now: float = 100.0) -> AxisHealth:
    health = AxisHealth("axisflow_a0", "a0")
    health.bridge(True)
    health.sample_arrived(now)
    return health


@pytest.mark.parametrize(
    ("events", "level"),
    [
        ((), Level.OK),
        ((MoveState.FAULT,), Level.ERROR),
        ((MoveState.COMM_LOST,), Level.ERROR),
        ((MoveState.DRIVE_STOPPED,), Level.ERROR),
        ((MoveState.WARNING,), Level.WARN),
        ((MoveState.FAULT, MoveState.ENABLED), Level.OK),
        ((MoveState.WARNING, MoveState.FAULT), Level.ERROR),
    ],
)
def test_the_drive_level_is_its_last_event(events, level):
    health = running()
    for state in events:
        health.on_status(status(state, text=state.name.lower(), error_code=0x4310))
    drive, _motion = health.statuses(now_s=100.5)
    assert drive.level is level and drive.hardware_id == "a0" and drive.name == "axisflow_a0: drive"
    if events:
        assert drive.message == events[-1].name.lower() or level is Level.OK
        assert ("error_code", "0x4310") in drive.values


def test_no_bridge_or_no_sample_is_stale_a_fault_outranks_late_samples():
    health = AxisHealth("axisflow_a0", "a0")
    assert health.drive_level(0.0)[0] is Level.STALE  # no bridge yet
    health.bridge(True)
    assert health.drive_level(0.0) == (
        Level.STALE,
        f"the bridge of axis 'a0' sent no sample for {SAMPLES_STALE_S:g} s",
    )
    health.sample_arrived(10.0)
    assert health.drive_level(10.0 + SAMPLES_STALE_S / 2)[0] is Level.OK
    assert health.drive_level(10.0 + 2 * SAMPLES_STALE_S)[0] is Level.STALE
    health.on_status(status(MoveState.COMM_LOST, text="no heartbeat"))
    assert health.drive_level(10.0 + 2 * SAMPLES_STALE_S) == (Level.ERROR, "no heartbeat")
    health.bridge(False)
    assert health.drive_level(10.0)[0] is Level.STALE


def test_the_motion_status_follows_moves_and_the_nodes_own_words():
    health = running()
    health.on_status(status(MoveState.REJECTED, 4, "rejected move 4: jumps"))
    assert health.statuses(now_s=100.0)[1].level is Level.WARN
    health.on_status(
        status(MoveState.STARTED, 5, "started move 5"), (Level.OK, "trajectory 2: moving to point 0")
    )
    motion = health.statuses(now_s=100.0)[1]
    assert (motion.level, motion.message) == (Level.OK, "trajectory 2: moving to point 0")
    assert ("last move", "5") in motion.values and ("last move state", "STARTED") in motion.values
    health.on_status(status(MoveState.STOPPED, 0, "quick stop: at rest at 0.3 m"))  # the stop confirmed
    assert health.statuses(now_s=100.0)[1].level is Level.OK
    health.on_refusal("point 0 asks to arrive 0.1 s after the start")
    motion = health.statuses(now_s=100.0)[1]
    assert motion.level is Level.WARN and motion.message.startswith("trajectory refused: point 0")
    assert ("trajectories refused", "1") in motion.values
