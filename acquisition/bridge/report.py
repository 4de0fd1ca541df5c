"""What a bridge run did (:class:`BridgeReport`): ticks, moves, drive faults, the period's jitter."""

from __future__ import annotations

from dataclasses import dataclass, field

from ...model import ticks_to_seconds
from ..histogram import DurationStats


@dataclass
class BridgeReport:
    """What a bridge run did."""

    ticks: int = 0
    wall_time_s: float = 0.0
    moves_accepted: int = 0
    moves_rejected: int = 0
    moves_completed: int = 0
    moves_dropped: int = 0
    """queued moves dropped because their sender disappeared"""
    moves_missed: int = 0
    """moves lost on the way, from the senders' sequence numbers"""
    quick_stops: int = 0
    stale_ticks: int = 0
    """ticks without a new sample from the drive (lost on the way, the drive silent, or between the
    cycles of a drive on a slower bus): none published for them"""
    drive_faults: int = 0
    """times the drive stopped following setpoints (fault, comm lost, its own stop)"""
    drive: str = ""
    """what drove the axis (:attr:`BridgeConfig.drive`)"""
    period_jitter: DurationStats | None = None
    """|tick-start period − 1 ms/speed| [µs]; None at speed 0"""
    late_ticks: int = 0
    """ticks that started more than a whole period after their deadline (at speed > 0)"""
    tick_lateness: DurationStats | None = None
    """tick start − its deadline [µs]; None at speed 0"""
    rejections: list[str] = field(default_factory=list)

    def summary(self) -> str:
        lines = [
            f"bridge: {self.ticks} ticks ({ticks_to_seconds(self.ticks):.3f} s of drive time) "
            f"in {self.wall_time_s:.3f} s" + (f"; drive: {self.drive}" if self.drive else ""),
            f"  moves: {self.moves_accepted} accepted, {self.moves_completed} completed, "
            f"{self.moves_rejected} rejected, {self.moves_dropped} dropped, {self.moves_missed} missed",
        ]
        if self.stale_ticks:
            lines.append(f"  ticks without a new sample from the drive: {self.stale_ticks} of {self.ticks}")
        if self.drive_faults:
            lines.append(f"  drive: stopped following {self.drive_faults} time(s) (see the event key)")
        if self.period_jitter is not None and self.period_jitter.count:
            j = self.period_jitter
            lines.append(
                f"  period jitter: p50 {j.p50_us:.0f} µs, p99 {j.p99_us:.0f} µs, max {j.max_us:.0f} µs "
                f"over {j.count} periods; {self.late_ticks} ticks late by more than a period"
            )
        if self.tick_lateness is not None and self.tick_lateness.count:
            t = self.tick_lateness
            lines.append(
                f"  tick start after its deadline: p50 {t.p50_us:.0f} µs, p99 {t.p99_us:.0f} µs, "
                f"max {t.max_us:.0f} µs"
            )
        return "\n".join(lines)

    def to_dict(self) -> dict[str, object]:
        return {
            "ticks": self.ticks,
            "wall_time_s": self.wall_time_s,
            "moves_accepted": self.moves_accepted,
            "moves_rejected": self.moves_rejected,
            "moves_completed": self.moves_completed,
            "moves_dropped": self.moves_dropped,
            "moves_missed": self.moves_missed,
            "quick_stops": self.quick_stops,
            "stale_ticks": self.stale_ticks,
            "drive_faults": self.drive_faults,
            "drive": self.drive,
            "period_jitter": self.period_jitter.to_dict() if self.period_jitter else None,
            "late_ticks": self.late_ticks,
            "tick_lateness": self.tick_lateness.to_dict() if self.tick_lateness else None,
            "rejections": self.rejections,
        }
