"""What a drive bridge did with a move, and what its drive did: the typed status record of the wire contract.

A bridge publishes one :class:`MoveStatus` on ``<prefix>/<axis>/event`` for each step of a move's life:

    accepted ──► started ──► completed
       │            └──────► stopped     (a quick stop or a drive fault brought it to rest early)
       └──► dropped                      (its sender vanished, a quick stop or a fault, before it started)
    rejected                             (never queued; ``text`` gives the reason)

and one for each event of the drive itself, with move id 0 (:data:`~.quick_stop.STOP_MOVE_ID`):

    fault ─┐                              (the drive faulted: ``error_code``, ``error_register``)
    comm_lost ─┼──► (moves refused) ──► enabled   (after ``axisflow stop --reset-fault``)
    drive_stopped ─┘                      (the drive left operation enabled on its own)
    warning                               (the drive warns; moves go on)

The record carries the move's id, its sender, the bridge tick at which the step happened and the
move's tick span, so programs (the planner node, tests, views) act on fields, never on text; the
human-readable ``text`` is one field of it. Ticks count from the bridge's first sample, 1 ms apart;
``header.stamp`` is the drive time of ``tick``.

Why the drive's events share the move status record instead of a record of their own: one key carries
one type (ROS 2 and MCAP bind a topic to one schema; the recorder registers a key's channel with the
type of its first message), and every reader of ``event`` — the move sender, the planner node, Table 2,
the views — already decodes this record; a fault ends moves (stopped, dropped) exactly like a quick
stop, so they learn of it without knowing anything about drives. The drive's fields were appended at
the end: a status recorded before they existed decodes with them 0.
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
    """abandoned while running: a quick stop or a drive fault stopped it before its end point"""
    FAULT = 7
    """(move 0) the drive faulted: ``error_code`` (CiA 301 emergency code, 0x603F), ``error_register``
    (0x1001), ``statusword`` (0x6041); the bridge refuses moves until the fault is reset"""
    COMM_LOST = 8
    """(move 0) nothing heard from the drive in time (process data or heartbeat): the bridge publishes
    no samples, commands the drive's own quick stop and refuses moves until the fault is reset"""
    DRIVE_STOPPED = 9
    """(move 0) the drive left operation enabled on its own (its quick stop, or switched off): moves are
    refused until the fault is reset"""
    WARNING = 10
    """(move 0) the drive warns (statusword warning bit, an emergency message that did not stop it);
    moves go on"""
    ENABLED = 11
    """(move 0) a fault reset brought the drive back to operation enabled: moves are accepted again (the
    answer to ``axisflow stop --reset-fault``, also when there was nothing to reset)"""


NO_TICK = -1
"""``start_tick``/``end_tick`` of a move that was never queued"""
DRIVE_EVENTS = frozenset(
    {MoveState.FAULT, MoveState.COMM_LOST, MoveState.DRIVE_STOPPED, MoveState.WARNING, MoveState.ENABLED}
)
"""the states that report the drive's own events (move 0), not a move's"""

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
    "uint8 FAULT=7\n"
    "uint8 COMM_LOST=8\n"
    "uint8 DRIVE_STOPPED=9\n"
    "uint8 WARNING=10\n"
    "uint8 ENABLED=11\n"
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
    "string text\n"
    "# the drive's event (FAULT … ENABLED), else 0: CiA 301 emergency error code (0x603F),\n"
    "# error register (0x1001) and the CiA 402 statusword (0x6041) when it happened\n"
    "uint16 error_code\n"
    "uint8 error_register\n"
    "uint16 statusword\n",
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
    error_code: int = 0
    """a drive event's CiA 301 emergency error code (0x603F); 0: none"""
    error_register: int = 0
    """a drive event's error register (0x1001)"""
    statusword: int = 0
    """the drive's CiA 402 statusword (0x6041) at a drive event"""

    def __post_init__(self) -> None:
        try:
            object.__setattr__(self, "state", MoveState(self.state))
        except ValueError:
            known = ", ".join(f"{s.value} ({s.name.lower()})" for s in MoveState)
            raise WireError(f"move status {self.state!r} is not one of {known}") from None
        if not 0 <= self.move_id < 2**64:
            raise WireError(f"move_id = {self.move_id} must be in [0, 2**64)")
        for name, bits in (("error_code", 16), ("error_register", 8), ("statusword", 16)):
            value = getattr(self, name)
            if not 0 <= value < 1 << bits:
                raise WireError(f"{name} = {value} must be an unsigned {bits}-bit number")

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
        w.uint16(self.error_code)
        w.uint8(self.error_register)
        w.uint16(self.statusword)
        return w.to_bytes()

    @classmethod
    def decode(cls, data: bytes | bytearray | memoryview) -> MoveStatus:
        r = CdrReader(data, MOVE_STATUS_TYPE)
        fields = {
            "stamp_ns": read_time(r),
            "axis": r.string(),
            "state": r.uint8(),  # validated into a MoveState
            "move_id": r.uint64(),
            "tick": r.int64(),
            "start_tick": r.int64(),
            "end_tick": r.int64(),
            "sender": r.string(),
            "text": r.string(),
        }
        if not r.at_end:  # recorded before the drive's fields were appended: they stay 0
            fields.update(error_code=r.uint16(), error_register=r.uint8(), statusword=r.uint16())
        return cls(**fields)  # type: ignore[arg-type]
