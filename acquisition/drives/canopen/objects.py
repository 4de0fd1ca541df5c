"""The objects of a CiA 402 drive that axisflow uses: index, sub-index, type, unit and why.

Only standard objects (CiA 301 communication profile, CiA 402 drive profile) are used, so any CiA 402
servo drive serves. :data:`MANDATORY` objects must exist (an EDS file lacking one is refused, naming
it); :data:`OPTIONAL` ones are written when the drive has them and reported when it has not.

Process data (:data:`RPDOS`, :data:`TPDOS`): the master writes these maps into 0x1600…/0x1A00… at
every start-up (never relying on a factory mapping), transmission type 1 (every SYNC):

=========  =========  ===========================================================  =====
PDO        COB-ID     contents (bits)                                               bytes
=========  =========  ===========================================================  =====
RPDO 1     0x200+id   controlword 0x6040 (16), target position 0x607A (32),          8
                      torque offset 0x60B2 (16)
RPDO 2     0x300+id   velocity offset 0x60B1 (32)                                    4
TPDO 1     0x180+id   statusword 0x6041 (16), position actual 0x6064 (32),           8
                      torque actual 0x6077 (16)
TPDO 2     0x280+id   velocity actual 0x606C (32)                                    4
=========  =========  ===========================================================  =====

TPDO 1 holds everything identification needs from one instant (position and torque with the state
they were measured in), so a lost TPDO 2 costs the velocity of one sample, nothing more.
:func:`frame_bits` gives the length of these frames on the wire (docs/drives.md: bus load).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from enum import Enum

from canopen import objectdictionary as od
from canopen.objectdictionary import ObjectDictionary, ODRecord, ODVariable


class Access(Enum):
    RO = "ro"
    RW = "rw"
    CONST = "const"


@dataclass(frozen=True)
class DataType:
    """A CiA 301 basic data type: its code, its little-endian struct format and its length in bits."""

    code: int
    fmt: str
    name: str

    @property
    def bits(self) -> int:
        return 8 * struct.calcsize("<" + self.fmt)

    @property
    def struct(self) -> struct.Struct:
        return struct.Struct("<" + self.fmt)


U8 = DataType(od.UNSIGNED8, "B", "UNSIGNED8")
U16 = DataType(od.UNSIGNED16, "H", "UNSIGNED16")
U32 = DataType(od.UNSIGNED32, "I", "UNSIGNED32")
I8 = DataType(od.INTEGER8, "b", "INTEGER8")
I16 = DataType(od.INTEGER16, "h", "INTEGER16")
I32 = DataType(od.INTEGER32, "i", "INTEGER32")
TEXT = DataType(od.VISIBLE_STRING, "", "VISIBLE_STRING")
"""a string (read as bytes, no fixed length)"""


@dataclass(frozen=True)
class Entry:
    """One object (or sub-object) of the dictionary, as axisflow uses it."""

    index: int
    subindex: int
    name: str
    type: DataType
    access: Access
    unit: str
    why: str
    pdo_mappable: bool = False

    @property
    def address(self) -> str:
        """``0x6064`` or ``0x1018:2``."""
        return f"0x{self.index:04X}" if self.subindex == 0 else f"0x{self.index:04X}:{self.subindex}"

    def describe(self) -> str:
        """``0x6064 position actual value (INTEGER32, counts)``."""
        unit = f", {self.unit}" if self.unit else ""
        return f"{self.address} {self.name} ({self.type.name}{unit})"

    def pack(self, value: int) -> bytes:
        return self.type.struct.pack(value)

    def unpack(self, data: bytes) -> int:
        return int(self.type.struct.unpack(bytes(data[: self.type.struct.size]))[0])


# ---- CiA 301 communication objects -----------------------------------------------------------------
DEVICE_TYPE = Entry(
    0x1000,
    0,
    "device type",
    U32,
    Access.RO,
    "",
    "bits 0–15 name the device profile: 402 (0x0192) for a drive; checked first",
)
ERROR_REGISTER = Entry(
    0x1001,
    0,
    "error register",
    U8,
    Access.RO,
    "bit field",
    "which class of error is active (also in every emergency message)",
)
COMM_CYCLE_PERIOD = Entry(
    0x1006,
    0,
    "communication cycle period",
    U32,
    Access.RW,
    "µs",
    "the SYNC period, for the drive's own SYNC monitoring",
)
DEVICE_NAME = Entry(
    0x1008,
    0,
    "manufacturer device name",
    TEXT,
    Access.CONST,
    "",
    "printed at start-up",
)
HEARTBEAT_TIME = Entry(
    0x1017,
    0,
    "producer heartbeat time",
    U16,
    Access.RW,
    "ms",
    "the drive's heartbeat period; the bridge watches it (comm lost)",
)
VENDOR_ID = Entry(0x1018, 1, "vendor-ID", U32, Access.RO, "", "identity, printed at start-up")
PRODUCT_CODE = Entry(0x1018, 2, "product code", U32, Access.RO, "", "identity, printed at start-up")
REVISION = Entry(0x1018, 3, "revision number", U32, Access.RO, "", "identity, printed at start-up")
SERIAL = Entry(0x1018, 4, "serial number", U32, Access.RO, "", "identity, printed at start-up")

# ---- CiA 402 drive objects ---------------------------------------------------------------------------
ERROR_CODE = Entry(
    0x603F,
    0,
    "error code",
    U16,
    Access.RO,
    "",
    "the code of the active fault (read when a fault comes without an emergency message)",
)
CONTROLWORD = Entry(
    0x6040,
    0,
    "controlword",
    U16,
    Access.RW,
    "bit field",
    "commands the state machine (enable, quick stop, fault reset)",
    True,
)
STATUSWORD = Entry(
    0x6041,
    0,
    "statusword",
    U16,
    Access.RO,
    "bit field",
    "the state machine's state, warning and following-error bits",
    True,
)
QUICK_STOP_OPTION = Entry(
    0x605A,
    0,
    "quick stop option code",
    I16,
    Access.RW,
    "",
    "how the drive's own quick stop brakes and where it ends",
)
FAULT_REACTION = Entry(
    0x605E, 0, "fault reaction option code", I16, Access.RW, "", "how the drive brakes on a fault (optional)"
)
MODES_OF_OPERATION = Entry(
    0x6060, 0, "modes of operation", I8, Access.RW, "", "set to 8: cyclic synchronous position (CSP)"
)
MODES_DISPLAY = Entry(
    0x6061, 0, "modes of operation display", I8, Access.RO, "", "read back: the drive really is in CSP"
)
POSITION_ACTUAL = Entry(
    0x6064, 0, "position actual value", I32, Access.RO, "counts", "the sample's position", True
)
FOLLOWING_ERROR_WINDOW = Entry(
    0x6065,
    0,
    "following error window",
    U32,
    Access.RW,
    "counts",
    "the drive faults when it lags its target by more (optional)",
)
FOLLOWING_ERROR_TIMEOUT = Entry(
    0x6066, 0, "following error time out", U16, Access.RW, "ms", "for longer than this (optional)"
)
VELOCITY_ACTUAL = Entry(
    0x606C,
    0,
    "velocity actual value",
    I32,
    Access.RO,
    "counts/s",
    "the sample's velocity (the drive's own estimate)",
    True,
)
RATED_TORQUE = Entry(
    0x6076,
    0,
    "motor rated torque",
    U32,
    Access.RW,
    "mN·m",
    "the scale of every torque object (per mille of it)",
)
TORQUE_ACTUAL = Entry(
    0x6077,
    0,
    "torque actual value",
    I16,
    Access.RO,
    "per mille of rated torque",
    "the sample's motor torque (what identification fits)",
    True,
)
TARGET_POSITION = Entry(
    0x607A, 0, "target position", I32, Access.RW, "counts", "the setpoint's position, every SYNC", True
)
SOFTWARE_LIMIT_MIN = Entry(
    0x607D,
    1,
    "min position limit",
    I32,
    Access.RW,
    "counts",
    "the stroke's end in counts: the drive refuses targets beyond (optional)",
)
SOFTWARE_LIMIT_MAX = Entry(
    0x607D, 2, "max position limit", I32, Access.RW, "counts", "the stroke's other end (optional)"
)
QUICK_STOP_DECELERATION = Entry(
    0x6085,
    0,
    "quick stop deceleration",
    U32,
    Access.RW,
    "counts/s²",
    "the ramp of the drive's own quick stop (optional)",
)
VELOCITY_OFFSET = Entry(
    0x60B1,
    0,
    "velocity offset",
    I32,
    Access.RW,
    "counts/s",
    "the setpoint's velocity: feed-forward for the drive's velocity loop",
    True,
)
TORQUE_OFFSET = Entry(
    0x60B2,
    0,
    "torque offset",
    I16,
    Access.RW,
    "per mille of rated torque",
    "the plan's feed-forward torque (eq. (1) with the nominal parameters)",
    True,
)
INTERPOLATION_PERIOD = Entry(
    0x60C2,
    1,
    "interpolation time period value",
    U8,
    Access.RW,
    "",
    "the SYNC period in units of 10^index s: the drive interpolates over it",
)
INTERPOLATION_INDEX = Entry(
    0x60C2, 2, "interpolation time index", I8, Access.RW, "", "−3: the period value is in ms (optional)"
)
SUPPORTED_MODES = Entry(
    0x6502,
    0,
    "supported drive modes",
    U32,
    Access.RO,
    "bit field",
    "bit 7: CSP; a drive without it is refused (optional)",
)

MANDATORY: tuple[Entry, ...] = (
    DEVICE_TYPE,
    ERROR_REGISTER,
    HEARTBEAT_TIME,
    VENDOR_ID,
    ERROR_CODE,
    CONTROLWORD,
    STATUSWORD,
    QUICK_STOP_OPTION,
    MODES_OF_OPERATION,
    MODES_DISPLAY,
    POSITION_ACTUAL,
    VELOCITY_ACTUAL,
    RATED_TORQUE,
    TORQUE_ACTUAL,
    TARGET_POSITION,
    VELOCITY_OFFSET,
    TORQUE_OFFSET,
)
"""the objects without which axisflow cannot run a drive (besides the PDO parameters below)"""
OPTIONAL: tuple[Entry, ...] = (
    COMM_CYCLE_PERIOD,
    DEVICE_NAME,
    PRODUCT_CODE,
    REVISION,
    SERIAL,
    FAULT_REACTION,
    FOLLOWING_ERROR_WINDOW,
    FOLLOWING_ERROR_TIMEOUT,
    SOFTWARE_LIMIT_MIN,
    SOFTWARE_LIMIT_MAX,
    QUICK_STOP_DECELERATION,
    INTERPOLATION_PERIOD,
    INTERPOLATION_INDEX,
    SUPPORTED_MODES,
)
"""objects written or read when the drive has them; their absence is reported, not refused"""

PROFILE_402 = 402
"""device type 0x1000 bits 0–15 of a CiA 402 drive"""
MODE_CSP = 8
"""0x6060 value: cyclic synchronous position mode"""
SUPPORTED_CSP_BIT = 1 << 7
"""0x6502 bit of CSP"""
NMT_OPERATIONAL = 5
"""the NMT state a heartbeat reports while process data flows"""


# ---- process data ----------------------------------------------------------------------------------
class Direction(Enum):
    RX = "rx"
    """received by the drive (master → drive)"""
    TX = "tx"
    """transmitted by the drive (drive → master)"""


PDO_VALID_BIT = 1 << 31
"""COB-ID bit 31 set: the PDO does not exist (is disabled)"""
PDO_NO_RTR_BIT = 1 << 30
"""COB-ID bit 30 set: no remote transmission request allowed"""
SYNC_EVERY_CYCLE = 1
"""transmission type 1: synchronous, every SYNC"""
SYNC_COB_ID = 0x080
EMCY_COB_BASE = 0x080
HEARTBEAT_COB_BASE = 0x700


@dataclass(frozen=True)
class PdoLayout:
    """One PDO: its number (1–4 of the predefined connection set), direction and mapped objects."""

    number: int
    direction: Direction
    entries: tuple[Entry, ...]

    @property
    def communication_index(self) -> int:
        """0x1400 + n − 1 (RPDO) or 0x1800 + n − 1 (TPDO)."""
        return (0x1400 if self.direction is Direction.RX else 0x1800) + self.number - 1

    @property
    def mapping_index(self) -> int:
        """0x1600 + n − 1 (RPDO) or 0x1A00 + n − 1 (TPDO)."""
        return (0x1600 if self.direction is Direction.RX else 0x1A00) + self.number - 1

    def cob_id(self, node_id: int) -> int:
        """Predefined connection set: TPDO n at 0x080 + n·0x100 + id, RPDO n at 0x100 + n·0x100 + id."""
        base = 0x080 if self.direction is Direction.TX else 0x100
        return base + self.number * 0x100 + node_id

    @property
    def struct(self) -> struct.Struct:
        return struct.Struct("<" + "".join(e.type.fmt for e in self.entries))

    @property
    def size(self) -> int:
        """Data bytes of the frame."""
        return self.struct.size

    def mapping_values(self) -> list[int]:
        """The 0x1600/0x1A00 sub-entries: index << 16 | sub-index << 8 | bits."""
        return [e.index << 16 | e.subindex << 8 | e.type.bits for e in self.entries]


RPDOS: tuple[PdoLayout, ...] = (
    PdoLayout(1, Direction.RX, (CONTROLWORD, TARGET_POSITION, TORQUE_OFFSET)),
    PdoLayout(2, Direction.RX, (VELOCITY_OFFSET,)),
)
TPDOS: tuple[PdoLayout, ...] = (
    PdoLayout(1, Direction.TX, (STATUSWORD, POSITION_ACTUAL, TORQUE_ACTUAL)),
    PdoLayout(2, Direction.TX, (VELOCITY_ACTUAL,)),
)


def frame_bits(data_bytes: int, worst_case: bool = False) -> int:
    """Bits a CAN 2.0A frame with ``data_bytes`` bytes occupies on the bus, the 3-bit interframe space
    included: 47 + 8·n, plus at most ⌊(34 + 8·n − 1)/4⌋ stuff bits in the worst case (bit stuffing
    applies from the start of frame through the CRC, 34 + 8·n bits)."""
    if not 0 <= data_bytes <= 8:
        raise ValueError(f"a classic CAN frame has 0…8 data bytes, not {data_bytes}")
    bits = 47 + 8 * data_bytes
    return bits + (34 + 8 * data_bytes - 1) // 4 if worst_case else bits


def bits_per_cycle(drives: int, worst_case: bool = False) -> int:
    """Bus bits of one cycle of ``drives`` drives: one SYNC, and each drive's RPDOs and TPDOs."""
    per_drive = sum(frame_bits(p.size, worst_case) for p in (*RPDOS, *TPDOS))
    return frame_bits(0, worst_case) + drives * per_drive


# ---- the dictionary of a drive -----------------------------------------------------------------------
def _variable(entry: Entry, default: int | bytes | None) -> ODVariable:
    var = ODVariable(entry.name, entry.index, entry.subindex)
    var.data_type = entry.type.code
    var.access_type = entry.access.value
    var.unit = entry.unit
    var.description = entry.why
    var.pdo_mappable = entry.pdo_mappable
    var.default = default
    return var


def _plain(
    name: str, index: int, subindex: int, dtype: DataType, default: int, access: str = "rw"
) -> ODVariable:
    var = ODVariable(name, index, subindex)
    var.data_type, var.access_type, var.default = dtype.code, access, default
    return var


def _pdo_records(dictionary: ObjectDictionary, layouts: tuple[PdoLayout, ...], node_id: int) -> None:
    for layout in layouts:
        kind = "RPDO" if layout.direction is Direction.RX else "TPDO"
        com = ODRecord(f"{kind} {layout.number} communication parameter", layout.communication_index)
        com.add_member(_plain("highest sub-index", layout.communication_index, 0, U8, 5, "const"))
        com.add_member(_plain("COB-ID", layout.communication_index, 1, U32, layout.cob_id(node_id)))
        com.add_member(_plain("transmission type", layout.communication_index, 2, U8, 255))
        com.add_member(_plain("inhibit time", layout.communication_index, 3, U16, 0))
        com.add_member(_plain("event timer", layout.communication_index, 5, U16, 0))
        dictionary.add_object(com)
        mapping = ODRecord(f"{kind} {layout.number} mapping parameter", layout.mapping_index)
        mapping.add_member(_plain("number of mapped objects", layout.mapping_index, 0, U8, 0))
        for sub in range(1, 9):
            mapping.add_member(_plain(f"mapped object {sub}", layout.mapping_index, sub, U32, 0))
        dictionary.add_object(mapping)


def drive_dictionary(
    node_id: int, defaults: dict[Entry, int | bytes], leave_out: tuple[Entry, ...] = ()
) -> ObjectDictionary:
    """The dictionary of a CiA 402 drive with every object of :data:`MANDATORY` and :data:`OPTIONAL`
    (except ``leave_out``), four RPDOs and four TPDOs (disabled, unmapped: a factory state a master
    must overwrite) and the ``defaults`` given; what the simulated drive serves, and what a test
    exports as an EDS file."""
    dictionary = ObjectDictionary()
    dictionary.node_id = node_id
    records: dict[int, ODRecord] = {}
    for entry in (*MANDATORY, *OPTIONAL):
        if entry in leave_out:
            continue
        var = _variable(entry, defaults.get(entry))
        if entry.index in (0x1018, 0x607D, 0x60C2):
            record = records.get(entry.index)
            if record is None:
                names = {
                    0x1018: "identity object",
                    0x607D: "software position limit",
                    0x60C2: "interpolation time period",
                }
                record = records[entry.index] = ODRecord(names[entry.index], entry.index)
                count = {0x1018: 4, 0x607D: 2, 0x60C2: 2}[entry.index]
                record.add_member(_plain("highest sub-index", entry.index, 0, U8, count, "const"))
                dictionary.add_object(record)
            record.add_member(var)
        else:
            dictionary.add_object(var)
    layouts = tuple(PdoLayout(n, d, ()) for d in Direction for n in range(1, 5))
    _pdo_records(dictionary, layouts, node_id)
    return dictionary


def missing_objects(dictionary: ObjectDictionary) -> list[Entry]:
    """The :data:`MANDATORY` objects (and PDO parameters of :data:`RPDOS`/:data:`TPDOS`) that
    ``dictionary`` (an EDS file's) lacks, in the order of the tables."""
    missing = [e for e in MANDATORY if dictionary.get_variable(e.index, e.subindex) is None]
    for layout in (*RPDOS, *TPDOS):
        for index, name in ((layout.communication_index, "communication"), (layout.mapping_index, "mapping")):
            if index not in dictionary:
                kind = "RPDO" if layout.direction is Direction.RX else "TPDO"
                missing.append(
                    Entry(
                        index,
                        0,
                        f"{kind} {layout.number} {name} parameter",
                        U32,
                        Access.RW,
                        "",
                        "the process data axisflow maps",
                    )
                )
    return missing
