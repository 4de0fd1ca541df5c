"""The drive interface: what the bridge needs from an axis drive, simulated or real.

A drive runs a fixed-period cycle (1 ms, :data:`axisflow.model.EXECUTION_PERIOD_NS`). Each cycle the
bridge :meth:`Drive.read` s the sample of the current tick (if it arrived), then :meth:`Drive.apply` s
the setpoint for it, which lets the drive advance to the next tick. A real drive (e.g. CiA 402 cyclic
synchronous position mode with velocity and torque offsets) implements the same two calls.
"""

from __future__ import annotations

from dataclasses import dataclass
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


class Drive(Protocol):
    """A 1 kHz axis drive."""

    axis: str
    """name of the axis (the JointState frame_id)"""

    def read(self) -> AxisSample | None:
        """The measured sample of the current tick (stamp = the drive's sample time), or None when it
        was lost on the way (a fieldbus frame that missed its cycle): the drive's own loop runs on, and
        the bridge publishes no sample for that tick. The first sample of a run is never None."""
        ...

    def apply(self, setpoint: Setpoint) -> None:
        """Command the setpoint for the current tick and advance to the next tick."""
        ...

    def close(self) -> None:
        """Release the drive (a real drive disables its power stage)."""
        ...
