"""The pieces the views are made of, driven one at a time: bulk decoding, the tracking-error join and
the per-move ledger in batches, the routing of keys and topics."""

from __future__ import annotations

import numpy as np
import pytest
from axisflow.acquisition import JointState, MoveState, MoveStatus, PlanRecord, TopicInfo
from axisflow.acquisition.wire.messages import AXIS_JOINTS
from axisflow.model import EXECUTION_PERIOD_S, EnergyAccounting, trace_energy
from axisflow.viz.errors import VizError
from axisflow.viz.live_view import route_of
from axisflow.viz.moves import MoveLedger
from axisflow.viz.samples import AxisSamples, decode_payloads
from axisflow.viz.session import find_axes
from axisflow.viz.tracking import TrackingJoin

T0 = 1_767_225_600_000_000_000


def _samples(rng: np.random.Generator, n: int, start_tick: int = 0) -> AxisSamples:
    stamps = T0 + (start_tick + np.arange(n, dtype=np.int64)) * 1_000_000
    return AxisSamples(stamps, *(rng.normal(size=n) for _ in range(4)))


def test_bulk_decoding_equals_message_by_message():
    rng = np.random.default_rng(0)
    messages = [
        JointState(
            T0 + k * 1_000_000,
            "a0" if k % 7 else "axis-with-a-longer-name",
            AXIS_JOINTS,
            tuple(rng.normal(size=2)),
            tuple(rng.normal(size=2)),
            tuple(rng.normal(size=2)),
        )
        for k in range(50)
    ]
    messages.append(JointState(T0 + 50_000_000, "a0", AXIS_JOINTS, (1.0, 2.0), (), (3.0, 4.0)))  # no velocity
    decoded = decode_payloads([m.encode() for m in messages], "test")
    assert decoded.stamp_ns.tolist() == [m.stamp_ns for m in messages]
    assert decoded.position_m.tolist() == [m.position[0] for m in messages]
    assert decoded.torque_nm.tolist() == [m.effort[1] for m in messages]
    assert decoded.motor_speed_rad_s[:-1].tolist() == [m.velocity[1] for m in messages[:-1]]
    assert np.isnan(decoded.velocity_m_s[-1]) and np.isnan(decoded.motor_speed_rad_s[-1])


def test_joints_that_are_not_the_axis_contract_are_named():
    payload = JointState(T0, "a0", ("x", "y"), (0.0, 0.0), (0.0, 0.0), (0.0, 0.0)).encode()
    with pytest.raises(VizError, match=r"joints \['x', 'y'\].*'carriage' and 'motor'"):
        decode_payloads([payload], "axisflow/a0/state")


@pytest.mark.parametrize("batch", [1, 7, 250, 10_000])
def test_tracking_join_in_batches_equals_the_whole(batch):
    rng = np.random.default_rng(1)
    state, setpoint = _samples(rng, 1000), _samples(rng, 1000)
    keep = np.ones(1000, bool)
    keep[[10, 500, 999]] = False  # three setpoints lost
    sp_stamps, sp_pos = setpoint.stamp_ns[keep], setpoint.position_m[keep]
    join = TrackingJoin()
    got_t, got_e = [], []
    for n, a in enumerate(range(0, 1000, batch)):
        stamps = state.stamp_ns[a : a + batch]
        st = (stamps, state.position_m[a : a + batch])
        mine = (sp_stamps >= stamps[0]) & (sp_stamps <= stamps[-1])
        sp = (sp_stamps[mine], sp_pos[mine])
        # the two topics of a batch arrive in either order
        for pushed in (
            [join.push(state=st), join.push(setpoint=sp)]
            if n % 2
            else [join.push(setpoint=sp), join.push(state=st)]
        ):
            got_t.append(pushed[0])
            got_e.append(pushed[1])
    t, e = np.concatenate(got_t), np.concatenate(got_e)
    np.testing.assert_array_equal(t, state.stamp_ns[keep])
    assert e.tobytes() == (sp_pos - state.position_m[keep]).tobytes()
    assert join.unpaired == 3


def _status(state: MoveState, move_id: int, tick: int, start: int, end: int) -> MoveStatus:
    return MoveStatus(T0 + tick * 1_000_000, "a0", state, move_id, tick, start, end, "s", "")


def _plan(move_id: int, x1: float, energy: float) -> PlanRecord:
    return PlanRecord(
        T0,
        "a0",
        move_id,
        "s",
        "r",
        move_id,
        "min-time",
        "poly5",
        "exact",
        0.9,
        0.0,
        x1,
        1.0,
        energy,
        "positive",
        1.0,
        0.0,
        "converged",
        1,
        0.0,
    )


@pytest.mark.parametrize("batch", [13, 400, 5000])
def test_move_energy_in_batches_equals_the_trapezoid_of_the_span(batch):
    rng = np.random.default_rng(2)
    samples = _samples(rng, 3000)
    ledger = MoveLedger(EnergyAccounting.POSITIVE)
    points = ledger.add_plan(_plan(1, 0.3, 5.0))
    points.extend(ledger.add_status(_status(MoveState.ACCEPTED, 1, 5, 100, 900)))
    points.extend(ledger.add_status(_status(MoveState.ACCEPTED, 2, 5, 900, 1700)))
    points.extend(ledger.add_status(_status(MoveState.ACCEPTED, 3, 5, 1700, 2500)))
    points.extend(ledger.add_status(_status(MoveState.DROPPED, 3, 6, 1700, 2500)))
    for a in range(0, 3000, batch):
        part = AxisSamples(
            *(
                getattr(samples, f)[a : a + batch]
                for f in ("stamp_ns", "position_m", "velocity_m_s", "torque_nm", "motor_speed_rad_s")
            )
        )
        points.extend(ledger.add_samples(part))
    assert [(p.stamp_ns, p.value) for p in points.waypoints] == [(T0 + 900 * 1_000_000, 0.3)]
    assert [p.value for p in points.planned_energy] == [5.0]
    expected = [
        trace_energy(
            samples.motor_speed_rad_s[lo : hi + 1],
            samples.torque_nm[lo : hi + 1],
            EXECUTION_PERIOD_S,
            EnergyAccounting.POSITIVE,
        )
        for lo, hi in ((100, 900), (900, 1700))
    ]
    assert [p.move_id for p in points.measured_energy] == [1, 2]
    assert [p.value for p in points.measured_energy] == expected


def test_a_move_begun_before_the_samples_gets_no_energy():
    rng = np.random.default_rng(3)
    ledger = MoveLedger(EnergyAccounting.POSITIVE)
    ledger.add_status(_status(MoveState.ACCEPTED, 1, 0, 0, 500))
    points = ledger.add_samples(_samples(rng, 1000, start_tick=100))
    assert points.measured_energy == [] and ledger.unmeasured == 1


@pytest.mark.parametrize(
    ("key", "route"),
    [
        ("axisflow/a0/state", ("a0", "state")),
        ("axisflow/a0/setpoint", ("a0", "setpoint")),
        ("plant/line2/x/event", ("plant/line2/x", "event")),
        ("axisflow/a0/plan", ("a0", "plan")),
        ("axisflow/a0/trajectory", None),
        ("axisflow/a0/sender/00ff", None),
        ("state", None),
    ],
)
def test_keys_route_to_an_axis_and_a_kind(key, route):
    assert route_of(key) == route


def test_axes_are_found_by_their_topics_and_types():
    js, st = "sensor_msgs/msg/JointState", "axisflow_msgs/msg/MoveStatus"
    topics = [
        TopicInfo("/axisflow/a0/state", js, "ros2msg", "cdr", 10),
        TopicInfo("/axisflow/a0/event", st, "ros2msg", "cdr", 2),
        TopicInfo("/lab/b1/setpoint", js, "ros2msg", "cdr", 10),
        TopicInfo("/axisflow/a2/event", "std_msgs/msg/String", "ros2msg", "cdr", 1),  # no samples: no axis
        TopicInfo("/axisflow/a3/state", "std_msgs/msg/String", "ros2msg", "cdr", 1),  # wrong type
    ]
    axes = find_axes(topics)
    assert [(a.label, a.state, a.setpoint, a.event) for a in axes] == [
        ("a0", "/axisflow/a0/state", None, "/axisflow/a0/event"),
        ("lab/b1", None, "/lab/b1/setpoint", None),
    ]


def test_every_move_status_has_a_log_level_in_the_scene():
    from axisflow.viz.scene import _LEVELS  # a status without one would stop the session's log

    assert set(_LEVELS) == set(MoveState)
