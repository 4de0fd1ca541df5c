"""A bridge on its own thread (real Zenoh sessions on loopback) for the planner node's tests."""

from __future__ import annotations

import threading

import pytest
import zenoh
from axisflow.acquisition import AxisKeys, BridgeConfig, SimulatedAxis, ZenohOptions, load_plant, open_session
from axisflow.acquisition.bridge.bridge import Bridge
from axisflow.model import default_params

KEYS = AxisKeys("a0")


class ThreadBridge:
    """``Bridge.run`` on a thread until the test ends; an observer session records the plan records."""

    def __init__(self, port: int, params=None, speed: float = 0.0) -> None:
        self.port = port
        self.params = params or default_params()
        self.drive = SimulatedAxis(
            load_plant(None, self.params), self.params, 1_700_000_000_000_000_000, "a0"
        )
        self.config = BridgeConfig(keys=KEYS, speed=speed)
        self.stop = threading.Event()

    def __enter__(self) -> ThreadBridge:
        self.session = open_session(ZenohOptions.loopback(listen_port=self.port))
        self.observer = open_session(ZenohOptions.loopback(connect_port=self.port))
        self.plans = self.observer.declare_subscriber(KEYS.plan, zenoh.handlers.FifoChannel(100_000))
        self.bridge = Bridge(self.session, self.drive, self.params, self.config).__enter__()
        self.thread = threading.Thread(target=self.bridge.run, args=(self.stop,))
        self.thread.start()
        return self

    def plan_records(self) -> list:
        from axisflow.acquisition import PlanRecord

        out = []
        while (s := self.plans.try_recv()) is not None:
            out.append(PlanRecord.decode(s.payload.to_bytes()))
        return out

    def __exit__(self, *exc: object) -> None:
        self.stop.set()
        self.thread.join(30)
        self.bridge.__exit__(*exc)
        self.plans.undeclare()
        self.observer.close()
        self.session.close()


@pytest.fixture
def thread_bridge():
    return ThreadBridge
