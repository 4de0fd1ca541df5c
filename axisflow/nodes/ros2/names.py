"""The ROS 2 names of an axis: its topics, services and node name.

Per axis ``<axis>``: ``/axisflow/<axis>/joint_states``, ``/axisflow/<axis>/joint_trajectory``,
``/axisflow/<axis>/quick_stop``, ``/axisflow/<axis>/reset_fault``, the node ``axisflow_<axis>``, and
the shared ``/diagnostics``. The ROS 2 namespace is fixed (``/axisflow``), whatever Zenoh key prefix
the bridge uses.

An axis name is a Zenoh key chunk (:mod:`axisflow.acquisition.wire.keys`), which allows characters a
ROS 2 name does not: here it must also be a ROS 2 name token — letters, digits and underscores, not
starting with a digit, no ``__`` — which :func:`ros_names` checks before any ROS 2 call, so a bad name
is one clear line, not an rclpy exception.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from .errors import Ros2Error

NAMESPACE = "/axisflow"
DIAGNOSTICS_TOPIC = "/diagnostics"
_TOKEN = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


class RosNameError(Ros2Error, ValueError):
    """An axis name that cannot be part of a ROS 2 topic or node name."""


@dataclass(frozen=True)
class RosNames:
    """The names of one axis's node (see the module docstring)."""

    axis: str

    def __post_init__(self) -> None:
        if not _TOKEN.match(self.axis) or "__" in self.axis:
            raise RosNameError(
                f"axis name {self.axis!r} cannot be part of a ROS 2 name: use letters, digits and single "
                "underscores, starting with a letter"
            )

    @property
    def node(self) -> str:
        return f"axisflow_{self.axis}"

    @property
    def joint_states(self) -> str:
        return f"{NAMESPACE}/{self.axis}/joint_states"

    @property
    def joint_trajectory(self) -> str:
        return f"{NAMESPACE}/{self.axis}/joint_trajectory"

    @property
    def quick_stop(self) -> str:
        return f"{NAMESPACE}/{self.axis}/quick_stop"

    @property
    def reset_fault(self) -> str:
        return f"{NAMESPACE}/{self.axis}/reset_fault"

    @property
    def diagnostics(self) -> str:
        return DIAGNOSTICS_TOPIC
