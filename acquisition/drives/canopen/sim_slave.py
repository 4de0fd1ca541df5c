"""The CiA 301 side of a simulated CANopen device, on its own canopen network (its own python-can bus).

canopen's ``LocalNode`` gives the SDO server, NMT (boot-up, pre-operational, operational), the heartbeat
producer (0x1017) and emergency messages; SYNC handling and PDOs are this module's: the RPDOs and TPDOs
are decoded and encoded per whatever mapping the master wrote into 0x1400…/0x1600…/0x1800…/0x1A00…
(mapping changes are refused in OPERATIONAL, for objects that cannot be mapped, beyond 64 bits, or while
the PDO is valid, with the standard abort codes). The objects the device lives on (its process image)
are read and written by SDO and PDO alike; the others keep the value written, or their default.

What the device does with them is its profile's (:class:`DeviceProfile`; the CiA 402 drive of
:mod:`.sim_drive`): it checks and takes writes, samples on each SYNC before the synchronous RPDOs are
applied, reacts once they are, and runs its cycle after the TPDOs are sent. A silent slave's transmitter
is dead (no TPDOs, heartbeat, SDO answers or emergencies); it still hears the master.
"""

from __future__ import annotations

import logging
import struct
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Protocol

import canopen
from canopen.objectdictionary import ObjectDictionary
from canopen.sdo import SdoAbortedError

from .config import CanSettings
from .network import CanopenNetwork
from .objects import DEVICE_TYPE, HEARTBEAT_TIME, PDO_VALID_BIT, SYNC_COB_ID, Direction, Entry

log = logging.getLogger("axisflow.acquisition.drives.canopen.sim_drive")  # the simulated drive's log

_PDO_CONFIG = range(0x1400, 0x1C00)
ABORT_RANGE = 0x06090030
"""SDO abort: value of parameter written too high or too low"""
_ABORT_UNSUPPORTED = 0x06010000
_ABORT_NOT_MAPPABLE = 0x06040041
_ABORT_PDO_LENGTH = 0x06040042
_ABORT_LOCAL_CONTROL = 0x08000022
ABORT_READ_ONLY = 0x06010002
"""SDO abort: attempt to write a read-only object"""


class DeviceProfile(Protocol):
    """What a device profile does with its slave's objects and SYNCs."""

    def check_write(self, entry: Entry, value: int) -> None:
        """An SDO write of ``value`` to ``entry``, before it is taken (raise SdoAbortedError to refuse)."""

    def written(self, entries: tuple[Entry, ...]) -> None:
        """``entries`` of the process image were written (an SDO, or an asynchronous RPDO)."""

    def sample(self) -> None:
        """A SYNC came: measure (before the synchronous RPDOs apply; the TPDOs carry what it set)."""

    def latched(self) -> None:
        """The SYNC's synchronous RPDOs were applied to the process image."""

    def cycle(self) -> None:
        """The TPDOs of the SYNC were sent: run until the next SYNC."""


class _SlaveNetwork(canopen.Network):
    """The slave's network; its transmitter can be cut (a silent slave) — ``send_message`` is the
    documented point to override, and the heartbeat task is stopped alongside."""

    silent = False
    NOTIFIER_CYCLE = 0.1
    """the longest the receive thread waits for a frame before it looks whether it is stopped [s]: a
    drive whose master is gone (no SYNC, no SDO) closes within it, not within canopen's 1 s"""

    def send_message(self, can_id: int, data: bytes, remote: bool = False) -> None:
        if not self.silent:
            super().send_message(can_id, data, remote)


@dataclass(frozen=True)
class _Map:
    """One valid PDO as the master mapped it."""

    cob_id: int
    transmission: int
    entries: tuple[Entry, ...]
    struct: struct.Struct


class SimulatedSlave:
    """A CiA 301 slave with node id ``node_id`` on the bus ``can``, its object ``dictionary`` and the
    ``entries`` it knows; ``live`` are the objects of its process image (:attr:`image`), ``profile``
    what the device does with them."""

    def __init__(
        self,
        can: CanSettings,
        node_id: int,
        dictionary: ObjectDictionary,
        entries: Iterable[Entry],
        live: Iterable[Entry],
        profile: DeviceProfile,
    ) -> None:
        self.can, self.node_id, self.dictionary = can, node_id, dictionary
        self._profile = profile
        self._entries = {(e.index, e.subindex): e for e in entries}
        self.image: dict[Entry, int] = {e: 0 for e in live}
        """the process image: what SDO and PDO read and write"""
        self._settings_values: dict[Entry, int] = {}
        self._latched: dict[Entry, int] = {}
        self._rx: dict[int, _Map] = {}
        self._tx: list[_Map] = []
        self._maps_stale = True
        self._syncs = 0
        self._heartbeat_ms = 0
        self._network: CanopenNetwork | None = None
        self.node: canopen.LocalNode | None = None

    # ---- set-up ----------------------------------------------------------------------------------------
    def start(self) -> None:
        """Connect, send the boot-up message, enter pre-operational."""
        network = _SlaveNetwork()
        self._network = CanopenNetwork(self.can, network)
        node = canopen.LocalNode(self.node_id, self.dictionary)
        network.add_node(node)
        self.node = node
        node.add_read_callback(self._on_read)
        node.add_write_callback(self._on_write)
        network.subscribe(SYNC_COB_ID, self._on_sync)
        node.nmt.send_command(0x81)  # reset node: boot-up message
        node.nmt.send_command(0x80)  # enter pre-operational (heartbeat per 0x1017)

    def close(self) -> None:
        if self.node is not None:
            self.node.nmt.stop_heartbeat()
        if self._network is not None:
            self._network.close()
            self._network = None

    @property
    def operational(self) -> bool:
        return self.node is not None and self.node.nmt.state == "OPERATIONAL"

    def setting(self, entry: Entry) -> int:
        """The value of an object outside the process image: as written, else its default."""
        value = self._settings_values.get(entry)
        if value is None:
            value = self._settings_values[entry] = int(
                self.dictionary.get_variable(entry.index, entry.subindex).default
            )
        return value

    def set_silent(self, silent: bool) -> None:
        """Cut the transmitter (no TPDOs, heartbeat, SDO answers or emergencies), or bring it back."""
        assert self._network is not None and self.node is not None
        network = self._network.network
        assert isinstance(network, _SlaveNetwork)
        network.silent = silent
        if silent:
            self.node.nmt.stop_heartbeat()
        elif self._heartbeat_ms:
            self.node.nmt.start_heartbeat(self._heartbeat_ms)
        log.warning("simulated drive node %d %s", self.node_id, "falls silent" if silent else "speaks again")

    # ---- SDO access (the network's thread) ------------------------------------------------------------
    def _on_read(self, index: int, subindex: int, od: object) -> int | None:
        entry = self._entries.get((index, subindex))
        return self.image.get(entry) if entry is not None else None

    def _on_write(self, index: int, subindex: int, od: object, data: bytes) -> None:
        if index in _PDO_CONFIG:
            self._check_pdo_write(index, subindex, data)
            self._maps_stale = True
            return
        entry = self._entries.get((index, subindex))
        if entry is None:
            return
        value = entry.unpack(data)
        if entry is HEARTBEAT_TIME:
            self._heartbeat_ms = value  # (NMT starts the producer itself on this write)
        elif entry is DEVICE_TYPE:
            raise SdoAbortedError(ABORT_READ_ONLY)
        self._profile.check_write(entry, value)
        if entry in self.image:
            self.image[entry] = value
            self._profile.written((entry,))
        else:
            self._settings_values[entry] = value

    # ---- PDO configuration -----------------------------------------------------------------------------
    def _stored(self, index: int, subindex: int) -> int:
        var = self.dictionary.get_variable(index, subindex)
        assert self.node is not None and var is not None
        raw = self.node.data_store.get(index, {}).get(subindex)
        return int(var.decode_raw(raw)) if raw is not None else int(var.default)

    def _check_pdo_write(self, index: int, subindex: int, data: bytes) -> None:
        if self.operational:
            raise SdoAbortedError(_ABORT_LOCAL_CONTROL)  # PDOs are mapped in pre-operational
        is_mapping = 0x1600 <= index < 0x1800 or 0x1A00 <= index < 0x1C00
        if not is_mapping:
            return
        communication = index - 0x200
        valid = not self._stored(communication, 1) & PDO_VALID_BIT
        value = int.from_bytes(data, "little")
        if subindex == 0:
            bits = sum(self._stored(index, sub) & 0xFF for sub in range(1, value + 1))
            if value > 8 or bits > 64:
                raise SdoAbortedError(_ABORT_PDO_LENGTH)
            return
        if valid or self._stored(index, 0) != 0:
            raise SdoAbortedError(_ABORT_UNSUPPORTED)  # CiA 301: disable the PDO and clear sub 0 first
        entry = self._entries.get((value >> 16, (value >> 8) & 0xFF))
        if entry is None or not entry.pdo_mappable or entry.type.bits != value & 0xFF:
            raise SdoAbortedError(_ABORT_NOT_MAPPABLE)
        receive = index < 0x1800
        if receive and entry.access.value == "ro":
            raise SdoAbortedError(_ABORT_NOT_MAPPABLE)

    def _rebuild_maps(self) -> None:
        assert self._network is not None
        network = self._network.network
        for cob_id in self._rx:
            network.unsubscribe(cob_id, self._on_rpdo)
        self._rx, self._tx = {}, []
        for direction in Direction:
            for number in range(1, 5):
                com = (0x1400 if direction is Direction.RX else 0x1800) + number - 1
                mapping = com + 0x200
                cob = self._stored(com, 1)
                if cob & PDO_VALID_BIT:
                    continue
                count = self._stored(mapping, 0)
                entries = []
                for sub in range(1, count + 1):
                    value = self._stored(mapping, sub)
                    entries.append(self._entries[(value >> 16, (value >> 8) & 0xFF)])
                fmt = "<" + "".join(e.type.fmt for e in entries)
                pdo = _Map(cob & 0x7FF, self._stored(com, 2), tuple(entries), struct.Struct(fmt))
                if direction is Direction.RX:
                    self._rx[pdo.cob_id] = pdo
                    network.subscribe(pdo.cob_id, self._on_rpdo)
                else:
                    self._tx.append(pdo)
        self._maps_stale = False

    # ---- process data ----------------------------------------------------------------------------------
    def _on_rpdo(self, cob_id: int, data: bytearray, _stamp: float) -> None:
        pdo = self._rx.get(cob_id)
        if pdo is None or not self.operational or len(data) < pdo.struct.size:
            return
        values = pdo.struct.unpack_from(bytes(data))
        synchronous = pdo.transmission <= 240
        for entry, value in zip(pdo.entries, values, strict=True):
            if synchronous:
                self._latched[entry] = value
            else:
                self.image[entry] = value
        if not synchronous:
            self._profile.written(pdo.entries)

    def _on_sync(self, _cob: int, _data: bytearray, _stamp: float) -> None:
        if not self.operational:
            return
        if self._maps_stale:
            self._rebuild_maps()
        self._syncs += 1
        self._profile.sample()
        self.image.update(self._latched)
        self._latched.clear()
        self._profile.latched()
        self._transmit()
        self._profile.cycle()

    def _transmit(self) -> None:
        assert self._network is not None
        send = self._network.network.send_message
        for pdo in self._tx:
            if pdo.transmission == 0 or pdo.transmission > 240 or self._syncs % pdo.transmission:
                continue
            send(pdo.cob_id, pdo.struct.pack(*(self.image[e] for e in pdo.entries)))
