"""The errors of :mod:`axisflow.nodes.ros2`: one root, and the refusal of a trajectory."""

from __future__ import annotations

from ...model import AxisflowError


class Ros2Error(AxisflowError):
    """Root of the errors of :mod:`axisflow.nodes.ros2`."""


class Ros2UnavailableError(Ros2Error):
    """rclpy (ROS 2 from wheels) is not installed: ``pip install "axisflow[ros2]"``."""


class TrajectoryRefusedError(Ros2Error, ValueError):
    """A JointTrajectory the node will not execute; the message names the point, the value and the limit."""
