"""A JointTrajectory read as way points: the real ROS 2 message classes, every refusal naming the point
and the value (a table), nothing half-read."""

from __future__ import annotations

import pytest

trajectory_msgs = pytest.importorskip(
    "trajectory_msgs.msg", reason='ROS 2 is not installed (pip install "axisflow[ros2]")'
)
from builtin_interfaces.msg import Duration, Time  # noqa: E402

from axisflow.nodes.ros2.errors import TrajectoryRefusedError  # noqa: E402
from axisflow.nodes.ros2.trajectory_request import WayPoint, read_trajectory  # noqa: E402

JointTrajectory, JointTrajectoryPoint = trajectory_msgs.JointTrajectory, trajectory_msgs.JointTrajectoryPoint


def trajectory(names, *points, stamp_ns: int = 0):
    message = JointTrajectory()
    message.joint_names = list(names)
    message.header.stamp = Time(sec=stamp_ns // 1_000_000_000, nanosec=stamp_ns % 1_000_000_000)
    message.points = list(points)
    return message


def point(*positions, t_s: float = 0.0, **fields):
    sec = int(t_s)
    p = JointTrajectoryPoint(
        positions=list(positions), time_from_start=Duration(sec=sec, nanosec=round((t_s - sec) * 1e9))
    )
    for name, values in fields.items():
        setattr(p, name, list(values))
    return p


def test_the_carriage_column_and_the_times_are_read():
    request = read_trajectory(
        trajectory(
            ["motor", "carriage"],
            point(75.0, 0.3),
            point(25.0, 0.1, t_s=2.5),
            stamp_ns=1_700_000_000_250_000_000,
        )
    )
    assert request.points == (WayPoint(0.3, None), WayPoint(0.1, 2.5))
    assert request.start_ns == 1_700_000_000_250_000_000
    assert request.timed == 1


def test_zero_velocities_are_rest_and_allowed():
    request = read_trajectory(trajectory(["carriage"], point(0.2, velocities=[0.0], accelerations=[0.0])))
    assert request.points == (WayPoint(0.2, None),)


@pytest.mark.parametrize(
    ("message", "says"),
    [
        (trajectory(["motor"], point(1.0)), "do not name 'carriage'"),
        (trajectory(["carriage", "elbow"], point(0.1, 0.2)), "each named once"),
        (trajectory(["carriage", "carriage"], point(0.1, 0.2)), "each named once"),
        (trajectory(["carriage"]), "no points"),
        (trajectory(["carriage"], point(0.1, 0.2)), "point 0 has 2 positions for 1 joint names"),
        (trajectory(["carriage"], point(0.1), point(float("nan"))), "point 1: the carriage position nan m"),
        (trajectory(["carriage"], point(0.1, velocities=[0.5])), "point 0: velocities 0.5 m/s is not 0"),
        (trajectory(["carriage"], point(0.1, accelerations=[1.0])), "accelerations 1 m/s² is not 0"),
        (trajectory(["carriage"], point(0.1, effort=[2.0])), "effort 2 N is not 0"),
        (trajectory(["carriage"], point(0.1, velocities=[0.0, 0.0])), "point 0 has 2 velocities for 1"),
        (trajectory(["carriage"], *[point(0.1)] * 1025), "1025 points; a bridge queues at most 1024"),
    ],
)
def test_a_trajectory_is_refused_whole_naming_the_point_and_value(message, says):
    with pytest.raises(TrajectoryRefusedError, match=None) as refused:
        read_trajectory(message)
    assert says in str(refused.value)


def test_a_negative_time_from_start_is_refused():
    p = JointTrajectoryPoint(positions=[0.1], time_from_start=Duration(sec=-1, nanosec=0))
    with pytest.raises(TrajectoryRefusedError, match=r"point 0: time_from_start = -1 s is negative"):
        read_trajectory(trajectory(["carriage"], p))
