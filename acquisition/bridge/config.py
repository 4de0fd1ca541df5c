"""What a bridge is to run (:class:`BridgeConfig`): its axis's keys, its pace, how long, what drives it."""

from __future__ import annotations

from dataclasses import dataclass, field

from ...model import EXECUTION_PERIOD_NS
from ..errors import AcquisitionError
from ..wire.drive_info import DriveInfo
from ..wire.keys import AxisKeys
from .continuity import DEFAULT_JUMP_TOLERANCE_M
from .tick_clock import TickTiming


@dataclass(frozen=True)
class BridgeConfig:
    keys: AxisKeys
    speed: float = 1.0
    """multiple of real time; 0 = as fast as the consumers allow"""
    duration_s: float | None = None
    """drive time to run [s]; None = until stopped"""
    wait_subscribers_s: float = 0.0
    """before the first tick, wait up to this long for a subscriber on the state key"""
    jump_tolerance_m: float = DEFAULT_JUMP_TOLERANCE_M
    drive: DriveInfo | None = None
    """what drives the axis: published on ``<prefix>/<axis>/drive`` at the start and every
    :data:`~axisflow.acquisition.wire.drive_info.PERIOD_TICKS`, and named in the report (None:
    neither)"""
    timing: TickTiming = field(default_factory=TickTiming)
    """the ticking thread's real-time priority and cores (tick_clock.py)"""

    def __post_init__(self) -> None:
        if not self.speed >= 0.0:
            raise AcquisitionError(f"bridge speed = {self.speed} must be >= 0 (0 = as fast as possible)")
        if self.duration_s is not None and not self.duration_s > 0.0:
            raise AcquisitionError(f"bridge duration = {self.duration_s} s must be > 0 s")
        if not self.jump_tolerance_m >= 0.0:
            raise AcquisitionError(f"bridge jump tolerance = {self.jump_tolerance_m} m must be >= 0 m")
        if not self.wait_subscribers_s >= 0.0:
            raise AcquisitionError(
                f"bridge wait for subscribers = {self.wait_subscribers_s} s must be >= 0 s"
            )

    @property
    def ticks(self) -> int | None:
        """Ticks to run (None: until stopped)."""
        return None if self.duration_s is None else round(self.duration_s * 1e9 / EXECUTION_PERIOD_NS)
