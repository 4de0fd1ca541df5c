"""Opening a CAN bus for CANopen: a python-can bus under a canopen network, with errors that name it.

python-can's interfaces fail in many ways when their driver or device is missing (an unknown name, an
``OSError`` from the kernel, a missing vendor library, even a ``NameError``): all of them become one
:class:`~axisflow.acquisition.errors.DriveError` naming the interface, the channel and the reason.
"""

from __future__ import annotations

import logging

import can
import canopen
from can.interfaces import VALID_INTERFACES

from ...errors import DriveError
from .config import CanSettings

log = logging.getLogger(__name__)


def open_bus(settings: CanSettings) -> can.BusABC:
    """The python-can bus of ``settings`` (raises :class:`DriveError` naming what failed)."""
    name = f"CAN interface {settings.interface!r} channel {settings.channel!r}"
    if settings.interface not in VALID_INTERFACES:
        known = ", ".join(sorted(VALID_INTERFACES))
        raise DriveError(f"{name}: {settings.interface!r} is not a python-can interface (known: {known})")
    kwargs = {} if settings.bitrate is None else {"bitrate": settings.bitrate}
    try:
        return can.Bus(interface=settings.interface, channel=settings.channel, **kwargs)
    except Exception as exc:  # every interface fails its own way; all mean "cannot open"
        reason = str(exc).strip() or type(exc).__name__
        raise DriveError(f"{name} cannot be opened: {reason}") from None


class CanopenNetwork:
    """A canopen network on its own bus (a context manager; closing stops its receive thread and
    releases the bus). The master and a simulated drive each open their own, even in one process:
    python-can's ``virtual`` bus delivers a frame to every other bus on its channel, as a real bus
    does, but not back to its sender."""

    def __init__(self, settings: CanSettings, network: canopen.Network | None = None) -> None:
        self.settings = settings
        self.network = network if network is not None else canopen.Network()
        self.network.bus = open_bus(settings)
        try:
            self.network.connect()
        except BaseException:
            self.network.bus.shutdown()
            raise

    def close(self) -> None:
        if self.network.bus is not None:
            self.network.disconnect()

    def __enter__(self) -> CanopenNetwork:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()
