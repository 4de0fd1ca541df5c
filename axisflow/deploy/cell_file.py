"""The launch file of a cell (``cell.toml``): its router, and what each machine runs.

::

    router = "tcp/192.168.10.5:7447"   # where every client reaches the router
    listen = "tcp/0.0.0.0:7447"        # optional: what the router binds (default: router)
    prefix = "axisflow"                # optional: the key prefix
    security = "cell1-sec"             # optional: a folder of `axisflow security init` (TLS, access list)

    [machine.hub]                      # one table per machine, by the name --machine gives
    router = true                      # it runs the router
    recorder = "logs/cell.mcap"        # and records the cell into this file

    [machine.m1]
    axes = ["a0", "a1"]                # a bridge per axis
    bridge = ["--sim", "--speed", "1"] # the bridges' other arguments (default: --sim)

``axisflow cell up cell.toml --machine m1`` starts what m1 runs, each an ``axisflow`` command of its
own, and holds them until Ctrl-C; without ``--machine``, what every machine runs (the whole cell on
this host, to try a file out). ``--print`` prints the commands instead (what a service unit runs).

Without ``security`` the router listens on ``listen`` (or ``router``) and every other process is its
client over the endpoint ``router``. With ``security`` each process takes its role's file in that
folder: the router ``router.json5`` (the endpoint is then the one the folder was made for), the
recorder ``recorder.json5``, the bridge of axis A the file of a bridge role limited to A
(``bridge@A``, ``bridge-m1@A+B``; docs/security.md), else ``bridge.json5``. A process that has no
role file is refused by name. Relative paths (``recorder``, ``security``) are taken from the launch
file's folder. Unknown keys are refused by name; an axis may have one bridge only.
"""

from __future__ import annotations

import shlex
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..acquisition.bus.options import check_endpoint
from ..acquisition.wire.keys import DEFAULT_PREFIX, AxisKeys, all_keys
from ..model import AxisflowError
from ..model.toml_file import read_toml
from .security.errors import SecurityArgumentError
from .security.roles import role_axes, role_kind

TOP_KEYS = ("router", "listen", "prefix", "security", "machine")
MACHINE_KEYS = ("router", "recorder", "axes", "bridge")
DEFAULT_BRIDGE_ARGS = ("--sim",)


class CellFileError(AxisflowError, ValueError):
    """A cell launch file is invalid (the message names the file, the key and the value)."""


@dataclass(frozen=True)
class Machine:
    """What one machine of the cell runs."""

    name: str
    router: bool = False
    recorder: Path | None = None
    axes: tuple[str, ...] = ()
    bridge_args: tuple[str, ...] = DEFAULT_BRIDGE_ARGS


@dataclass(frozen=True)
class Process:
    """One ``axisflow`` command of a machine: ``axisflow ARGS``."""

    name: str
    machine: str
    args: tuple[str, ...]

    @property
    def command(self) -> str:
        """As a shell would take it (quoted where needed: ``'axisflow/**'``)."""
        return shlex.join(("axisflow", *self.args))


@dataclass(frozen=True)
class CellFile:
    """A validated ``cell.toml`` (see the module docstring)."""

    source: str
    router: str
    machines: tuple[Machine, ...]
    listen: str | None = None
    prefix: str = DEFAULT_PREFIX
    security: Path | None = None

    def machine(self, name: str) -> Machine:
        for m in self.machines:
            if m.name == name:
                return m
        raise CellFileError(
            f"--machine {name}: {self.source} has no such machine; it has "
            f"{', '.join(m.name for m in self.machines)}"
        )

    def processes(self, machine: str | None = None) -> list[Process]:
        """The processes of ``machine`` (None: of every machine) in starting order: the router, the
        recorders, then the bridges."""
        chosen = self.machines if machine is None else (self.machine(machine),)
        out = [Process("router", m.name, self._router_args()) for m in chosen if m.router]
        for m in chosen:
            if m.recorder is not None:
                args = ("record", "-o", str(m.recorder), "--keys", all_keys(self.prefix))
                out.append(Process(f"recorder-{m.name}", m.name, (*args, *self._client("recorder"))))
        for m in chosen:
            for axis in m.axes:
                args = ("bridge", "--axis", axis, "--prefix", self.prefix, *m.bridge_args)
                out.append(Process(f"bridge-{axis}", m.name, (*args, *self._client("bridge", axis))))
        return out

    def _router_args(self) -> tuple[str, ...]:
        if self.security is not None:
            return ("router", "--zenoh-config", str(self._role_file("router")))
        return ("router", "--listen", self.listen or self.router)

    def _client(self, kind: str, axis: str | None = None) -> tuple[str, ...]:
        if self.security is None:
            return ("--mode", "client", "--connect", self.router)
        return ("--zenoh-config", str(self._role_file(kind, axis)))

    def _role_file(self, kind: str, axis: str | None = None) -> Path:
        """The Zenoh file of the role ``kind`` (limited to ``axis`` if the folder has one) in the
        security folder."""
        assert self.security is not None
        if kind != "router" and axis is not None:
            for path in sorted(self.security.glob("*.json5")):
                try:
                    if role_kind(path.stem) == kind and axis in role_axes(path.stem):
                        return path
                except SecurityArgumentError:  # router.json5, or a file of someone else's
                    continue
        path = self.security / f"{kind}.json5"
        if not path.is_file():
            what = f"the {kind} of axis {axis}" if axis is not None else f"the {kind}"
            role = f"{kind}@{axis}" if axis is not None else kind
            limited = f" nor a {kind} role limited to {axis}" if axis is not None else ""
            raise CellFileError(
                f"{self.source}: security folder {self.security} holds no {path.name}{limited} for {what}: "
                f"issue one with `axisflow security add {self.security} --roles {role}`"
            )
        return path


def load_cell_file(path: str | Path) -> CellFile:
    """Read and validate the launch file ``path`` (a :class:`CellFileError` naming what is wrong)."""
    data, source = read_toml(
        path, package="axisflow", resource="cell.toml", kind="cell launch", error=CellFileError
    )
    return cell_from_mapping(data, source, Path(path).parent)


def cell_from_mapping(data: dict[str, Any], source: str, base: Path) -> CellFile:
    """Validate a parsed ``cell.toml`` (``base``: the folder relative paths start from)."""
    _known(source, "the file", data, TOP_KEYS)
    router = _endpoint(source, "router", data.get("router"), listen=False)
    listen = _endpoint(source, "listen", data["listen"], listen=True) if "listen" in data else None
    prefix = _text(source, "prefix", data.get("prefix", DEFAULT_PREFIX))
    try:
        all_keys(prefix)
    except AxisflowError as exc:
        raise CellFileError(f"{source}: prefix: {exc}") from None
    security = None
    if "security" in data:
        security = base / _text(source, "security", data["security"])
        if not security.is_dir():
            raise CellFileError(f"{source}: security folder {security} does not exist")
    tables = data.get("machine")
    if not isinstance(tables, dict) or not tables:
        raise CellFileError(f"{source}: no [machine.NAME] table: name each machine and what it runs")
    machines = tuple(_machine(source, name, table, base, prefix) for name, table in tables.items())
    _check_roles(source, machines)
    return CellFile(source, router, machines, listen, prefix, security)


def _machine(source: str, name: str, table: Any, base: Path, prefix: str) -> Machine:
    where = f"[machine.{name}]"
    if not isinstance(table, dict):
        raise CellFileError(f"{source}: {where} must be a table of keys, not {type(table).__name__}")
    _known(source, where, table, MACHINE_KEYS)
    router = table.get("router", False)
    if not isinstance(router, bool):
        raise CellFileError(f"{source}: {where} router = {router!r} must be true or false")
    recorder = None
    if "recorder" in table:
        recorder = base / _text(source, f"{where} recorder", table["recorder"])
        if recorder.suffix != ".mcap":
            raise CellFileError(f"{source}: {where} recorder = {table['recorder']!r} must end in .mcap")
    axes = _texts(source, f"{where} axes", table.get("axes", []))
    for axis in axes:
        try:
            AxisKeys(axis, prefix)
        except AxisflowError as exc:
            raise CellFileError(f"{source}: {where} axes: {exc}") from None
    bridge = _texts(source, f"{where} bridge", table.get("bridge", list(DEFAULT_BRIDGE_ARGS)))
    owned = {"--axis", "--prefix", "--mode", "--connect", "--listen", "--zenoh-config"} & set(bridge)
    if owned:
        raise CellFileError(
            f"{source}: {where} bridge gives {', '.join(sorted(owned))}: the launch file sets them (axes, "
            "prefix, router, security)"
        )
    if not (router or recorder or axes):
        raise CellFileError(f"{source}: {where} runs nothing: give it router = true, a recorder or axes")
    return Machine(name, router, recorder, axes, bridge)


def _check_roles(source: str, machines: tuple[Machine, ...]) -> None:
    routers = [m.name for m in machines if m.router]
    if len(routers) != 1:
        raise CellFileError(
            f"{source}: {len(routers)} machines run the router ({', '.join(routers) or 'none'}): a cell "
            "has one"
        )
    seen: dict[str, str] = {}
    for m in machines:
        for axis in m.axes:
            if axis in seen:
                raise CellFileError(
                    f"{source}: axis {axis} is driven by machine {seen[axis]} and by machine {m.name}: "
                    "an axis has one bridge"
                )
            seen[axis] = m.name


def _known(source: str, where: str, table: dict[str, Any], keys: tuple[str, ...]) -> None:
    unknown = sorted(set(table) - set(keys))
    if unknown:
        raise CellFileError(
            f"{source}: unknown key(s) {', '.join(unknown)} in {where}; allowed: {', '.join(keys)}"
        )


def _text(source: str, key: str, value: Any) -> str:
    if not isinstance(value, str) or not value:
        raise CellFileError(f"{source}: {key} = {value!r} must be a non-empty string")
    return value


def _texts(source: str, key: str, value: Any) -> tuple[str, ...]:
    if not isinstance(value, list) or not all(isinstance(v, str) and v for v in value):
        raise CellFileError(f"{source}: {key} = {value!r} must be a list of non-empty strings")
    return tuple(value)


def _endpoint(source: str, key: str, value: Any, listen: bool) -> str:
    if value is None:
        raise CellFileError(
            f'{source}: no {key} = "<proto>/<host>:<port>" (where every client reaches the router)'
        )
    try:
        return check_endpoint(_text(source, key, value), listen=listen)
    except AxisflowError as exc:
        raise CellFileError(f"{source}: {key}: {exc}") from None
