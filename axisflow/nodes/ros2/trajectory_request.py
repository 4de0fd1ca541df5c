"""A ``trajectory_msgs/msg/JointTrajectory`` read as the way points of an axis.

The axis has one commanded joint, ``carriage`` (position in m); the ``motor`` joint of its JointState
follows from it and is ignored when given. Each point is a way point the axis moves to and stops at
(axisflow's moves are rest to rest); its ``time_from_start``, when not zero, asks the axis to arrive
then, counted from the start of the trajectory's first move. A trajectory is read whole or refused
whole (:class:`~axisflow.nodes.ros2.errors.TrajectoryRefusedError`, naming the point and the value):

* ``joint_names`` must name ``carriage`` (and may name ``motor``), each once, nothing else;
* every point has one finite position per joint name; velocities, accelerations and efforts are
  empty or zero (a point passed through at speed is not a rest-to-rest way point);
* ``time_from_start`` is not negative; ``header.stamp`` not zero asks the first move to start at that
  drive time (nanoseconds since the epoch; zero: after the moves already queued).

The reader takes any object with the message's attributes, so it needs no ROS 2 installation.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from ...acquisition.bridge.move_queue import MAX_QUEUED_MOVES
from ...acquisition.wire.messages import CARRIAGE_JOINT, MOTOR_JOINT
from .errors import TrajectoryRefusedError

NS_PER_S = 1_000_000_000


@dataclass(frozen=True)
class WayPoint:
    """One point of a trajectory: where the carriage stops, and (optionally) when it arrives."""

    position_m: float
    arrive_s: float | None
    """``time_from_start`` [s] after the trajectory's start; None: when the planner's case says"""


@dataclass(frozen=True)
class TrajectoryRequest:
    """The way points of one JointTrajectory, in order."""

    points: tuple[WayPoint, ...]
    start_ns: int = 0
    """drive time of the first move's start [ns since the epoch]; 0: after the queued moves"""

    @property
    def timed(self) -> int:
        """How many points ask for an arrival time."""
        return sum(1 for p in self.points if p.arrive_s is not None)


def _duration_s(duration: Any) -> float:
    return duration.sec + duration.nanosec * 1e-9


def _stamp_ns(stamp: Any) -> int:
    return stamp.sec * NS_PER_S + stamp.nanosec


def read_trajectory(message: Any) -> TrajectoryRequest:
    """The way points of a JointTrajectory (see the module docstring); raises TrajectoryRefusedError."""
    names = list(message.joint_names)
    if CARRIAGE_JOINT not in names:
        raise TrajectoryRefusedError(
            f"joint_names {names} do not name {CARRIAGE_JOINT!r}, the axis's commanded joint (position in m)"
        )
    unknown = [n for n in names if n not in (CARRIAGE_JOINT, MOTOR_JOINT)]
    if unknown or len(set(names)) != len(names):
        raise TrajectoryRefusedError(
            f"joint_names {names}: the axis has the joints {CARRIAGE_JOINT!r} (commanded) and "
            f"{MOTOR_JOINT!r} (follows it), each named once"
        )
    points = list(message.points)
    if not points:
        raise TrajectoryRefusedError("the trajectory has no points")
    if len(points) > MAX_QUEUED_MOVES:
        raise TrajectoryRefusedError(
            f"the trajectory has {len(points)} points; a bridge queues at most {MAX_QUEUED_MOVES} moves"
        )
    column = names.index(CARRIAGE_JOINT)
    way_points = tuple(_way_point(k, p, len(names), column) for k, p in enumerate(points))
    start_ns = _stamp_ns(message.header.stamp)
    if start_ns < 0:
        raise TrajectoryRefusedError(f"header.stamp = {start_ns} ns is before the epoch")
    return TrajectoryRequest(way_points, start_ns)


def _way_point(k: int, point: Any, joints: int, column: int) -> WayPoint:
    positions = list(point.positions)
    if len(positions) != joints:
        raise TrajectoryRefusedError(f"point {k} has {len(positions)} positions for {joints} joint names")
    x = float(positions[column])
    if not math.isfinite(x):
        raise TrajectoryRefusedError(f"point {k}: the {CARRIAGE_JOINT} position {x} m is not finite")
    for field_name, unit in (("velocities", "m/s"), ("accelerations", "m/s²"), ("effort", "N")):
        _check_at_rest(k, field_name, list(getattr(point, field_name)), joints, unit)
    t = _duration_s(point.time_from_start)
    if t < 0.0:
        raise TrajectoryRefusedError(f"point {k}: time_from_start = {t:.9g} s is negative")
    return WayPoint(x, t if t > 0.0 else None)


def _check_at_rest(k: int, field_name: str, values: Sequence[float], joints: int, unit: str) -> None:
    if not values:
        return
    if len(values) != joints:
        raise TrajectoryRefusedError(f"point {k} has {len(values)} {field_name} for {joints} joint names")
    moving = [v for v in values if v != 0.0]
    if moving:
        raise TrajectoryRefusedError(
            f"point {k}: {field_name} {moving[0]:g} {unit} is not 0: axisflow's moves stop at every way "
            f"point (leave {field_name} empty)"
        )
