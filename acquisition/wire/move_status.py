"""What a drive bridge did with a move: the typed status record of the wire contract.

A bridge publishes one :class:`MoveStatus` on ``<prefix>/<axis>/event`` for each step of a move's life:

    accepted ──► started ──► completed
       │            └──────► stopped     (a quick stop brought it to rest early)
       └──► dropped                      (its sender vanished, or a quick stop, before it started)
    rejected                             (never queued; ``text`` gives the reason)

The record carries the move's id, its sender, the bridge tick at which the step happened and the
move's tick span, so programs (the planner node, tests, views) act on fields, never on text; the
human-readable ``text`` is one field of it. Ticks count from the bridge's first sample, 1 ms apart;
``header.stamp`` is the drive time of ``tick``.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

from ...model import EXECUTION_PERIOD_NS
from ..errors import WireError
from .cdr import HEADER_DEPENDENCIES, CdrReader, CdrWriter, read_time, schema_with_dependencies, write_time

MOVE_STATUS_TYPE = "axisflow_msgs/msg/MoveStatus"


class MoveState(IntEnum):
    """The step of a move's life a :class:`MoveStatus` reports (the ``status`` byte on the wire)."""

    ACCEPTED = 1
    """validated and queued; ``start_tick``/``end_tick`` say when it will run"""
    REJECTED = 2
    """refused; ``text`` says why (the move never runs)"""
    STARTED = 3
    """its first sample is the setpoint of ``tick``"""
    COMPLETED = 4
    """it ran to its end point; the axis is there at rest from ``end_tick`` on"""
    DROPPED = 5
    """removed from the queue before it started (its sender vanished, or a quick stop)"""
    STOPPED = 6
    """abandoned while running: a quick stop brought the axis to rest before its end point"""


NO_TICK = -1
"""``start_tick``/``end_tick`` of a move that was never queued"""

MOVE_STATUS_SCHEMA = schema_with_dependencies(
    "# What a drive bridge did with a move: one message per step of the move's life.\n"
    "# header.stamp: drive time of the tick at which it happened (ns since the Unix epoch);\n"
    "# header.frame_id: the axis name.\n"
    "std_msgs/Header header\n"
    "uint8 ACCEPTED=1\n"
    "uint8 REJECTED=2\n"
    "uint8 STARTED=3\n"
    "uint8 COMPLETED=4\n"
    "uint8 DROPPED=5\n"
    "uint8 STOPPED=6\n"
    "uint8 status\n"
    "# the move's identifier, as its sender chose it\n"
    "uint64 move_id\n"
    "# the bridge tick (1 ms apart, 0 = the bridge's first sample) at which this happened\n"
    "int64 tick\n"
    "# the move's first tick and the first tick at rest at its end point; -1 if never queued\n"
    "int64 start_tick\n"
    "int64 end_tick\n"
    "# the publisher id of the move's sender (hex), empty if unknown\n"
    "string sender\n"
    "# the same in words; for a rejection, the reason\n"
    "string text\n",
    *HEADER_DEPENDENCIES,
)


@dataclass(frozen=True)
class MoveStatus:
    """``axisflow_msgs/msg/MoveStatus``: one step of one move's life (see the module docstring)."""

    stamp_ns: int
    """drive time of ``tick`` [ns since the Unix epoch]"""
    axis: str
    state: MoveState
    move_id: int
    tick: int
    start_tick: int = NO_TICK
    end_tick: int = NO_TICK
    sender: str = ""
    """hex publisher id of the move's sender"""
    text: str = ""

    def __post_init__(self) -> None:
        try:
            object.__setattr__(self, "state", MoveState(self.state))
        except ValueError:
            known = ", ".join(f"{s.value} ({s.name.lower()})" for s in MoveState)
            raise WireError(f"move status {self.state!r} is not one of {known}") from None
        if not 0 <= self.move_id < 2**64:
            raise WireError(f"move_id = {self.move_id} must be in [0, 2**64)")

    def stamp_of(self, tick: int) -> int:
        """The drive time [ns since the epoch] of ``tick`` on the bridge that published this status
        (its ticks are 1 ms apart and ``stamp_ns`` is the drive time of ``self.tick``)."""
        return self.stamp_ns + (tick - self.tick) * EXECUTION_PERIOD_NS

    def encode(self) -> bytes:
        w = CdrWriter()
        write_time(w, self.stamp_ns)
        w.string(self.axis)
        w.uint8(int(self.state))
        w.uint64(self.move_id)
        w.int64(self.tick)
        w.int64(self.start_tick)
        w.int64(self.end_tick)
        w.string(self.sender)
        w.string(self.text)
        return w.to_bytes()

    @classmethod
    def decode(cls, data: bytes | bytearray | memoryview) -> MoveStatus:
        r = CdrReader(data, MOVE_STATUS_TYPE)
        return cls(
            stamp_ns=read_time(r),
            axis=r.string(),
            state=r.uint8(),  # type: ignore[arg-type]  # validated into a MoveState
            move_id=r.uint64(),
            tick=r.int64(),
            start_tick=r.int64(),
            end_tick=r.int64(),
            sender=r.string(),
            text=r.string(),
        )
