"""What an axis node is told: its axis, how it decimates the samples, how it plans way points."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ...acquisition.wire.keys import AxisKeys
from ...model import EXECUTION_RATE_HZ
from ...model.motion_laws import POLYNOMIAL_LAWS
from ...planner.problem import DEFAULT_OMEGA, Case
from .errors import Ros2Error
from .names import RosNames

DIAGNOSTICS_PERIOD_S = 1.0
"""how often the node publishes the axis's diagnostics when nothing happens [s] (ROS 2 drivers: 1 Hz)"""


@dataclass(frozen=True)
class MotionSettings:
    """How way points become moves: the planner's case, law and ω (``axisflow planner``'s options)."""

    case: Case = Case.MIN_TIME
    """the objective of a way point without ``time_from_start``"""
    law: str = "poly5"
    """the polynomial law of every move"""
    omega: float = DEFAULT_OMEGA
    """ω of min-time-energy"""

    def __post_init__(self) -> None:
        object.__setattr__(self, "case", Case(self.case))
        if self.law not in POLYNOMIAL_LAWS:
            raise Ros2Error(f"law {self.law!r} is not one of {', '.join(POLYNOMIAL_LAWS)}")
        if not 0.0 <= self.omega <= 1.0:
            raise Ros2Error(f"omega = {self.omega} is outside [0, 1]")


@dataclass(frozen=True)
class NodeSettings:
    """One axis node: its keys, the JointState rate and the motion settings."""

    keys: AxisKeys
    motion: MotionSettings = field(default_factory=MotionSettings)
    rate_hz: float | None = None
    """JointState messages per second of drive time; None: every sample"""
    diagnostics_period_s: float = DIAGNOSTICS_PERIOD_S

    def __post_init__(self) -> None:
        RosNames(self.keys.axis)  # the axis must be a ROS 2 name too
        if self.rate_hz is not None and not (
            math.isfinite(self.rate_hz) and 0.0 < self.rate_hz <= EXECUTION_RATE_HZ
        ):
            raise Ros2Error(
                f"rate = {self.rate_hz} Hz must be in (0, {EXECUTION_RATE_HZ:g}] Hz, the drive's rate "
                "(leave it out to publish every sample)"
            )
        if not (math.isfinite(self.diagnostics_period_s) and self.diagnostics_period_s > 0.0):
            raise Ros2Error(f"diagnostics period = {self.diagnostics_period_s} s must be > 0 s")

    @property
    def names(self) -> RosNames:
        return RosNames(self.keys.axis)
