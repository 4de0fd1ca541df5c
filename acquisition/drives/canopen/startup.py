"""The master's start-up of one CiA 402 drive over SDO and NMT, as every CANopen master does it.

1. the object dictionary: the drive's EDS file if given (it must hold every object axisflow needs,
   :func:`~.objects.missing_objects`), else none (only standard objects are used);
2. device type 0x1000: profile 402, else refused; identity 0x1018 (and 0x1008) printed;
3. NMT enter pre-operational (a drive takes new PDO maps only there);
4. statusword 0x6041: a drive already in fault is refused with its code (0x603F) and how to reset it,
   unless the reset was asked for;
5. supported modes 0x6502 (bit 7, CSP) where the drive has the object; motor rated torque 0x6076
   (the scale of the per-mille torques, > 0);
6. the process data maps (:data:`~.objects.RPDOS`, :data:`~.objects.TPDOS`), written by the CiA 301
   sequence — disable the PDO (COB-ID bit 31), transmission type 1, clear the map, the entries, their
   count, enable — and RPDO/TPDO 3–4 disabled, so no factory mapping stays on the bus;
7. modes of operation 0x6060 = 8 (CSP), read back from 0x6061; quick stop option 0x605A; and where the
   drive has them: fault reaction 0x605E (quick-stop ramp), quick stop deceleration 0x6085,
   following error window and time out 0x6065/0x6066, software position limits 0x607D (the stroke
   [0, L]), interpolation period 0x60C2 and communication cycle period 0x1006 (the SYNC period);
8. producer heartbeat 0x1017, then a heartbeat is awaited; NMT start, and a heartbeat reporting
   OPERATIONAL is awaited.

Enabling (the 402 state machine walk to operation enabled) needs the SYNC cycle and is done by
:meth:`~.cycle.SyncCycle.enable`. Every SDO is tried ``3`` times with ``sdo_timeout_ms`` each, so a
node that does not answer is named within about a second.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import canopen
from canopen.objectdictionary import ObjectDictionary
from canopen.sdo import SdoAbortedError, SdoCommunicationError

from ....model import AxisParams
from ....model.braking import QUICK_STOP_FORCE, braking_acceleration
from ....model.drive_units import DriveUnits
from ...errors import DriveConfigError, DriveError
from .cia402 import State, state_of
from .config import CanSettings, DriveConfig, DriveSettings
from .emergency import describe_code
from .objects import (
    COMM_CYCLE_PERIOD,
    DEVICE_NAME,
    DEVICE_TYPE,
    ERROR_CODE,
    ERROR_REGISTER,
    FAULT_REACTION,
    FOLLOWING_ERROR_TIMEOUT,
    FOLLOWING_ERROR_WINDOW,
    HEARTBEAT_TIME,
    INTERPOLATION_INDEX,
    INTERPOLATION_PERIOD,
    MODE_CSP,
    MODES_DISPLAY,
    MODES_OF_OPERATION,
    PDO_NO_RTR_BIT,
    PDO_VALID_BIT,
    PRODUCT_CODE,
    PROFILE_402,
    QUICK_STOP_DECELERATION,
    QUICK_STOP_OPTION,
    RATED_TORQUE,
    REVISION,
    RPDOS,
    SERIAL,
    SOFTWARE_LIMIT_MAX,
    SOFTWARE_LIMIT_MIN,
    STATUSWORD,
    SUPPORTED_CSP_BIT,
    SUPPORTED_MODES,
    SYNC_EVERY_CYCLE,
    TPDOS,
    VENDOR_ID,
    Direction,
    Entry,
    PdoLayout,
    missing_objects,
)

log = logging.getLogger(__name__)

SDO_ATTEMPTS = 3
MODE_TIMEOUT_S = 1.0
"""how long the drive may take to show CSP in 0x6061"""
FAULT_REACTION_QUICK_STOP_RAMP = 2
_ABSENT = {0x06020000, 0x06090011}
"""SDO abort codes: the object / the sub-index does not exist"""


@dataclass(frozen=True)
class DriveInfo:
    """What the start-up learnt about a drive."""

    node_id: int
    device_type: int
    vendor_id: int
    product_code: int | None
    revision: int | None
    serial: int | None
    device_name: str
    rated_torque_nm: float
    absent: tuple[Entry, ...]
    """optional objects the drive does not have"""

    def describe(self) -> str:
        parts = [f"vendor 0x{self.vendor_id:08X}"]
        for label, value in (
            ("product", self.product_code),
            ("revision", self.revision),
            ("serial", self.serial),
        ):
            if value is not None:
                parts.append(f"{label} 0x{value:08X}")
        name = f" {self.device_name!r}" if self.device_name else ""
        return (
            f"node {self.node_id}{name}: CiA 402 drive (device type 0x{self.device_type:08X}), "
            f"{', '.join(parts)}; rated torque {self.rated_torque_nm:g} N·m"
        )


class _Sdo:
    """SDO reads and writes of the :mod:`.objects` entries, with errors that name the object."""

    def __init__(self, node: canopen.RemoteNode, drive: DriveSettings, can: CanSettings) -> None:
        self.node, self.drive, self.can = node, drive, can

    def read(self, entry: Entry) -> int:
        return entry.unpack(self.upload(entry))

    def upload(self, entry: Entry) -> bytes:
        try:
            return self.node.sdo.upload(entry.index, entry.subindex)
        except SdoCommunicationError:
            raise DriveError(self._silent(f"reading {entry.describe()}")) from None
        except SdoAbortedError as exc:
            raise DriveError(f"drive {self.drive.name} refused reading {entry.describe()}: {exc}") from None

    def write(self, entry: Entry, value: int) -> None:
        try:
            self.node.sdo.download(entry.index, entry.subindex, entry.pack(value))
        except SdoCommunicationError:
            raise DriveError(self._silent(f"writing {entry.describe()} = {value}")) from None
        except SdoAbortedError as exc:
            raise DriveError(f"drive {self.drive.name} refused {entry.describe()} = {value}: {exc}") from None

    def write_raw(self, index: int, subindex: int, data: bytes, what: str) -> None:
        try:
            self.node.sdo.download(index, subindex, data)
        except SdoCommunicationError:
            raise DriveError(self._silent(what)) from None
        except SdoAbortedError as exc:
            raise DriveError(f"drive {self.drive.name} refused {what}: {exc}") from None

    def optional(self, entry: Entry, value: int | None, absent: list[Entry]) -> int | None:
        """Write ``value`` (or read, if None) where the drive has the object; note it absent otherwise."""
        try:
            if value is None:
                return entry.unpack(self.node.sdo.upload(entry.index, entry.subindex))
            self.node.sdo.download(entry.index, entry.subindex, entry.pack(value))
            return value
        except SdoAbortedError as exc:
            if exc.code in _ABSENT:
                absent.append(entry)
                return None
            action = f"reading {entry.describe()}" if value is None else f"{entry.describe()} = {value}"
            raise DriveError(f"drive {self.drive.name} refused {action}: {exc}") from None
        except SdoCommunicationError:
            raise DriveError(self._silent(f"accessing {entry.describe()}")) from None

    def _silent(self, what: str) -> str:
        timeout = self.drive.sdo_timeout_ms
        return (
            f"no answer from drive {self.drive.name} on CAN interface {self.can.interface!r} channel "
            f"{self.can.channel!r} ({what}: no SDO response in {SDO_ATTEMPTS} × {timeout} ms): is a drive "
            f"with node id {self.drive.node_id} on this bus, powered, at the bus's bitrate?"
        )


def object_dictionary(drive: DriveSettings) -> ObjectDictionary:
    """The drive's EDS file (checked for every object axisflow needs), or an empty dictionary."""
    if drive.eds is None:
        return ObjectDictionary()
    if not drive.eds.is_file():
        raise DriveConfigError(f"EDS file {drive.eds} of drive {drive.name} does not exist")
    try:
        dictionary = canopen.import_od(str(drive.eds), drive.node_id)
    except Exception as exc:  # the EDS parser raises what its configparser and int() raise
        raise DriveConfigError(f"EDS file {drive.eds} of drive {drive.name} cannot be read: {exc}") from None
    missing = missing_objects(dictionary)
    if missing:
        shown = "; ".join(f"{e.describe()} — {e.why}" for e in missing)
        raise DriveConfigError(
            f"EDS file {drive.eds} of drive {drive.name} lacks what axisflow needs: {shown}"
        )
    return dictionary


def configure(
    network: canopen.Network,
    config: DriveConfig,
    drive: DriveSettings,
    params: AxisParams,
    allow_fault: bool = False,
) -> tuple[canopen.RemoteNode, DriveInfo, DriveUnits]:
    """Steps 1–8 of the module docstring for ``drive``; its node (added to ``network``), what was
    learnt, and its units. ``allow_fault``: a drive in fault is accepted (enabling resets it)."""
    node = canopen.RemoteNode(drive.node_id, object_dictionary(drive))
    network.add_node(node)
    node.sdo.RESPONSE_TIMEOUT = drive.sdo_timeout_ms / 1000.0
    node.sdo.MAX_RETRIES = SDO_ATTEMPTS
    sdo = _Sdo(node, drive, config.can)
    absent: list[Entry] = []
    device_type = sdo.read(DEVICE_TYPE)
    if device_type & 0xFFFF != PROFILE_402:
        raise DriveError(
            f"node {drive.node_id} is not a CiA 402 drive: its device type 0x{device_type:08X} names profile "
            f"{device_type & 0xFFFF} (0x1000 bits 0–15; a drive has {PROFILE_402})"
        )
    node.nmt.state = "PRE-OPERATIONAL"
    _check_not_in_fault(sdo, drive, allow_fault)
    supported = sdo.optional(SUPPORTED_MODES, None, absent)
    if supported is not None and not supported & SUPPORTED_CSP_BIT:
        raise DriveError(
            f"drive {drive.name} does not offer cyclic synchronous position mode: supported drive modes "
            f"0x6502 = 0x{supported:08X} lacks bit 7"
        )
    rated_mnm = sdo.read(RATED_TORQUE)
    if rated_mnm <= 0:
        raise DriveError(
            f"drive {drive.name}: 0x6076 motor rated torque = {rated_mnm} mN·m; set it in the drive"
        )
    units = DriveUnits.for_axis(
        params, drive.encoder_counts_per_rev, rated_mnm / 1000.0, drive.zero_counts, drive.direction
    )
    info = DriveInfo(
        node_id=drive.node_id,
        device_type=device_type,
        vendor_id=sdo.read(VENDOR_ID),
        product_code=sdo.optional(PRODUCT_CODE, None, absent),
        revision=sdo.optional(REVISION, None, absent),
        serial=sdo.optional(SERIAL, None, absent),
        device_name=_device_name(sdo, absent),
        rated_torque_nm=rated_mnm / 1000.0,
        absent=(),
    )
    for layout in (*RPDOS, *TPDOS):
        _map_pdo(sdo, layout, drive.node_id)
    for number in (3, 4):
        for direction in Direction:
            _disable_pdo(sdo, PdoLayout(number, direction, ()), drive.node_id)
    _set_mode(sdo, drive)
    _set_drive_objects(sdo, config, drive, params, units, absent)
    _start(node, sdo, drive)
    info = DriveInfo(**{**info.__dict__, "absent": tuple(absent)})
    if absent:
        log.warning(
            "drive %s lacks optional objects (not written: %s)",
            drive.name,
            ", ".join(e.address for e in absent),
        )
    return node, info, units


def _device_name(sdo: _Sdo, absent: list[Entry]) -> str:
    try:
        return sdo.node.sdo.upload(DEVICE_NAME.index, 0).decode("ascii", "replace").rstrip("\x00")
    except SdoAbortedError:
        absent.append(DEVICE_NAME)
        return ""
    except SdoCommunicationError:
        raise DriveError(sdo._silent(f"reading {DEVICE_NAME.describe()}")) from None


def fault_text(drive: DriveSettings, code: int, register: int, statusword: int) -> str:
    """How a drive found in fault at start-up is reported."""
    state = state_of(statusword)
    return (
        f"drive {drive.name} is in fault: {describe_code(code)} (error register 0x{register:02X}, "
        f"{state.value if state else 'statusword'} 0x{statusword:04X}); remove the cause, then start the "
        "bridge with --reset-fault (or reset it in the drive)"
    )


def _check_not_in_fault(sdo: _Sdo, drive: DriveSettings, allow_fault: bool) -> None:
    statusword = sdo.read(STATUSWORD)
    if state_of(statusword) not in (State.FAULT, State.FAULT_REACTION_ACTIVE):
        return
    code, register = sdo.read(ERROR_CODE), sdo.read(ERROR_REGISTER)
    if not allow_fault:
        raise DriveError(fault_text(drive, code, register, statusword))
    log.warning("drive %s is in fault %s: resetting it (--reset-fault)", drive.name, describe_code(code))


def _map_pdo(sdo: _Sdo, layout: PdoLayout, node_id: int) -> None:
    """The CiA 301 sequence: disable, transmission type, clear, entries, count, enable."""
    kind = "RPDO" if layout.direction is Direction.RX else "TPDO"
    com, mapping, cob = layout.communication_index, layout.mapping_index, layout.cob_id(node_id)
    flags = PDO_NO_RTR_BIT if layout.direction is Direction.TX else 0
    u8, u32 = (lambda v: v.to_bytes(1, "little")), (lambda v: v.to_bytes(4, "little"))
    what = f"mapping {kind} {layout.number}"
    sdo.write_raw(com, 1, u32(cob | flags | PDO_VALID_BIT), f"{what}: disabling it (0x{com:04X}:1)")
    sdo.write_raw(com, 2, u8(SYNC_EVERY_CYCLE), f"{what}: transmission type 1 (0x{com:04X}:2)")
    sdo.write_raw(mapping, 0, u8(0), f"{what}: clearing 0x{mapping:04X}")
    for sub, (entry, value) in enumerate(zip(layout.entries, layout.mapping_values(), strict=True), 1):
        sdo.write_raw(mapping, sub, u32(value), f"{what}: 0x{mapping:04X}:{sub} = {entry.describe()}")
    sdo.write_raw(
        mapping, 0, u8(len(layout.entries)), f"{what}: {len(layout.entries)} entries (0x{mapping:04X}:0)"
    )
    sdo.write_raw(com, 1, u32(cob | flags), f"{what}: enabling it at COB-ID 0x{cob:03X} (0x{com:04X}:1)")


def _disable_pdo(sdo: _Sdo, layout: PdoLayout, node_id: int) -> None:
    """Disable a PDO axisflow does not use (a factory mapping would load the bus); absent ones are fine."""
    cob = layout.cob_id(node_id) | PDO_VALID_BIT
    try:
        sdo.node.sdo.download(layout.communication_index, 1, cob.to_bytes(4, "little"))
    except SdoAbortedError as exc:
        if exc.code not in _ABSENT:
            kind = "RPDO" if layout.direction is Direction.RX else "TPDO"
            raise DriveError(
                f"drive {sdo.drive.name} refused disabling {kind} {layout.number}: {exc}"
            ) from None
    except SdoCommunicationError:
        raise DriveError(sdo._silent(f"disabling PDO 0x{layout.communication_index:04X}")) from None


def _set_mode(sdo: _Sdo, drive: DriveSettings) -> None:
    sdo.write(MODES_OF_OPERATION, MODE_CSP)
    deadline = time.monotonic() + MODE_TIMEOUT_S
    while (shown := sdo.read(MODES_DISPLAY)) != MODE_CSP:
        if time.monotonic() > deadline:
            raise DriveError(
                f"drive {drive.name} does not enter cyclic synchronous position mode: 0x6061 shows {shown} "
                f"{MODE_TIMEOUT_S:g} s after 0x6060 = {MODE_CSP}"
            )
        time.sleep(0.01)


def default_quick_stop_deceleration(params: AxisParams) -> float:
    """[m/s²] the deceleration the bridge's own quick stop is sure to reach: :data:`QUICK_STOP_FORCE` of
    the force limit with the friction at rest (friction only grows with speed)."""
    return -braking_acceleration(0.0, params, QUICK_STOP_FORCE)


def _set_drive_objects(
    sdo: _Sdo,
    config: DriveConfig,
    drive: DriveSettings,
    params: AxisParams,
    units: DriveUnits,
    absent: list[Entry],
) -> None:
    sdo.write(QUICK_STOP_OPTION, drive.quick_stop_option)
    sdo.optional(FAULT_REACTION, FAULT_REACTION_QUICK_STOP_RAMP, absent)
    deceleration = drive.quick_stop_deceleration_m_s2 or default_quick_stop_deceleration(params)
    sdo.optional(QUICK_STOP_DECELERATION, abs(units.counts_per_s2(deceleration)), absent)
    sdo.optional(FOLLOWING_ERROR_WINDOW, units.distance_counts(drive.following_error_window_m), absent)
    sdo.optional(FOLLOWING_ERROR_TIMEOUT, drive.following_error_timeout_ms, absent)
    low, high = sorted((units.counts(0.0), units.counts(params.L)))
    sdo.optional(SOFTWARE_LIMIT_MIN, low, absent)
    sdo.optional(SOFTWARE_LIMIT_MAX, high, absent)
    period_ms = 1000 // config.cycle_hz
    sdo.optional(INTERPOLATION_PERIOD, period_ms, absent)
    sdo.optional(INTERPOLATION_INDEX, -3, absent)
    sdo.optional(COMM_CYCLE_PERIOD, period_ms * 1000, absent)


def _start(node: canopen.RemoteNode, sdo: _Sdo, drive: DriveSettings) -> None:
    """Producer heartbeat, a heartbeat seen, NMT start, a heartbeat saying OPERATIONAL."""
    sdo.write(HEARTBEAT_TIME, drive.heartbeat_ms)
    timeout_s = drive.heartbeat_timeout_ms / 1000.0
    try:
        node.nmt.wait_for_heartbeat(timeout_s)
    except canopen.nmt.NmtError:
        raise DriveError(
            f"drive {drive.name} sends no heartbeat within {drive.heartbeat_timeout_ms} ms of 0x1017 = "
            f"{drive.heartbeat_ms} ms"
        ) from None
    node.nmt.state = "OPERATIONAL"
    deadline = time.monotonic() + timeout_s
    while True:
        try:
            state = node.nmt.wait_for_heartbeat(max(deadline - time.monotonic(), 0.001))
        except canopen.nmt.NmtError:
            state = None
        if state == "OPERATIONAL":
            return
        if time.monotonic() > deadline:
            raise DriveError(
                f"drive {drive.name} did not enter NMT OPERATIONAL within {drive.heartbeat_timeout_ms} ms "
                f"(its heartbeat says {state or 'nothing'})"
            )
