"""A CAN bus for each test: python-can's in-process ``virtual`` bus (a real bus: every frame goes through
python-can and canopen on both sides), simulated CiA 402 drives on it, and the master."""

from __future__ import annotations

import itertools
import time
from collections.abc import Callable, Iterator
from contextlib import ExitStack
from typing import Any

import can
import pytest
from axisflow.acquisition.drives.canopen.config import DriveConfig, config_from_mapping
from axisflow.acquisition.drives.canopen.master import CanopenMaster, open_master
from axisflow.acquisition.drives.canopen.sim_drive import FaultPlan, SimulatedDrive
from axisflow.acquisition.drives.drive import DriveEvent, Setpoint
from axisflow.acquisition.drives.plant import load_plant
from axisflow.model import default_params

PARAMS = default_params()
T0 = 1_700_000_000_000_000_000
_channels = itertools.count()


class CanBus:
    """One virtual CAN channel of a test, with what runs on it (closed after the test)."""

    def __init__(self, stack: ExitStack) -> None:
        self.channel = f"axisflow-test-{next(_channels)}"
        self.stack = stack
        self.params = PARAMS
        self.plant = load_plant(None, PARAMS)

    def config(self, *drives: dict[str, Any], **bus: Any) -> DriveConfig:
        """A lock-step configuration of ``drives`` (default: node 5 on axis a0) on this channel."""
        tables = [dict(d) for d in drives] or [{"node_id": 5, "axis": "a0"}]
        for table in tables:
            table.setdefault("encoder_counts_per_rev", 131072)
            table.setdefault("pacing", bus.get("pacing", "lockstep"))
            table.setdefault("cycle_hz", bus.get("cycle_hz", 1000))
            # the drive's threads share this process and a loaded machine: generous, except where a test
            # waits for a silence to be noticed
            table.setdefault("heartbeat_timeout_ms", 2000)
            table.setdefault("pdo_timeout_ms", 1000)
        return config_from_mapping(
            {"can": {"interface": "virtual", "channel": self.channel}, "drive": tables}
        )

    def sim(self, config: DriveConfig, index: int = 0, faults: FaultPlan | None = None) -> SimulatedDrive:
        """A simulated drive for drive ``index`` of ``config``, booted on this channel."""
        plan = faults or FaultPlan()
        drive = SimulatedDrive(config.can, config.drives[index], config.cycle_hz, self.plant, PARAMS, plan)
        return self.stack.enter_context(drive)

    def master(self, config: DriveConfig, reset_fault: bool = False) -> CanopenMaster:
        return self.stack.enter_context(open_master(config, PARAMS, reset_fault, start_stamp_ns=T0))

    def listener(self) -> can.BusABC:
        """A third bus on the channel that only listens (frames counted by tests)."""
        bus = can.Bus(interface="virtual", channel=self.channel)
        self.stack.callback(bus.shutdown)
        return bus


@pytest.fixture
def canbus() -> Iterator[CanBus]:
    with ExitStack() as stack:
        yield CanBus(stack)


Setpoints = Callable[[int], Setpoint]


def hold(position_m: float) -> Setpoints:
    return lambda _tick: Setpoint(position_m, 0.0, 0.0, 0.0)


class Runner:
    """Runs a master's ticks as the bridge does (read, status, apply, SYNC) and keeps what it saw."""

    def __init__(self, master: CanopenMaster) -> None:
        self.master = master
        self.samples: list[list] = [[] for _ in master.drives]
        self.events: list[list[DriveEvent]] = [[] for _ in master.drives]
        self.statuses: list[list] = [[] for _ in master.drives]

    def tick(self, setpoints: list[Setpoints]) -> None:
        for i, drive in enumerate(self.master.drives):
            sample = drive.read()
            status = drive.status()
            self.statuses[i].append(status)
            if status.fresh:
                self.samples[i].append(sample)
            self.events[i] += drive.events()
            drive.apply(setpoints[i](self.master.cycle.clock.tick))
        self.master.cycle.after_tick()

    def until(self, done: Callable[[], bool], setpoints: list[Setpoints], max_ticks: int = 20_000,
              timeout_s: float = 60.0) -> int:  # fmt: skip
        """Tick until ``done()`` holds; the number of ticks run (fails the test past the limits)."""
        deadline = time.monotonic() + timeout_s
        for n in range(max_ticks):
            if done():
                return n
            if time.monotonic() > deadline:
                break
            self.tick(setpoints)
        pytest.fail(f"not done after {n + 1} ticks: events {self.events}")

    def kinds(self, i: int = 0) -> list:
        return [e.kind for e in self.events[i]]


@pytest.fixture
def runner() -> type[Runner]:
    return Runner


@pytest.fixture
def hold_at() -> Callable[[float], Setpoints]:
    return hold


def eventually(predicate: Callable[[], bool], timeout_s: float = 10.0) -> None:
    """Poll ``predicate`` (something another thread makes true: the simulated drive works through the
    frames on its bus in its own thread) until it holds; fail the test after ``timeout_s``."""
    deadline = time.monotonic() + timeout_s
    while not predicate():
        if time.monotonic() > deadline:
            pytest.fail(f"not true within {timeout_s} s")
        time.sleep(0.001)


@pytest.fixture
def until() -> Callable[..., None]:
    return eventually
