"""The typed records of the wire contract and their ROS 2 CDR encoding.

The message types that cross Zenoh and land in MCAP, each with its ``ros2msg`` schema text (the
definition with its dependencies, as rosbag2 stores it) so that any tool decodes them:

* ``sensor_msgs/msg/JointState`` — :class:`JointState`; the 1 kHz samples and setpoints of an axis,
  with the two joints of :class:`AxisSample` (``carriage``: m, m/s, N; ``motor``: rad, rad/s, N·m).
* ``axisflow_msgs/msg/Move`` — :class:`MoveCommand`; one rest-to-rest move sent to a drive: a
  polynomial law, or (law ``sampled``) a path given by its :class:`Knots`.
* ``axisflow_msgs/msg/MoveStatus`` — :class:`~axisflow.acquisition.wire.move_status.MoveStatus`; what a
  bridge did with each move (accepted, rejected with the reason, started, completed, dropped).
* ``axisflow_msgs/msg/QuickStop`` — :class:`~axisflow.acquisition.wire.quick_stop.QuickStop`; stop now.
* ``axisflow_msgs/msg/PlanResult`` — :class:`~axisflow.acquisition.wire.plan_record.PlanRecord`; what a
  planner decided for each move (duration, model energy, objective, solver status, certificate).
* ``axisflow_msgs/msg/DriveInfo`` — :class:`~axisflow.acquisition.wire.drive_info.DriveInfo`; what
  drives an axis (the simulated axis and its plant profile, or a real drive).
* ``axisflow_msgs/msg/ParamsEstimate`` — :class:`~axisflow.acquisition.wire.params_estimate.ParamsEstimate`;
  an adaptive node's estimate of the axis's parameters, accepted (a new version) or not, and why.

Time stamps are integer nanoseconds since the Unix epoch (``builtin_interfaces/Time`` on the wire).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...model import SampledTrajectory
from ..errors import WireError
from .cdr import (
    HEADER_DEPENDENCIES,
    CdrReader,
    CdrWriter,
    read_time,
    schema_with_dependencies,
    write_time,
)
from .drive_info import DRIVE_INFO_SCHEMA, DRIVE_INFO_TYPE
from .move_status import MOVE_STATUS_SCHEMA, MOVE_STATUS_TYPE
from .params_estimate import PARAMS_ESTIMATE_SCHEMA, PARAMS_ESTIMATE_TYPE
from .plan_record import PLAN_SCHEMA, PLAN_TYPE
from .quick_stop import QUICK_STOP_SCHEMA, QUICK_STOP_TYPE

JOINT_STATE_TYPE = "sensor_msgs/msg/JointState"
MOVE_TYPE = "axisflow_msgs/msg/Move"

JOINT_STATE_SCHEMA = schema_with_dependencies(
    "std_msgs/Header header\nstring[] name\nfloat64[] position\nfloat64[] velocity\nfloat64[] effort\n",
    *HEADER_DEPENDENCIES,
)

MOVE_SCHEMA = schema_with_dependencies(
    "# A rest-to-rest move of a linear axis: x(t) = x0 + (x1 - x0)·s((t - start)/duration), s = law.\n"
    "# header.stamp: when the move was sent (ns since the Unix epoch); header.frame_id: the axis name.\n"
    "std_msgs/Header header\n"
    "# identifier chosen by the sender, echoed in the bridge's move status\n"
    "uint64 move_id\n"
    "# drive time at which the move starts; 0 s 0 ns = append: start right after the queued moves\n"
    "builtin_interfaces/Time start\n"
    "# motion law: poly3, poly5, poly7, or sampled (follow the knots below)\n"
    "string law\n"
    "float64 start_position_m\n"
    "float64 end_position_m\n"
    "float64 duration_s\n"
    "# law sampled: the knots of the path, joined by quintic Hermite pieces: time from the move's\n"
    "# start [s] (first 0, last duration_s), position [m] (first start_position_m, last end_position_m),\n"
    "# velocity [m/s] (0 at both ends) and acceleration [m/s^2]. Empty for the polynomial laws.\n"
    "float64[] knot_t_s\n"
    "float64[] knot_position_m\n"
    "float64[] knot_velocity_m_s\n"
    "float64[] knot_acceleration_m_s2\n",
    *HEADER_DEPENDENCIES,
)

SCHEMAS: dict[str, str] = {
    JOINT_STATE_TYPE: JOINT_STATE_SCHEMA,
    MOVE_TYPE: MOVE_SCHEMA,
    MOVE_STATUS_TYPE: MOVE_STATUS_SCHEMA,
    PLAN_TYPE: PLAN_SCHEMA,
    QUICK_STOP_TYPE: QUICK_STOP_SCHEMA,
    DRIVE_INFO_TYPE: DRIVE_INFO_SCHEMA,
    PARAMS_ESTIMATE_TYPE: PARAMS_ESTIMATE_SCHEMA,
}
"""ros2msg schema text by ROS 2 type name, for every type axisflow publishes."""

CARRIAGE_JOINT = "carriage"
MOTOR_JOINT = "motor"
AXIS_JOINTS = (CARRIAGE_JOINT, MOTOR_JOINT)


@dataclass(frozen=True)
class JointState:
    """``sensor_msgs/msg/JointState``: named joints with position, velocity and effort arrays."""

    stamp_ns: int
    frame_id: str
    name: tuple[str, ...]
    position: tuple[float, ...]
    velocity: tuple[float, ...]
    effort: tuple[float, ...]

    def encode(self) -> bytes:
        """ROS 2 CDR bytes (with the CDR_LE encapsulation header)."""
        w = CdrWriter()
        write_time(w, self.stamp_ns)
        w.string(self.frame_id)
        w.string_sequence(self.name)
        w.float64_sequence(self.position)
        w.float64_sequence(self.velocity)
        w.float64_sequence(self.effort)
        return w.to_bytes()

    @classmethod
    def decode(cls, data: bytes | bytearray | memoryview) -> JointState:
        r = CdrReader(data, JOINT_STATE_TYPE)
        stamp_ns = read_time(r)
        return cls(
            stamp_ns=stamp_ns,
            frame_id=r.string(),
            name=r.string_sequence(),
            position=r.float64_sequence(),
            velocity=r.float64_sequence(),
            effort=r.float64_sequence(),
        )


@dataclass(frozen=True)
class AxisSample:
    """One tick of an axis as the two-joint JointState contract.

    ``carriage``: position [m], velocity [m/s], effort = belt force on the cart [N];
    ``motor``: position [rad], velocity [rad/s], effort = motor torque [N·m].
    For a setpoint the efforts are the feed-forward force and torque.
    """

    stamp_ns: int
    axis: str
    position_m: float
    velocity_m_s: float
    force_n: float
    motor_angle_rad: float
    motor_speed_rad_s: float
    motor_torque_nm: float

    def to_joint_state(self) -> JointState:
        return JointState(
            stamp_ns=self.stamp_ns,
            frame_id=self.axis,
            name=AXIS_JOINTS,
            position=(self.position_m, self.motor_angle_rad),
            velocity=(self.velocity_m_s, self.motor_speed_rad_s),
            effort=(self.force_n, self.motor_torque_nm),
        )

    def encode(self) -> bytes:
        return self.to_joint_state().encode()

    @classmethod
    def from_joint_state(cls, js: JointState) -> AxisSample:
        if js.name != AXIS_JOINTS:
            raise WireError(
                f"JointState joints {list(js.name)} are not the axis contract {list(AXIS_JOINTS)}"
            )
        for field_name in ("position", "velocity", "effort"):
            n = len(getattr(js, field_name))
            if n != 2:
                raise WireError(f"JointState {field_name} has {n} values, the axis contract needs 2")
        return cls(
            stamp_ns=js.stamp_ns,
            axis=js.frame_id,
            position_m=js.position[0],
            velocity_m_s=js.velocity[0],
            force_n=js.effort[0],
            motor_angle_rad=js.position[1],
            motor_speed_rad_s=js.velocity[1],
            motor_torque_nm=js.effort[1],
        )

    @classmethod
    def decode(cls, data: bytes | bytearray | memoryview) -> AxisSample:
        return cls.from_joint_state(JointState.decode(data))


APPEND = 0
"""``MoveCommand.start_ns`` value meaning: start right after the moves already queued."""
SAMPLED_LAW = "sampled"
"""``MoveCommand.law`` of a move given by knots (:class:`Knots`) instead of a polynomial law"""


@dataclass(frozen=True, eq=False)
class Knots:
    """The knots of a sampled move (arrays of equal length; see :data:`MOVE_SCHEMA`)."""

    t_s: np.ndarray
    position_m: np.ndarray
    velocity_m_s: np.ndarray
    acceleration_m_s2: np.ndarray

    @classmethod
    def of(cls, trajectory: SampledTrajectory) -> Knots:
        return cls(
            trajectory.t_s, trajectory.position_m, trajectory.velocity_m_s, trajectory.acceleration_m_s2
        )

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        return self.t_s, self.position_m, self.velocity_m_s, self.acceleration_m_s2

    def __len__(self) -> int:
        return int(np.asarray(self.t_s).size)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Knots):
            return NotImplemented
        return all(np.array_equal(a, b) for a, b in zip(self.arrays(), other.arrays(), strict=True))

    __hash__ = None  # type: ignore[assignment]  # mutable arrays: not hashable


@dataclass(frozen=True)
class MoveCommand:
    """``axisflow_msgs/msg/Move``: one rest-to-rest move for a drive (see :data:`MOVE_SCHEMA`)."""

    stamp_ns: int
    axis: str
    move_id: int
    start_ns: int
    """drive time of the first sample of the move [ns]; :data:`APPEND` (0) = after the queued moves"""
    law: str
    start_position_m: float
    end_position_m: float
    duration_s: float
    knots: Knots | None = None
    """the path of a :data:`SAMPLED_LAW` move; None for a polynomial law"""

    def __post_init__(self) -> None:
        for name in ("start_position_m", "end_position_m", "duration_s"):
            value = getattr(self, name)
            if not math.isfinite(value):
                raise WireError(f"move {self.move_id}: {name} = {value} is not finite")
        if self.start_ns < 0:
            raise WireError(f"move {self.move_id}: start_ns = {self.start_ns} ns must be >= 0 (0 = append)")
        if not 0 <= self.move_id < 2**64:
            raise WireError(f"move_id = {self.move_id} must be in [0, 2**64)")

    @property
    def appends(self) -> bool:
        return self.start_ns == APPEND

    def encode(self) -> bytes:
        w = CdrWriter()
        write_time(w, self.stamp_ns)
        w.string(self.axis)
        w.uint64(self.move_id)
        write_time(w, self.start_ns)
        w.string(self.law)
        w.float64(self.start_position_m)
        w.float64(self.end_position_m)
        w.float64(self.duration_s)
        for values in self.knots.arrays() if self.knots is not None else (np.empty(0),) * 4:
            w.float64_array(values)
        return w.to_bytes()

    @classmethod
    def decode(cls, data: bytes | bytearray | memoryview) -> MoveCommand:
        r = CdrReader(data, MOVE_TYPE)
        stamp_ns = read_time(r)
        axis = r.string()
        move_id = r.uint64()
        start_ns = read_time(r)
        law = r.string()
        x0, x1, duration = r.float64(), r.float64(), r.float64()
        arrays = [r.float64_array() for _ in range(4)]
        knots = Knots(*arrays) if any(a.size for a in arrays) else None
        return cls(stamp_ns, axis, move_id, start_ns, law, x0, x1, duration, knots)
