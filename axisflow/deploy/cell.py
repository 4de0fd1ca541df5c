"""A cell: several axes through one Zenoh router, their processes started as a launch file would.

A robot cell has several axes, each driven from a machine near its drive, and one place where
everything is recorded (docs/deployment.md). On one machine — the demo, the tests, the benchmark — a
:class:`Cell` starts the processes such a deployment runs on several, each an ``axisflow`` command of
its own, through a :class:`~axisflow.deploy.processes.Launcher`:

* one **router** (``axisflow router --listen EP``), the only listener of the cell;
* one **bridge** per axis (``axisflow bridge --axis aK``), axes named ``a0``, ``a1``, …
  (:func:`axis_names`), each a Zenoh **client** of the router;
* one **recorder** (``axisflow record``) of every key of the cell, a client too;
* for the demo, one **planner** per axis (``axisflow planner --axis aK``), a client too.

:class:`CellLayout` is the launch description: the command line of each process. Every process says
when it is ready (the router: it listens; a bridge: it holds its token; the recorder: its subscriber
has joined), so nothing waits on a sleep; the recorder starts before the bridges, which wait for its
subscriber before their first tick (so it records each from its first sample). :meth:`Cell.restart_router`
stops the router and starts another on the same endpoint: the bridges keep their axes safe and every
client reconnects by itself (docs/deployment.md, tests/deploy/test_cell.py).
"""

from __future__ import annotations

import signal
import time
from dataclasses import dataclass
from pathlib import Path

from ..acquisition.bus.options import check_endpoint
from ..acquisition.wire.keys import DEFAULT_PREFIX, AxisKeys, all_keys
from ..model import AxisflowError
from .processes import READY_TIMEOUT_S, STOP_TIMEOUT_S, Child, Exited, Launcher, free_port, last_line

MAX_AXES = 32
"""axes a cell of ``axisflow demo --axes`` may have (one bridge process each, on one machine)"""


class CellError(AxisflowError):
    """A process of the cell failed or did not get ready."""


def axis_names(count: int) -> tuple[str, ...]:
    """The axes of a cell of ``count``: ``a0``, ``a1``, …"""
    if not 1 <= count <= MAX_AXES:
        raise AxisflowError(f"--axes {count} must be in 1…{MAX_AXES} (one bridge process per axis)")
    return tuple(f"a{k}" for k in range(count))


@dataclass(frozen=True)
class CellLayout:
    """The launch description of a cell on this machine: which ``axisflow`` commands run, with which
    arguments (every process but the router is a client of the router at ``endpoint``)."""

    axes: tuple[str, ...]
    endpoint: str
    prefix: str = DEFAULT_PREFIX
    bridge_speed: float = 1.0
    """the bridges' ``--speed`` (0: as fast as the recorder takes their samples)"""
    bridge_options: tuple[str, ...] = ()
    """more arguments of every bridge (``--plant-profile``, ``--params``, ``--drive``)"""

    def __post_init__(self) -> None:
        check_endpoint(self.endpoint)
        for axis in self.axes:
            AxisKeys(axis, self.prefix)  # a valid key chunk, or a KeyExprError naming it
        if not self.axes or len(set(self.axes)) != len(self.axes):
            raise AxisflowError(f"a cell needs distinct axes, not {', '.join(self.axes) or 'none'}")

    @classmethod
    def on_loopback(
        cls, count: int, bridge_speed: float = 1.0, bridge_options: tuple[str, ...] = ()
    ) -> CellLayout:
        """``count`` axes around a router on a free port of 127.0.0.1."""
        endpoint = f"tcp/127.0.0.1:{free_port()}"
        return cls(axis_names(count), endpoint, bridge_speed=bridge_speed, bridge_options=bridge_options)

    @property
    def client(self) -> tuple[str, ...]:
        """The Zenoh options of every process but the router."""
        return ("--mode", "client", "--connect", self.endpoint)

    def router(self) -> tuple[str, ...]:
        return ("router", "--listen", self.endpoint)

    def bridge(
        self, axis: str, duration_s: float | None = None, wait_subscribers_s: float = 0.0
    ) -> tuple[str, ...]:
        duration = ("--duration", f"{duration_s:g}") if duration_s is not None else ()
        return (
            "bridge", "--axis", axis, "--prefix", self.prefix, "--speed", f"{self.bridge_speed:g}",
            "--wait-subscribers", f"{wait_subscribers_s:g}", *duration, "--json", *self.bridge_options,
            *self.client,
        )  # fmt: skip

    def recorder(self, path: Path) -> tuple[str, ...]:
        return ("record", "-o", str(path), "--keys", all_keys(self.prefix), "--json", *self.client)

    def planner(self, axis: str, options: tuple[str, ...]) -> tuple[str, ...]:
        return ("planner", "--axis", axis, "--prefix", self.prefix, *options, *self.client)


@dataclass(frozen=True)
class RouterRestart:
    """When :meth:`Cell.restart_router` stopped the router and when its successor listened
    (``time.monotonic()`` seconds)."""

    asked_s: float
    stopped_s: float
    listening_s: float

    @property
    def down_s(self) -> float:
        """From the stop asked to the new router listening [s]."""
        return self.listening_s - self.asked_s


class Cell:
    """The processes of a cell (see the module docstring); a context manager: leaving stops whatever
    still runs (SIGINT, the recorder finishing its file)."""

    def __init__(self, layout: CellLayout, logs: Path) -> None:
        self.layout = layout
        self.launcher = Launcher(logs)
        self.router: Child | None = None
        self.recorder: Child | None = None
        self.bridges: dict[str, Child] = {}

    def __enter__(self) -> Cell:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.launcher.close(STOP_TIMEOUT_S)

    def _ready(self, child: Child) -> Child:
        try:
            self.launcher.wait_ready(child, READY_TIMEOUT_S)
        except AxisflowError as exc:
            raise CellError(f"{exc} (its output: {child.err_path})") from None
        return child

    def start_router(self) -> Child:
        self.router = self._ready(self.launcher.start("router", *self.layout.router(), ready=True))
        return self.router

    def start_recorder(self, path: Path) -> Child:
        self.recorder = self._ready(self.launcher.start("recorder", *self.layout.recorder(path), ready=True))
        return self.recorder

    def start_bridges(self, duration_s: float | None = None, wait_subscribers_s: float = 0.0) -> None:
        """Every axis's bridge, started together; returns once each holds its token."""
        for axis in self.layout.axes:
            args = self.layout.bridge(axis, duration_s, wait_subscribers_s)
            self.bridges[axis] = self.launcher.start(f"bridge-{axis}", *args, ready=True)
        for child in self.bridges.values():
            self._ready(child)

    def restart_router(self) -> RouterRestart:
        """Stop the router (SIGINT) and start another on the same endpoint."""
        assert self.router is not None, "start_router first"
        asked = time.monotonic()
        self._check(self.launcher.stop(self.router, STOP_TIMEOUT_S))
        stopped = time.monotonic()
        self.start_router()
        return RouterRestart(asked, stopped, time.monotonic())

    def wait_bridges(self, timeout_s: float) -> dict[str, dict]:
        """The reports of the bridges (started with a duration), once they have ended by themselves."""
        return {
            axis: self._check(self.launcher.wait(c, timeout_s)).json() for axis, c in self.bridges.items()
        }

    def stop_bridges(self) -> dict[str, dict]:
        """SIGINT to every bridge; their reports by axis."""
        for child in self.bridges.values():
            if child.poll() is None:
                child.send_signal(signal.SIGINT)
        return self.wait_bridges(STOP_TIMEOUT_S)

    def stop_recorder(self) -> dict:
        """SIGINT to the recorder (it proves nothing is on the way, then finishes its file): its summary."""
        assert self.recorder is not None, "start_recorder first"
        return self._check(self.launcher.stop(self.recorder, STOP_TIMEOUT_S)).json()

    def stop_router(self) -> None:
        if self.router is not None:
            self._check(self.launcher.stop(self.router, STOP_TIMEOUT_S))

    def check_alive(self) -> None:
        """A :class:`CellError` if the router, the recorder or a bridge has ended."""
        for child in (self.router, self.recorder, *self.bridges.values()):
            if child is not None and child.poll() is not None:
                raise CellError(
                    f"{child.command} ended with code {child.returncode}: {last_line(child.stderr_text())}"
                )

    def _check(self, end: Exited) -> Exited:
        if end.returncode != 0 or end.timed_out:
            how = "hung and was killed" if end.timed_out else f"exited with code {end.returncode}"
            raise CellError(f"{end.name} {how}: {last_line(end.stderr)} (see {self.launcher.logs})")
        return end
