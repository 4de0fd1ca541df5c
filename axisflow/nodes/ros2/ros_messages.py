"""axisflow's records as ROS 2 messages (the ROS 2 side of the node; the CDR of a JointState needs no
conversion at all: :mod:`.joint_state_relay` publishes the bridge's bytes as they are)."""

from __future__ import annotations

from builtin_interfaces.msg import Time
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from sensor_msgs.msg import JointState

from ...acquisition.wire.messages import AXIS_JOINTS, AxisSample
from .axis_health import HealthStatus

NS_PER_S = 1_000_000_000


def ros_time(stamp_ns: int) -> Time:
    """``builtin_interfaces/Time`` of a time stamp [ns since the epoch]."""
    sec, nanosec = divmod(int(stamp_ns), NS_PER_S)
    return Time(sec=sec, nanosec=nanosec)


def time_ns(stamp: Time) -> int:
    """Nanoseconds since the epoch of a ``builtin_interfaces/Time``."""
    return stamp.sec * NS_PER_S + stamp.nanosec


def diagnostic_array(statuses: tuple[HealthStatus, ...], stamp_ns: int) -> DiagnosticArray:
    """A ``diagnostic_msgs/msg/DiagnosticArray`` of ``statuses`` stamped ``stamp_ns``."""
    array = DiagnosticArray()
    array.header.stamp = ros_time(stamp_ns)
    array.status = [
        DiagnosticStatus(
            level=bytes([int(s.level)]),
            name=s.name,
            message=s.message,
            hardware_id=s.hardware_id,
            values=[KeyValue(key=k, value=v) for k, v in s.values],
        )
        for s in statuses
    ]
    return array


def joint_state(sample: AxisSample) -> JointState:
    """The JointState of a sample built field by field (what the relay avoids: see
    ``axisflow bench ros2``, which compares both)."""
    message = JointState()
    message.header.stamp = ros_time(sample.stamp_ns)
    message.header.frame_id = sample.axis
    message.name = list(AXIS_JOINTS)
    message.position = [sample.position_m, sample.motor_angle_rad]
    message.velocity = [sample.velocity_m_s, sample.motor_speed_rad_s]
    message.effort = [sample.force_n, sample.motor_torque_nm]
    return message
