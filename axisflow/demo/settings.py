"""What ``axisflow demo`` is to run (:class:`DemoSettings`) and its defaults: the command line offers
them before it loads the demo itself (:mod:`axisflow.demo.loop`)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ..acquisition.drives.plant_profiles import DEFAULT_PROFILE

DEFAULT_WAYPOINTS = 50
"""way points of Fig. 5 (the paper's 25)"""
DEFAULT_LOOKAHEAD = 1
DEFAULT_LOOKAHEAD_S = 60.0
"""drive time kept queued behind the running move [s]: at --speed 0 the bridge runs ~40× real time on
two cores shared by three processes, and a planner that loses the CPU for 150 ms (seen on a loaded
machine) finds the queue 6 s of drive time shorter (docs/performance.md)"""


@dataclass(frozen=True)
class DemoSettings:
    out: Path
    waypoints: int = DEFAULT_WAYPOINTS
    seed: int = 0
    speed: float = 0.0
    solver: str = "exact"
    lookahead: int = DEFAULT_LOOKAHEAD
    lookahead_s: float = DEFAULT_LOOKAHEAD_S
    params_path: str | None = None
    plant_profile: str = DEFAULT_PROFILE
    """the simulated axis's packaged plant profile (ideal, realistic, warm-up)"""
    drive: str = "sim"
    """the bridge's drive: ``sim`` (the built-in simulated axis) or ``canopen-sim`` (a simulated CiA 402
    drive on an in-process CAN bus in the bridge's process: encoder counts, per-mille torque, one bus
    cycle of latency)"""
