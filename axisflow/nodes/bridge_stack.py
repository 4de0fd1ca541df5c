"""The bridge's stack, assembled: a drive, its bridge(s) and one Zenoh session, run until stopped
(``axisflow bridge``).

The drive (:attr:`BridgeStackSettings.drive`) is one of

* ``sim`` — the built-in simulated axis (:class:`~axisflow.acquisition.drives.sim_axis.SimulatedAxis`)
  on the plant of :attr:`~BridgeStackSettings.plant_profile` or :attr:`~BridgeStackSettings.plant`;
* ``canopen`` — the CiA 402 drive(s) of a ``drive.toml`` over CANopen, one bridge per drive in one loop
  with one SYNC per tick;
* ``canopen-sim`` — the same, with simulated CiA 402 drives hosted in this process first (on the bus
  of the ``drive.toml``).

:func:`run_bridge_stack` runs it and says what happens through :class:`StackHooks`: each bridge's
configuration as it starts, that the stack is ready (every bridge holds its token), and the reports
once the bridges have ended.
"""

from __future__ import annotations

import gc
import threading
from collections.abc import Callable
from contextlib import ExitStack
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ..acquisition.bridge.continuity import DEFAULT_JUMP_TOLERANCE_M
from ..acquisition.bridge.tick_clock import TickTiming
from ..acquisition.bus.options import ZenohOptions
from ..acquisition.wire.keys import DEFAULT_AXIS, DEFAULT_PREFIX, AxisKeys
from ..model import AxisflowError, AxisParams
from .drive_kinds import DRIVES

if TYPE_CHECKING:  # loaded when a stack runs
    from ..acquisition.bridge.config import BridgeConfig
    from ..acquisition.bridge.report import BridgeReport
    from ..acquisition.drives.canopen.config import DriveConfig
    from ..acquisition.drives.canopen.cycle import CycleReport
    from ..acquisition.drives.plant import PlantConfig
    from ..acquisition.wire.drive_info import DriveInfo


@dataclass(frozen=True)
class BridgeStackSettings:
    """What ``axisflow bridge`` runs."""

    drive: str = "sim"
    """one of :data:`~.drive_kinds.DRIVES`"""
    drive_config: str | None = None
    """drive.toml: the CAN bus and its drives (``canopen``, ``canopen-sim``)"""
    reset_fault: bool = False
    """reset a CANopen drive found in fault at start-up"""
    axis: str = DEFAULT_AXIS
    prefix: str = DEFAULT_PREFIX
    plant: str | None = None
    """a plant file of the simulated axis or simulated drives (None: the packaged default)"""
    plant_profile: str | None = None
    """a packaged plant profile instead of :attr:`plant`"""
    plant_state: str | None = None
    """where the simulated axis keeps its position between runs"""
    speed: float = 1.0
    """multiple of real time; 0 = as fast as the consumers allow"""
    duration_s: float | None = None
    """drive time to run [s]; None = until stopped"""
    wait_subscribers_s: float = 0.0
    jump_tolerance_m: float = DEFAULT_JUMP_TOLERANCE_M
    timing: TickTiming = field(default_factory=TickTiming)
    """the ticking thread's real-time priority and cores"""

    def __post_init__(self) -> None:
        if self.drive not in DRIVES:
            raise AxisflowError(f"drive {self.drive!r} is not one of {', '.join(DRIVES)}")


@dataclass(frozen=True)
class StackHooks:
    """What the stack says while it runs."""

    started: Callable[[BridgeConfig], None] = lambda _config: None
    """a bridge has entered (declared everything; its first sample read)"""
    ready: Callable[[], None] = lambda: None
    """every bridge has entered"""
    reports: Callable[[dict[str, BridgeReport], CycleReport | None], None] = lambda _reports, _bus: None
    """the bridges' reports by axis, and the CAN cycle's (None without CANopen); for the simulated
    axis before its session closes (a close that hangs must not take the report along)"""


def run_bridge_stack(
    settings: BridgeStackSettings,
    params: AxisParams,
    options: ZenohOptions,
    stop: threading.Event,
    hooks: StackHooks = StackHooks(),
) -> None:
    """Run the stack of ``settings`` until its duration has passed or ``stop`` is set."""
    # Zenoh, python-can and canopen load here, once a bridge is to run
    from ..acquisition.drives.canopen.config import Pacing, load_drive_config

    if settings.drive == "sim":
        _run_simulated_axis(settings, params, options, stop, hooks)
        return
    drives = load_drive_config(settings.drive_config).with_axis(settings.axis)
    if drives.pacing is Pacing.WALL and settings.speed != 1.0:
        raise AxisflowError(
            f"pacing = wall runs the drives in real time: --speed must be 1, not {settings.speed:g} "
            "(lock-step pacing, for simulated drives, runs at any speed)"
        )
    plant = _plant(settings, params) if settings.drive == "canopen-sim" else None
    reports, bus = _run_canopen(settings, params, drives, plant, options, stop, hooks)
    hooks.reports(reports, bus)


def _plant(settings: BridgeStackSettings, params: AxisParams) -> PlantConfig:
    """The plant of the simulated axis or simulated drives: the profile, the file or the default."""
    from ..acquisition.drives.plant import load_plant, load_profile

    if settings.plant_profile is not None:
        return load_profile(settings.plant_profile, params)
    return load_plant(settings.plant, params)


def _bridge_config(settings: BridgeStackSettings, axis: str, drive: DriveInfo) -> BridgeConfig:
    from ..acquisition.bridge.config import BridgeConfig

    return BridgeConfig(
        keys=AxisKeys(axis, settings.prefix),
        speed=settings.speed,
        duration_s=settings.duration_s,
        wait_subscribers_s=settings.wait_subscribers_s,
        jump_tolerance_m=settings.jump_tolerance_m,
        drive=drive,
        timing=settings.timing,
    )


def _run_simulated_axis(
    settings: BridgeStackSettings,
    params: AxisParams,
    options: ZenohOptions,
    stop: threading.Event,
    hooks: StackHooks,
) -> None:
    from ..acquisition.bridge.bridge import Bridge
    from ..acquisition.bus.session import open_session
    from ..acquisition.drives.sim_axis import SimulatedAxis
    from ..acquisition.wire.drive_info import SIMULATED, DriveInfo

    axis = settings.axis
    plant = _plant(settings, params)
    config = _bridge_config(settings, axis, DriveInfo(0, axis, SIMULATED, plant.profile, plant.source))
    # its clock starts at the first sample
    drive = SimulatedAxis(plant, params, axis=axis, state_path=settings.plant_state)
    with open_session(options) as session:
        try:
            with Bridge(session, drive, params, config) as bridge:
                hooks.started(config)
                hooks.ready()
                # what is allocated by now lives as long as the process: out of the collector's way,
                # so a full collection on the 1 kHz loop costs ~0 ms instead of 40–55 ms (measured)
                gc.freeze()
                bridge.run(stop)
        finally:
            drive.close()
        hooks.reports({axis: bridge.report}, None)


def _run_canopen(
    settings: BridgeStackSettings,
    params: AxisParams,
    drives: DriveConfig,
    plant: PlantConfig | None,
    options: ZenohOptions,
    stop: threading.Event,
    hooks: StackHooks,
) -> tuple[dict[str, BridgeReport], CycleReport]:
    """Start the drives (with a ``plant``: simulated ones hosted here first, for canopen-sim), then one
    bridge per drive in one loop with one SYNC per tick; on the way out the bridges close, then the
    drives are stopped."""
    from ..acquisition.bridge.bridge import Bridge, run_bridges
    from ..acquisition.bus.session import open_session
    from ..acquisition.drives.canopen.master import open_master
    from ..acquisition.drives.canopen.sim_drive import SimulatedDrive
    from ..acquisition.wire.drive_info import DriveInfo

    with ExitStack() as stack:
        if plant is not None:
            for drive_settings in drives.drives:
                stack.enter_context(
                    SimulatedDrive(drives.can, drive_settings, drives.cycle_hz, plant, params)
                )
        session = stack.enter_context(open_session(options))
        master = stack.enter_context(open_master(drives, params, settings.reset_fault))
        with master.cycle.idle():  # a real drive watches the SYNC from the moment it is enabled
            bridges = []
            for drive, drive_settings, info in zip(master.drives, drives.drives, master.infos, strict=True):
                what = DriveInfo(0, drive_settings.axis or settings.axis, info.describe())
                if plant is not None:  # a simulated drive: say which plant it simulates
                    what = DriveInfo(0, what.axis, f"simulated {what.drive}", plant.profile, plant.source)
                config = _bridge_config(settings, what.axis, what)
                bridges.append(stack.enter_context(Bridge(session, drive, params, config)))
                hooks.started(config)
            hooks.ready()
            gc.freeze()
        master.cycle.start_measuring()
        run_bridges(bridges, stop, master.cycle.after_tick)
        return {b.keys.axis: b.report for b in bridges}, master.cycle.report()
