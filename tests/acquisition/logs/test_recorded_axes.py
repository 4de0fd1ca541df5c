"""The axes of a recording, and choosing one by name (identify, table2, view of a cell's recording)."""

from __future__ import annotations

import pytest
from axisflow.acquisition import AxisSample
from axisflow.acquisition.errors import AxisNotRecordedError
from axisflow.acquisition.logs.mcap_writer import Ros2McapWriter
from axisflow.acquisition.logs.recorded_axes import (
    axis_label,
    choose_axis,
    choose_axis_of_logs,
    recorded_axes,
)
from axisflow.acquisition.logs.synthetic_log import SyntheticLogSpec
from axisflow.acquisition.wire.messages import JOINT_STATE_TYPE, MOVE_TYPE
from axisflow.acquisition.wire.move_status import MOVE_STATUS_TYPE

from .cell_log import write_cell_log

T0_NS = 1_700_000_000_000_000_000


@pytest.fixture(scope="module")
def cell(tmp_path_factory):
    """A cell's recording: axes a0, a1, a2 (state and setpoint, 0.5 s each)."""
    path = tmp_path_factory.mktemp("cell") / "cell.mcap"
    return write_cell_log(path, [SyntheticLogSpec(duration_s=0.5, axis=f"a{k}", seed=k) for k in range(3)])


def _log(path, topics: dict[str, str]):
    """A small log with one message on each topic (JointState payloads for JointState topics)."""
    writer = Ros2McapWriter(path)
    for topic, type_name in topics.items():
        channel = writer.channel_for(topic, type_name)
        payload = AxisSample(T0_NS, "x", 0.4, 0.0, 12.0, 80.0, 0.0, 0.05).encode()
        writer.add(channel, T0_NS, T0_NS, 1, payload)
    writer.finish()
    return path


def test_the_axes_of_a_cell_recording_are_found_with_their_topics(cell):
    axes = recorded_axes(cell)
    assert [a.label for a in axes] == ["a0", "a1", "a2"]
    assert axes[1].state == "/axisflow/a1/state" and axes[1].setpoint == "/axisflow/a1/setpoint"
    assert (axes[1].event, axes[1].plan) == (None, None)


def test_an_axis_is_chosen_by_name_and_a_missing_one_names_what_the_file_holds(cell):
    assert choose_axis(cell, "a2").state == "/axisflow/a2/state"
    assert choose_axis(cell, "a2", "axisflow").label == "a2"
    with pytest.raises(
        AxisNotRecordedError, match=r"cell.mcap holds 3 axes \(a0, a1, a2\): choose one with --axis"
    ):
        choose_axis(cell, None)
    with pytest.raises(
        AxisNotRecordedError, match=r"--axis a7: .*cell.mcap holds no such axis .* 3 axes \(a0, a1, a2\)"
    ):
        choose_axis(cell, "a7")
    with pytest.raises(AxisNotRecordedError, match=r"--axis plant/a1: .* 3 axes \(a0, a1, a2\)"):
        choose_axis(cell, "a1", "plant")


def test_a_single_axis_recording_needs_no_name(tmp_path):
    path = write_cell_log(tmp_path / "one.mcap", [SyntheticLogSpec(duration_s=0.2, axis="x")])
    assert choose_axis(path, None).label == "x"
    with pytest.raises(AxisNotRecordedError, match=r"--axis a0: .* one axis \(x\)"):
        choose_axis(path, "a0")


def test_axes_need_a_joint_state_topic_and_records_of_the_right_type(tmp_path):
    path = _log(
        tmp_path / "mixed.mcap",
        {
            "/axisflow/a0/state": JOINT_STATE_TYPE,
            "/axisflow/a0/event": MOVE_STATUS_TYPE,
            "/axisflow/a1/event": MOVE_STATUS_TYPE,  # no samples: not an axis
            "/axisflow/a2/state": MOVE_TYPE,  # the wrong type: not an axis
            "/axisflow/a3/setpoint": JOINT_STATE_TYPE,  # setpoints only: an axis without state
        },
    )
    axes = recorded_axes(path)
    assert [(a.label, a.state, a.event) for a in axes] == [
        ("a0", "/axisflow/a0/state", "/axisflow/a0/event"),
        ("a3", None, None),
    ]
    assert choose_axis(path, None).label == "a0"  # the only one with a state topic
    assert choose_axis(path, None, what="setpoint").label == "a3"
    with pytest.raises(AxisNotRecordedError, match="no axis with a plan topic"):
        choose_axis(path, None, what="plan")


def test_the_same_axis_under_two_prefixes_needs_the_prefix(tmp_path):
    path = _log(
        tmp_path / "two.mcap",
        {"/axisflow/a0/state": JOINT_STATE_TYPE, "/plant/cell1/a0/state": JOINT_STATE_TYPE},
    )
    assert [a.label for a in recorded_axes(path)] == ["a0", "plant/cell1/a0"]
    assert axis_label("plant/cell1", "a0") == "plant/cell1/a0"
    with pytest.raises(AxisNotRecordedError, match="under several prefixes"):
        choose_axis(path, "a0")
    assert choose_axis(path, "a0", "plant/cell1").state == "/plant/cell1/a0/state"
    assert choose_axis(path, "plant/cell1/a0").state == "/plant/cell1/a0/state"  # by label


def test_several_logs_must_hold_the_axis_and_agree_on_it(cell, tmp_path):
    one = write_cell_log(tmp_path / "a1.mcap", [SyntheticLogSpec(duration_s=0.2, axis="a1")])
    other = write_cell_log(tmp_path / "a0.mcap", [SyntheticLogSpec(duration_s=0.2, axis="a0")])
    assert choose_axis_of_logs([cell, one], "a1").label == "a1"
    with pytest.raises(AxisNotRecordedError, match=r"cell\.mcap holds 3 axes"):
        choose_axis_of_logs([one, cell], None)
    with pytest.raises(AxisNotRecordedError, match=r"different axes \(a1 in .*a1.mcap, a0 in .*a0.mcap\)"):
        choose_axis_of_logs([one, other], None)
    with pytest.raises(AxisNotRecordedError, match=r"--axis a2: .*a1\.mcap holds no such axis"):
        choose_axis_of_logs([cell, one], "a2")
