"""The quick-stop request of the wire contract: ``axisflow_msgs/msg/QuickStop`` on ``<prefix>/<axis>/stop``.

A bridge that receives one abandons its queue and brings the running move to rest as fast as the
torque limit allows (CiA 402 quick-stop semantics), then holds; it answers with move statuses: the
running move STOPPED, the queued ones DROPPED, and a STOPPED status of move 0 when the axis is at rest
(its text gives the stopping distance and time). Only the planner's identity may publish it when the
secure configuration is in use (docs/security.md).

With ``reset_fault`` set (``axisflow stop --reset-fault``) the bridge also resets its drive's fault
(the CiA 402 fault-reset sequence) and answers with an ENABLED status of move 0 once the drive follows
setpoints again (or at once, if there was no fault), or a FAULT status if the reset did not clear it.
The field was appended: a request sent before it existed decodes with it false.
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
    "string reason\n"
    "# also reset the drive's fault (CiA 402 fault reset) and enable it again\n"
    "bool reset_fault\n",
    *HEADER_DEPENDENCIES,
)
STOP_MOVE_ID = 0
"""the move id of the bridge's statuses about the stop itself"""


@dataclass(frozen=True)
class QuickStop:
    stamp_ns: int
    axis: str
    reason: str = ""
    reset_fault: bool = False
    """also reset the drive's fault and enable it again"""

    def encode(self) -> bytes:
        w = CdrWriter()
        write_time(w, self.stamp_ns)
        w.string(self.axis)
        w.string(self.reason)
        w.uint8(1 if self.reset_fault else 0)
        return w.to_bytes()

    @classmethod
    def decode(cls, data: bytes | bytearray | memoryview) -> QuickStop:
        r = CdrReader(data, QUICK_STOP_TYPE)
        stamp_ns, axis, reason = read_time(r), r.string(), r.string()
        reset = False if r.at_end else r.uint8() != 0  # a request from before the field existed: False
        return cls(stamp_ns, axis, reason, reset)
