"""The drive interface: what the bridge needs from an axis drive, simulated or real.

A drive runs a fixed-period cycle (1 ms, :data:`axisflow.model.EXECUTION_PERIOD_NS`). Each cycle the
bridge :meth:`Drive.read` s the latest sample, then :meth:`Drive.apply` s the setpoint of the current
tick (drive time :attr:`Drive.stamp_ns`), which lets the drive advance to the next tick. A real drive
(CiA 402 cyclic synchronous position mode with velocity and torque offsets,
:mod:`axisflow.acquisition.drives.canopen`) implements the same calls.

A real drive can also fault, fall silent, stop on its own and be reset. :meth:`Drive.status` says each
tick whether the drive follows setpoints and whether :meth:`Drive.read` returns a measurement not
returned before (a drive on a field bus measures once per bus cycle, one cycle late, and not at all
when its messages stop); :meth:`Drive.events` hands over what happened since the last call, as typed
:class:`DriveEvent` s; :meth:`Drive.reset_fault` starts the drive's fault reset. The simulated axis
never faults: it inherits the trivial answers of :class:`AlwaysReady`.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum
from typing import Protocol

from ...model import AxisParams, motor_angle, motor_speed, motor_torque
from ..wire.messages import AxisSample


@dataclass(frozen=True)
class Setpoint:
    """What the drive is commanded to track at one tick (SI units)."""

    position_m: float
    velocity_m_s: float
    acceleration_m_s2: float
    force_ff_n: float
    """model feed-forward: belt force that eq. (1) with the nominal parameters requires [N]"""

    def to_sample(self, stamp_ns: int, axis: str, params: AxisParams) -> AxisSample:
        """The setpoint as the two-joint contract (effort = feed-forward force and torque)."""
        return AxisSample(
            stamp_ns=stamp_ns,
            axis=axis,
            position_m=self.position_m,
            velocity_m_s=self.velocity_m_s,
            force_n=self.force_ff_n,
            motor_angle_rad=float(motor_angle(self.position_m, params)),
            motor_speed_rad_s=float(motor_speed(self.velocity_m_s, params)),
            motor_torque_nm=float(motor_torque(self.force_ff_n, params)),
        )


class DriveEventKind(Enum):
    """What happened to a drive (the bridge turns each into a move status of move 0)."""

    FAULT = "fault"
    """the drive faulted (or a fault reset did not clear its fault): it follows no setpoints"""
    COMM_LOST = "comm_lost"
    """nothing heard from the drive in time: its samples stop; it follows no setpoints"""
    DRIVE_STOPPED = "drive_stopped"
    """the drive left operation enabled on its own (its own quick stop, switched off)"""
    WARNING = "warning"
    """the drive warns but goes on following setpoints"""
    ENABLED = "enabled"
    """a fault reset brought the drive back to following setpoints"""


STOPPING_EVENTS = frozenset({DriveEventKind.FAULT, DriveEventKind.COMM_LOST, DriveEventKind.DRIVE_STOPPED})
"""the events after which the drive follows no setpoints until its fault is reset"""


@dataclass(frozen=True)
class DriveEvent:
    """One event of a drive, with the codes of the drive's own diagnostics (0 where there are none)."""

    kind: DriveEventKind
    text: str
    """what happened, in words, naming the drive"""
    error_code: int = 0
    """CiA 301 emergency error code (0x603F error code of a CiA 402 drive)"""
    error_register: int = 0
    """CiA 301 error register (0x1001)"""
    statusword: int = 0
    """CiA 402 statusword (0x6041) when it happened"""


@dataclass(frozen=True)
class DriveStatus:
    """The drive's condition at the current tick."""

    following: bool
    """operation enabled: the setpoints given to :meth:`Drive.apply` are carried out"""
    fresh: bool
    """:meth:`Drive.read` returns a measurement it has not returned before (publish it)"""
    commanded: bool
    """the setpoint of this tick reaches the drive (a drive on a slower bus cycle than the 1 ms tick
    takes every n-th one)"""


READY = DriveStatus(following=True, fresh=True, commanded=True)
"""the status of a drive that never faults and is sampled every tick"""


class Drive(Protocol):
    """A 1 kHz axis drive."""

    axis: str
    """name of the axis (the JointState frame_id)"""

    @property
    def stamp_ns(self) -> int:
        """Drive time of the current tick [ns since the Unix epoch]: the tick the next :meth:`apply`
        commands (ticks are 1 ms apart)."""
        ...

    def read(self) -> AxisSample:
        """The latest measured sample (stamp = when the drive measured it). Whether it is new this tick
        — or was lost on the way, or falls between the bus cycles of a slower drive — is
        :attr:`DriveStatus.fresh`."""
        ...

    def apply(self, setpoint: Setpoint) -> None:
        """Command the setpoint for the current tick and advance to the next tick."""
        ...

    def status(self) -> DriveStatus:
        """The drive's condition at the current tick (call after :meth:`read`)."""
        ...

    def events(self) -> list[DriveEvent]:
        """What happened since the last call, oldest first."""
        ...

    def reset_fault(self) -> None:
        """Start the drive's fault reset; an :attr:`DriveEventKind.ENABLED` event follows once it
        follows setpoints again, a :attr:`DriveEventKind.FAULT` event if the reset fails."""
        ...

    def close(self) -> None:
        """Release the drive (a real drive disables its power stage)."""
        ...


class AlwaysReady:
    """The drive-health part of :class:`Drive` for a drive that cannot fault (the simulated axis)."""

    def status(self) -> DriveStatus:
        return READY

    def events(self) -> list[DriveEvent]:
        return []

    def reset_fault(self) -> None:
        """Nothing to reset (the bridge asks only a drive that reported a fault)."""
