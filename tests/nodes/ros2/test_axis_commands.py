"""Quick stops and fault resets through a real :class:`MoveSender` on loopback Zenoh (a second session
holds the bridge's token): the node finds the bridge's answers among the statuses it polls, however
they are batched."""

from __future__ import annotations

import pytest
from axisflow.acquisition import AxisKeys, MoveSender, MoveState, MoveStatus, ZenohOptions, open_session
from axisflow.acquisition.bus.axis_state import AxisState
from axisflow.acquisition.wire.quick_stop import STOP_MOVE_ID
from axisflow.model import default_params
from axisflow.planner import make_backend

from axisflow.deploy.processes import wait_until
from axisflow.nodes.ros2.axis_commands import AxisCommands
from axisflow.nodes.ros2.errors import Ros2Error
from axisflow.nodes.ros2.settings import MotionSettings
from axisflow.nodes.ros2.trajectory_plan import TrajectoryPlanner

KEYS = AxisKeys("a0")


def answer(state: MoveState, sender: str, text: str = "") -> MoveStatus:
    """A status of move 0 for ``sender``, as the bridge answers a quick stop or a fault reset."""
    return MoveStatus(1_700_000_000_000_000_000, "a0", state, STOP_MOVE_ID, 10, sender=sender, text=text)


@pytest.fixture
def commands(port):
    with (
        open_session(ZenohOptions.loopback(listen_port=port)) as bridge_side,
        open_session(ZenohOptions.loopback(connect_port=port)) as session,
        MoveSender(session, KEYS) as sender,
        AxisState(session, KEYS, "setpoint") as setpoint,
    ):
        token = bridge_side.liveliness().declare_token(KEYS.alive)
        assert wait_until(lambda: sender.bridge_alive, 10), "the bridge's token did not arrive"
        planner = TrajectoryPlanner(make_backend("exact"), default_params(), MotionSettings())
        yield AxisCommands(sender, setpoint, planner)
        token.undeclare()


def polls(*batches: list[MoveStatus]):
    """A ``poll`` that gives ``batches`` one per call (the first: what arrived before the request),
    then nothing."""
    left = list(batches)
    return lambda: left.pop(0) if left else []


@pytest.mark.parametrize("together", [True, False], ids=["in one poll", "in two polls"])
def test_a_fault_reset_is_answered_whether_its_answer_comes_with_its_stop_or_after(commands, together):
    mine = commands.sender.sender_id
    stopped = answer(MoveState.STOPPED, mine, "quick stop: the drive follows no setpoints; it stops")
    enabled = answer(MoveState.ENABLED, mine, "fault reset; operation enabled")
    batches = [[stopped, enabled]] if together else [[stopped], [enabled]]
    assert commands.reset_fault(polls([], *batches), timeout_s=2.0) == enabled


def test_answers_to_others_and_from_before_the_request_are_not_the_answer(commands):
    mine = commands.sender.sender_id
    before = answer(MoveState.ENABLED, mine, "an answer to an earlier reset")
    theirs = answer(MoveState.ENABLED, "0123456789abcdef", "another sender's reset")
    stopped = answer(MoveState.STOPPED, mine)
    with pytest.raises(Ros2Error, match=r"did not answer the fault reset within 0\.2 s"):
        commands.reset_fault(polls([before], [stopped, theirs]), timeout_s=0.2)
