"""A bridge and a recorder on loopback as processes (axisflow's launcher), and what a scenario watches
them with: the bridge's move statuses, its token, its memory; how they ended."""

from __future__ import annotations

import threading
import time
from collections import Counter
from dataclasses import dataclass
from typing import Any

import zenoh

from ...acquisition import AxisKeys, MoveState, MoveStatus, ZenohOptions, is_complete, load_plant
from ...acquisition.bridge.tick_clock import fifo_allowed
from ...acquisition.bus.readiness import JoinedSubscriber, say_hello
from ...deploy.processes import READY_TIMEOUT_S, Child, Exited, Launcher, free_port, wait_until
from ...model import AxisParams, default_params
from ..toolkit.proc_stats import status_kb
from .ticks import KEYS, SETPOINT_TOPIC, STATE_TOPIC, TickRecord, tick_record

RT_PRIORITY = 50
"""the SCHED_FIFO priority of a scenario's bridge, where allowed (docs/acquisition.md)"""


def rss_mb(pid: int) -> float:
    """Resident set size of process ``pid`` [MB] (an ``OSError`` or ``RuntimeError`` once it is gone)."""
    return status_kb(pid) / 1024.0


class Rig:
    """A recorder (listening) and bridges (connecting to it, each listening on a port of its own) as
    processes of a :class:`~axisflow.deploy.processes.Launcher`, and the Zenoh options for this process's own
    sessions (connected to both)."""

    def __init__(self, launcher: Launcher, name: str) -> None:
        self.launcher = launcher
        self.recording = launcher.logs / f"{name}.mcap"
        self.recorder_port = free_port()
        self.bridge_ports: list[int] = []

    @property
    def recorder_endpoint(self) -> str:
        return f"tcp/127.0.0.1:{self.recorder_port}"

    def start_recorder(self, *extra: str) -> Child:
        """``axisflow record`` of ``axisflow/**`` into :attr:`recording`, started before the bridge and
        ready (its subscriber has joined) when this returns."""
        proc = self.launcher.start(
            "recorder", "record", "-o", str(self.recording), "--listen", self.recorder_endpoint, "--json",
            *extra, ready=True,
        )  # fmt: skip
        self.launcher.wait_ready(proc, READY_TIMEOUT_S)
        return proc

    def start_bridge(self, name: str = "bridge", *extra: str) -> Child:
        """``axisflow bridge --sim --json`` at 1× real time, waiting for the recorder's subscription
        before its first tick; ready (it holds its token) when this returns. Its ticking thread runs at
        real-time priority where the system allows it (:data:`RT_PRIORITY`), as a bridge on a real
        bus would: the scenarios measure what a fault does to its loop, not what other processes on a
        loaded machine do."""
        self.bridge_ports.append(free_port())
        listen = f"tcp/127.0.0.1:{self.bridge_ports[-1]}"
        real_time = ("--rt-priority", str(RT_PRIORITY)) if fifo_allowed(RT_PRIORITY) else ()
        proc = self.launcher.start(
            name, "bridge", "--sim", "--json", "--wait-subscribers", "10",
            "--connect", self.recorder_endpoint, "--listen", listen, *real_time, *extra, ready=True,
        )  # fmt: skip
        self.launcher.wait_ready(proc, READY_TIMEOUT_S)
        return proc

    def options(self) -> ZenohOptions:
        """A peer of this process, connected to the recorder (it learns the bridges by gossip)."""
        return ZenohOptions(mode="peer", connect=(self.recorder_endpoint,))


class StatusWatch:
    """The move statuses a bridge publishes on ``<prefix>/<axis>/event``, as typed records."""

    def __init__(self, session: Any, keys: AxisKeys = KEYS) -> None:
        self._session, self._keys = session, keys

        def handler() -> zenoh.handlers.FifoChannel:
            return zenoh.handlers.FifoChannel(1 << 18)

        self._joined = JoinedSubscriber(session, keys.event, handler).__enter__()  # misses no status
        self._sub = self._joined.subscriber
        self.statuses: list[MoveStatus] = []
        # per (state, sender): a count stays O(1) while a flood's thousands of statuses arrive
        self._counts: Counter[tuple[MoveState, str]] = Counter()

    def drain(self) -> list[MoveStatus]:
        while (sample := self._sub.try_recv()) is not None:
            status = MoveStatus.decode(sample.payload.to_bytes())
            self.statuses.append(status)
            self._counts[status.state, status.sender] += 1
        return self.statuses

    def count(self, state: MoveState, sender: str | None = None) -> int:
        self.drain()
        if sender is not None:
            return self._counts[state, sender]
        return sum(n for (s, _sender), n in self._counts.items() if s is state)

    def wait(self, state: MoveState, count: int, timeout_s: float, sender: str | None = None) -> bool:
        return wait_until(lambda: self.count(state, sender) >= count, timeout_s)

    def settled(self, timeout_s: float = 10.0) -> list[MoveStatus]:
        """Every status the bridge published before now: one hello to its event publisher, answered
        after everything it sent before (acquisition.bus.readiness), then :meth:`drain`."""
        say_hello(self._session, self._keys.event, timeout_s)
        return self.drain()

    def close(self) -> None:
        self._joined.__exit__()


def require_bridge(session: Any, timeout_s: float = 30.0, keys: AxisKeys = KEYS) -> None:
    """Return once a bridge holds its liveliness token ``<prefix>/<axis>/alive``; a
    :class:`RuntimeError` (the scenario cannot run) if none does within ``timeout_s``."""
    if not wait_until(lambda: bool(list(session.liveliness().get(keys.alive, timeout=1.0))), timeout_s, 0.1):
        raise RuntimeError(f"the bridge did not come up within {timeout_s:g} s")


class RssSampler:
    """The resident memory of a process [MB], sampled on a thread every ``period_s``."""

    def __init__(self, pid: int, period_s: float = 0.05) -> None:
        self.pid, self.period_s = pid, period_s
        self.samples: list[tuple[float, float]] = []
        """(monotonic time [s], RSS [MB])"""
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)

    def _run(self) -> None:
        while not self._stop.is_set():
            try:
                self.samples.append((time.monotonic(), rss_mb(self.pid)))
            except (OSError, RuntimeError):
                return  # the process is gone
            self._stop.wait(self.period_s)

    def after(self, t: float, timeout_s: float = 10.0) -> float:
        """The RSS [MB] of the first sample taken at or after monotonic time ``t`` (waiting for it); a
        :class:`RuntimeError` if none comes within ``timeout_s`` (the process is gone)."""
        found: list[float] = []

        def sampled() -> bool:
            found[:] = [mb for when, mb in self.samples if when >= t][:1]
            return bool(found)

        if not wait_until(sampled, timeout_s, self.period_s / 4):
            raise RuntimeError(f"no RSS sample of process {self.pid} within {timeout_s:g} s")
        return found[0]

    def between(self, t0: float, t1: float) -> list[float]:
        return [mb for t, mb in self.samples if t0 <= t <= t1]

    @property
    def peak_mb(self) -> float:
        return max((mb for _t, mb in self.samples), default=float("nan"))

    def __enter__(self) -> RssSampler:
        self._thread.start()
        return self

    def __exit__(self, *_exc: object) -> None:
        self._stop.set()
        self._thread.join()


@dataclass(frozen=True)
class RunEnd:
    """How the bridge and the recorder of a :class:`Rig` ended (both stopped with SIGINT)."""

    bridge: Exited
    recorder: Exited
    state: TickRecord
    setpoint: TickRecord
    complete: bool
    """the recording has its summary and footer"""

    @property
    def report(self) -> dict[str, Any]:
        return self.bridge.json()

    @property
    def summary(self) -> dict[str, Any]:
        return self.recorder.json()

    @property
    def telemetry_intact(self) -> bool:
        """Both processes exited 0 and every tick the bridge ran is in the file, once, 1 ms apart."""
        ticks = self.report["ticks"]
        return (
            self.bridge.returncode == 0
            and self.recorder.returncode == 0
            and self.complete
            and self.state.every_tick
            and self.setpoint.every_tick
            and self.state.messages == ticks == self.setpoint.messages
        )

    def timing(self) -> str:
        r = self.report
        j = r["period_jitter"] or {}
        return (
            f"{r['ticks']} ticks, {r['late_ticks']} late by more than a period, period jitter p99 "
            f"{j.get('p99_us', float('nan')):.0f} µs, max {j.get('max_us', float('nan')) / 1e3:.1f} ms"
        )


def stop_rig(rig: Rig, bridge: Child, recorder: Child) -> RunEnd:
    """SIGINT the bridge, then the recorder (whose stop proves that the bridge's last samples have
    arrived: acquisition.bus.readiness); read the recording."""
    bridge_end = rig.launcher.stop(bridge)
    recorder_end = rig.launcher.stop(recorder, 60.0)
    complete = is_complete(rig.recording)
    return RunEnd(
        bridge_end,
        recorder_end,
        tick_record(rig.recording, STATE_TOPIC),
        tick_record(rig.recording, SETPOINT_TOPIC),
        complete,
    )


def true_axis(nominal: AxisParams | None = None) -> AxisParams:
    """The simulated plant's true parameters (the packaged plant file on the nominal ones)."""
    return load_plant(None, nominal or default_params()).axis


def fastest_move_s(x0_m: float, x1_m: float, params: AxisParams) -> float:
    """The duration of the minimum-time poly5 move (the planner's exact solver)."""
    from ...planner import Case, MoveProblem, solve_exact

    return solve_exact(MoveProblem(x0_m, x1_m, "poly5", Case.MIN_TIME), params).duration_s
