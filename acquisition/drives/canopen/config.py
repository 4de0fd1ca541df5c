"""The drive configuration file (``drive.toml``): the CAN bus and the CiA 402 drives on it.

::

    [can]
    interface = "socketcan"          # any python-can interface name
    channel = "can0"
    bitrate = 1000000                # optional [bit/s]; checks the bus load

    [drive]                          # one drive; [[drive]] tables for several on one bus
    node_id = 5
    cycle_hz = 1000                  # the bridge sends SYNC at this rate
    encoder_counts_per_rev = 131072  # motor-side counts per motor revolution

Every other key is optional (:data:`DRIVE_KEYS` lists them with their defaults, ranges and units);
an unknown key is refused by name, a value out of range with the range and its unit. With several
drives each ``[[drive]]`` names its ``axis`` (its Zenoh keys) and its ``node_id``; ``cycle_hz`` and
``pacing`` belong to the one SYNC that serves them all, so the drives that give them must agree. An
``eds`` path is taken relative to the configuration file.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from enum import Enum
from pathlib import Path
from typing import Any

from ....model.toml_file import read_toml
from ...errors import DriveConfigError
from .cia402 import QuickStopOption
from .objects import bits_per_cycle

DEFAULT_SIM_CONFIG_RESOURCE = "default_drive.toml"
"""the packaged configuration of ``--drive canopen-sim``: one simulated drive on an in-process bus"""
CYCLE_RATES_HZ = (100, 125, 200, 250, 500, 1000)
"""SYNC rates a bridge can serve: its 1 ms ticks divide evenly into the cycle"""


class Pacing(Enum):
    WALL = "wall"
    """SYNC on absolute deadlines of the wall clock; a drive's data that comes late is not waited for"""
    LOCKSTEP = "lockstep"
    """the next SYNC only once every drive's process data of the last one arrived (deterministic)"""


@dataclass(frozen=True)
class CanSettings:
    interface: str
    """python-can interface name (socketcan, pcan, kvaser, virtual, udp_multicast, …)"""
    channel: str
    bitrate: int | None = None
    """[bit/s]; None: the interface's own setting"""


@dataclass(frozen=True)
class DriveSettings:
    """One drive on the bus (defaults: :data:`DRIVE_KEYS`)."""

    node_id: int
    encoder_counts_per_rev: int
    axis: str | None = None
    """the axis name (its keys); None: the bridge's ``--axis``"""
    zero_counts: int = 0
    """the position count at x = 0: the drive's counts start wherever it was switched on or homed"""
    direction: int = 1
    """+1: the counts grow towards +x; −1: towards −x (the motor mounted the other way round)"""
    eds: Path | None = None
    heartbeat_ms: int = 100
    heartbeat_timeout_ms: int = 300
    pdo_timeout_ms: int = 100
    sdo_timeout_ms: int = 300
    following_error_window_m: float = 0.02
    """0x6065: the lag that faults the drive; the demo's minimum-time moves with the nominal (wrong by
    5–20 %) parameters lag up to ~6 mm at the torque limit (docs/drives.md)"""
    following_error_timeout_ms: int = 10
    quick_stop_option: int = QuickStopOption.QUICK_STOP_RAMP_STAY.value
    quick_stop_deceleration_m_s2: float | None = None
    """None: what the bridge's own quick stop is sure to reach with the nominal parameters"""

    def __post_init__(self) -> None:
        if self.heartbeat_timeout_ms <= self.heartbeat_ms:
            raise DriveConfigError(
                f"drive node {self.node_id}: heartbeat_timeout_ms = {self.heartbeat_timeout_ms} ms must be "
                f"longer than heartbeat_ms = {self.heartbeat_ms} ms (the drive's heartbeat period)"
            )

    @property
    def name(self) -> str:
        """``node 5 (axis a0)``: how messages name the drive."""
        return f"node {self.node_id}" + (f" (axis {self.axis})" if self.axis else "")


@dataclass(frozen=True)
class DriveConfig:
    """A validated ``drive.toml``."""

    can: CanSettings
    drives: tuple[DriveSettings, ...]
    cycle_hz: int = 1000
    pacing: Pacing = Pacing.WALL
    source: str = "drive configuration"

    @property
    def ticks_per_cycle(self) -> int:
        """Bridge ticks (1 ms) per SYNC."""
        return 1000 // self.cycle_hz

    def bus_load(self, worst_case: bool = True) -> float | None:
        """The share of the bus the cycle takes (None without a bitrate); see :func:`bits_per_cycle`."""
        if self.can.bitrate is None:
            return None
        return bits_per_cycle(len(self.drives), worst_case) * self.cycle_hz / self.can.bitrate

    def with_axis(self, axis: str) -> DriveConfig:
        """A single drive without an ``axis`` key takes ``axis`` (the bridge's ``--axis``)."""
        if len(self.drives) == 1 and self.drives[0].axis is None:
            d = self.drives[0]
            named = DriveSettings(**{**{f.name: getattr(d, f.name) for f in fields(d)}, "axis": axis})
            return DriveConfig(self.can, (named,), self.cycle_hz, self.pacing, self.source)
        return self


@dataclass(frozen=True)
class _Key:
    kind: type
    low: float | None = None
    high: float | None = None
    unit: str = ""
    choices: tuple[Any, ...] = ()


CAN_KEYS: dict[str, _Key] = {
    "interface": _Key(str),
    "channel": _Key(str),
    "bitrate": _Key(int, 10_000, 1_000_000, "bit/s"),
}
DRIVE_KEYS: dict[str, _Key] = {
    "node_id": _Key(int, 1, 127),
    "encoder_counts_per_rev": _Key(int, 1, 1 << 30, "counts"),
    "axis": _Key(str),
    "zero_counts": _Key(int, -(1 << 31), (1 << 31) - 1, "counts"),
    "direction": _Key(int, choices=(1, -1)),
    "eds": _Key(str),
    "heartbeat_ms": _Key(int, 1, 65535, "ms"),
    "heartbeat_timeout_ms": _Key(int, 2, 600_000, "ms"),
    "pdo_timeout_ms": _Key(int, 1, 10_000, "ms"),
    "sdo_timeout_ms": _Key(int, 10, 1500, "ms"),
    "following_error_window_m": _Key(float, 1e-6, 1.0, "m"),
    "following_error_timeout_ms": _Key(int, 0, 65535, "ms"),
    "quick_stop_option": _Key(int, choices=tuple(o.value for o in QuickStopOption)),
    "quick_stop_deceleration_m_s2": _Key(float, 1e-3, 1000.0, "m/s²"),
}
BUS_KEYS: dict[str, _Key] = {
    "cycle_hz": _Key(int, unit="Hz", choices=CYCLE_RATES_HZ),
    "pacing": _Key(str, choices=tuple(p.value for p in Pacing)),
}
"""keys of a [drive] table that belong to the bus's one SYNC (all drives that give them agree)"""
REQUIRED_CAN = ("interface", "channel")
REQUIRED_DRIVE = ("node_id", "encoder_counts_per_rev")


def _value(source: str, table: str, key: str, value: Any, spec: _Key) -> Any:
    where = f"{source}: [{table}] {key}"
    if spec.kind is str:
        if not isinstance(value, str) or not value:
            raise DriveConfigError(f"{where} = {value!r} must be a non-empty string")
    elif spec.kind is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise DriveConfigError(
                f"{where} = {value!r} must be an integer{f' [{spec.unit}]' if spec.unit else ''}"
            )
    elif isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise DriveConfigError(
            f"{where} = {value!r} must be a finite number{f' [{spec.unit}]' if spec.unit else ''}"
        )
    unit = f" {spec.unit}" if spec.unit else ""
    if spec.choices and value not in spec.choices:
        shown = ", ".join(f"{c}" for c in spec.choices)
        raise DriveConfigError(f"{where} = {value!r}{unit} is not one of {shown}{unit}")
    if spec.low is not None and spec.high is not None and not spec.low <= value <= spec.high:
        raise DriveConfigError(f"{where} = {value}{unit} must be in {spec.low:g}…{spec.high:g}{unit}")
    return float(value) if spec.kind is float else value


def _table(
    source: str, table: str, data: Any, keys: dict[str, _Key], required: tuple[str, ...]
) -> dict[str, Any]:
    if not isinstance(data, dict):
        raise DriveConfigError(f"{source}: [{table}] must be a table of keys, not {type(data).__name__}")
    unknown = sorted(set(data) - set(keys))
    if unknown:
        raise DriveConfigError(
            f"{source}: unknown key(s) {', '.join(unknown)} in [{table}]; allowed: {', '.join(keys)}"
        )
    missing = [k for k in required if k not in data]
    if missing:
        raise DriveConfigError(f"{source}: [{table}] lacks {', '.join(missing)}")
    return {k: _value(source, table, k, v, keys[k]) for k, v in data.items()}


def config_from_mapping(
    data: dict[str, Any], source: str = "drive configuration", base: Path | None = None
) -> DriveConfig:
    """Validate a parsed ``drive.toml`` (``base``: the folder relative ``eds`` paths start from)."""
    unknown = sorted(set(data) - {"can", "drive"})
    if unknown:
        raise DriveConfigError(f"{source}: unknown section(s) {', '.join(unknown)}; allowed: can, drive")
    for section in ("can", "drive"):
        if section not in data:
            raise DriveConfigError(f"{source}: no [{section}] section")
    can = CanSettings(**_table(source, "can", data["can"], CAN_KEYS, REQUIRED_CAN))
    tables = data["drive"] if isinstance(data["drive"], list) else [data["drive"]]
    if not tables:
        raise DriveConfigError(f"{source}: [[drive]] lists no drive")
    drives, bus = [], {}
    for i, table in enumerate(tables, 1):
        label = "drive" if len(tables) == 1 else f"[drive] {i}"
        values = _table(source, label, table, {**DRIVE_KEYS, **BUS_KEYS}, REQUIRED_DRIVE)
        for key in BUS_KEYS:
            if key in values:
                value = values.pop(key)
                first = bus.setdefault(key, (value, i))
                if first[0] != value:
                    raise DriveConfigError(
                        f"{source}: [drive] {i} {key} = {value!r} differs from {first[0]!r} of [drive] "
                        f"{first[1]}: one SYNC serves every drive on the bus"
                    )
        if "eds" in values:
            eds = Path(values["eds"])
            values["eds"] = eds if eds.is_absolute() or base is None else base / eds
        drives.append(DriveSettings(**values))
    _distinct(source, drives)
    config = DriveConfig(
        can,
        tuple(drives),
        bus.get("cycle_hz", (1000, 0))[0],
        Pacing(bus.get("pacing", ("wall", 0))[0]),
        source,
    )
    load = config.bus_load()
    if load is not None and load > 1.0:
        fits = [hz for hz in CYCLE_RATES_HZ if bits_per_cycle(len(drives), True) * hz <= can.bitrate]
        advice = f"lower cycle_hz to {max(fits)} Hz" if fits else "use fewer drives per bus"
        raise DriveConfigError(
            f"{source}: {len(drives)} drive(s) at cycle_hz = {config.cycle_hz} Hz need "
            f"{load * can.bitrate / 1e6:.2f} Mbit/s in the worst case, more than the bitrate of "
            f"{can.bitrate / 1e6:g} Mbit/s: {advice}"
        )
    return config


def _distinct(source: str, drives: list[DriveSettings]) -> None:
    for key in ("node_id", "axis"):
        seen: dict[Any, int] = {}
        for i, d in enumerate(drives, 1):
            value = getattr(d, key)
            if key == "axis" and value is None and len(drives) > 1:
                raise DriveConfigError(
                    f"{source}: [drive] {i} lacks axis (every one of several drives names its axis)"
                )
            if value in seen:
                raise DriveConfigError(
                    f"{source}: [drive] {i} {key} = {value!r} is also [drive] {seen[value]}'s"
                )
            seen[value] = i


def load_drive_config(path: str | Path | None) -> DriveConfig:
    """Load a drive configuration file (None: the packaged one of ``--drive canopen-sim``)."""
    data, source = read_toml(
        path, package=__package__, resource=DEFAULT_SIM_CONFIG_RESOURCE, kind="drive configuration",
        error=DriveConfigError,
    )  # fmt: skip
    return config_from_mapping(data, source, Path(path).parent if path is not None else None)
