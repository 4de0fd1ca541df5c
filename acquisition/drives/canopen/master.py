"""The master of one CAN bus: opens it, starts every drive of the configuration, owns their cycle.

:func:`open_master` is what ``axisflow bridge --drive-config`` (and the tests, and the benchmark) use:
the bus opened (:class:`~.network.CanopenNetwork`), each drive configured over SDO and NMT
(:func:`~.startup.configure`), its adapter created (:class:`~.adapter.CanopenDrive`), and all of them
walked to operation enabled by the SYNC cycle (:class:`~.cycle.SyncCycle`). Closing the master stops
the drives (their own quick stop, then switched off) and releases the bus.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

from ....model import AxisParams
from .adapter import CanopenDrive
from .clock import BusClock
from .config import DriveConfig
from .cycle import SyncCycle
from .network import CanopenNetwork
from .startup import DriveInfo, configure

log = logging.getLogger(__name__)


@dataclass
class CanopenMaster:
    """A started bus (a context manager): its drives in configuration order, and its cycle."""

    config: DriveConfig
    network: CanopenNetwork
    cycle: SyncCycle
    drives: list[CanopenDrive] = field(default_factory=list)
    closed: bool = False

    @property
    def infos(self) -> list[DriveInfo]:
        return [d.info for d in self.drives]

    def close(self) -> None:
        """Stop the drives (their own quick stop, then switched off) and release the bus (once)."""
        if self.closed:
            return
        self.closed = True
        try:
            self.cycle.shutdown()
        finally:
            for drive in self.drives:
                drive.close()
            self.network.close()

    def __enter__(self) -> CanopenMaster:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()


def open_master(
    config: DriveConfig,
    params: AxisParams,
    reset_fault: bool = False,
    start_stamp_ns: int | None = None,
) -> CanopenMaster:
    """Open the bus of ``config`` and start every drive on it (see the module docstring).
    ``reset_fault``: a drive found in fault is reset instead of refused."""
    network = CanopenNetwork(config.can)
    try:
        clock = BusClock(config.ticks_per_cycle, start_stamp_ns)
        drives = []
        for settings in config.drives:
            node, info, units = configure(network.network, config, settings, params, reset_fault)
            log.info("%s", info.describe())
            drives.append(CanopenDrive(network.network, node, settings, info, units, params, clock))
        cycle = SyncCycle(network.network, config, drives, clock)
        cycle.enable()
    except BaseException:
        network.close()
        raise
    return CanopenMaster(config, network, cycle, drives)
