"""The quick-stop request of the wire contract: ``axisflow_msgs/msg/QuickStop`` on ``<prefix>/<axis>/stop``.

A bridge that receives one abandons its queue and brings the running move to rest as fast as the
torque limit allows (CiA 402 quick-stop semantics), then holds; it answers with move statuses: the
running move STOPPED, the queued ones DROPPED, and a STOPPED status of move 0 when the axis is at rest
(its text gives the stopping distance and time). Only the planner's identity may publish it when the
secure configuration is in use (docs/security.md).
"""

from __future__ import annotations

from dataclasses import dataclass

from .cdr import HEADER_DEPENDENCIES, CdrReader, CdrWriter, read_time, schema_with_dependencies, write_time

QUICK_STOP_TYPE = "axisflow_msgs/msg/QuickStop"
QUICK_STOP_SCHEMA = schema_with_dependencies(
    "# Stop the axis now: abandon the queued moves, brake to rest within the torque limit, hold.\n"
    "# header.stamp: when it was sent (ns since the Unix epoch); header.frame_id: the axis name.\n"
    "std_msgs/Header header\n"
    "# why (for the log)\n"
    "string reason\n",
    *HEADER_DEPENDENCIES,
)
STOP_MOVE_ID = 0
"""the move id of the bridge's statuses about the stop itself"""


@dataclass(frozen=True)
class QuickStop:
    stamp_ns: int
    axis: str
    reason: str = ""

    def encode(self) -> bytes:
        w = CdrWriter()
        write_time(w, self.stamp_ns)
        w.string(self.axis)
        w.string(self.reason)
        return w.to_bytes()

    @classmethod
    def decode(cls, data: bytes | bytearray | memoryview) -> QuickStop:
        r = CdrReader(data, QUICK_STOP_TYPE)
        return cls(read_time(r), r.string(), r.string())
