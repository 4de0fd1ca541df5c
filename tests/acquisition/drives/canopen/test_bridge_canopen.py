"""The bridge with a CiA 402 drive on a virtual CAN bus, over real Zenoh sessions on loopback: moves run
through CANopen; a drive fault stops the axis, is published with its codes, refuses moves until a quick
stop with a fault reset brings the drive back; while the drive is silent no sample is published."""

import time

import numpy as np
import pytest
import zenoh
from axisflow.acquisition import AxisKeys, AxisSample, BridgeConfig, MoveSender, MoveState, MoveStatus
from axisflow.acquisition.bridge.bridge import Bridge
from axisflow.acquisition.bus.session import ZenohOptions, open_session
from axisflow.acquisition.drives.canopen.cia402 import State, state_of
from axisflow.acquisition.drives.canopen.sim_drive import FaultPlan

KEYS = AxisKeys("a0")


class Rig:
    """A bridge stepped by hand with the bus's SYNC after each tick, a move sender and an observer."""

    def __init__(self, bridge, master, sender, observer):
        self.bridge, self.master, self.sender = bridge, master, sender
        self.events = observer.declare_subscriber(KEYS.event, zenoh.handlers.FifoChannel(100_000))
        self.states = observer.declare_subscriber(KEYS.state, zenoh.handlers.FifoChannel(100_000))
        self.setpoints = observer.declare_subscriber(KEYS.setpoint, zenoh.handlers.FifoChannel(100_000))
        self.seen_events: list[MoveStatus] = []
        self.samples: list[AxisSample] = []
        self.setpoint_stamps: list[int] = []

    def step(self) -> None:
        self.bridge.step()
        self.master.cycle.after_tick()

    def drain(self) -> None:
        while (s := self.events.try_recv()) is not None:
            self.seen_events.append(MoveStatus.decode(s.payload.to_bytes()))
        while (s := self.states.try_recv()) is not None:
            self.samples.append(AxisSample.decode(s.payload.to_bytes()))
        while (s := self.setpoints.try_recv()) is not None:
            self.setpoint_stamps.append(AxisSample.decode(s.payload.to_bytes()).stamp_ns)

    def until(self, done, limit=20_000, timeout_s=60.0):
        deadline = time.monotonic() + timeout_s
        for _ in range(limit):
            self.sender.poll_status()
            self.drain()
            found = done()
            if found:
                return found
            if time.monotonic() > deadline:
                break
            self.step()
            time.sleep(0.0001)  # let Zenoh deliver (the condition is the fact waited on)
        pytest.fail(f"not done: {[(s.state.name, s.move_id, s.text) for s in self.seen_events][-10:]}")

    def status(self, move_id, state):
        return next((s for s in self.sender.statuses if s.move_id == move_id and s.state is state), None)

    def event(self, state, after=0):
        return next((s for s in self.seen_events[after:] if s.state is state and s.move_id == 0), None)


def _rig(stack, canbus, port, faults):
    config = canbus.config()
    canbus.sim(config, faults=faults)
    master = canbus.master(config)
    session = stack.enter_context(open_session(ZenohOptions.loopback(listen_port=port)))
    observer = stack.enter_context(open_session(ZenohOptions.loopback(connect_port=port)))
    bridge = stack.enter_context(
        Bridge(session, master.drives[0], canbus.params, BridgeConfig(keys=KEYS, speed=0))
    )
    sender = stack.enter_context(MoveSender(observer, KEYS))
    assert sender.wait_for_bridge(10.0)
    return Rig(bridge, master, sender, observer)


@pytest.mark.slow
def test_a_fault_stops_the_axis_refuses_moves_and_a_reset_brings_it_back(canbus, port):
    stack = canbus.stack
    rig = _rig(stack, canbus, port, FaultPlan(fault_at_s=1.2, fault_code=0x2310))
    first = rig.sender.send(0.0, 0.3, 0.6)
    rig.until(lambda: rig.status(first.move_id, MoveState.COMPLETED))
    second = rig.sender.send(0.3, 0.0, 2.0)
    fault = rig.until(lambda: rig.event(MoveState.FAULT))
    assert (fault.error_code, fault.error_register) == (0x2310, 0x03)
    assert state_of(fault.statusword) is State.FAULT_REACTION_ACTIVE  # it was moving: it brakes first
    assert "0x2310 continuous over-current" in fault.text
    stopped = rig.until(lambda: rig.status(second.move_id, MoveState.STOPPED))
    assert "faulted" in stopped.text and rig.bridge.report.drive_faults == 1
    samples_at_fault = len(rig.samples)
    third = rig.sender.send(rig.samples[-1].position_m, 0.1, 1.0)
    rejected = rig.until(lambda: rig.status(third.move_id, MoveState.REJECTED))
    assert "the drive follows no setpoints" in rejected.text and "--reset-fault" in rejected.text
    assert len(rig.samples) > samples_at_fault  # it keeps publishing what the drive measures
    setpoints_at_fault = len(rig.setpoint_stamps)
    for _ in range(30):
        rig.step()
    rig.drain()
    assert len(rig.setpoint_stamps) == setpoints_at_fault  # nothing commanded while in fault
    n = len(rig.seen_events)
    rig.sender.stop("reset after the fault", reset_fault=True)
    enabled = rig.until(lambda: rig.event(MoveState.ENABLED, n))
    assert enabled.sender == rig.sender.sender_id and "fault reset; operation enabled" in enabled.text
    for _ in range(5):
        rig.step()
    rig.drain()
    here = rig.samples[-1].position_m
    fourth = rig.sender.send(here, 0.2, 1.0)
    rig.until(lambda: rig.status(fourth.move_id, MoveState.COMPLETED))


@pytest.mark.slow
def test_no_sample_is_published_while_the_drive_is_silent(canbus, port):
    rig = _rig(canbus.stack, canbus, port, FaultPlan(silent_at_s=0.5, silent_for_s=0.3))
    lost = rig.until(lambda: rig.event(MoveState.COMM_LOST))
    assert "no process data" in lost.text
    rig.until(lambda: rig.event(MoveState.WARNING))  # it answers again
    for _ in range(20):
        rig.step()
    rig.drain()
    stamps = np.array([s.stamp_ns for s in rig.samples])
    gaps = np.diff(stamps) // 1_000_000
    assert gaps.max() >= 250  # the silence (0.3 s of the drive's time) left a hole in the samples ...
    assert set(gaps[gaps < 250]) == {1}  # ... and no sample elsewhere was missed or repeated
    n = len(rig.seen_events)
    rig.sender.stop("back", reset_fault=True)
    rig.until(lambda: rig.event(MoveState.ENABLED, n))


@pytest.mark.slow
def test_a_quick_stop_is_braked_by_the_bridge_and_the_drive_stays_enabled(canbus, port):
    rig = _rig(canbus.stack, canbus, port, FaultPlan())
    move = rig.sender.send(0.0, 0.7, 1.2)
    rig.until(lambda: rig.status(move.move_id, MoveState.STARTED))
    for _ in range(500):  # near the top speed (1.1 m/s)
        rig.step()
    rig.sender.stop("test")
    stopped = rig.until(lambda: rig.status(0, MoveState.STOPPED))
    assert "physical minimum" in stopped.text and rig.status(move.move_id, MoveState.STOPPED)
    for _ in range(300):
        rig.step()
    rig.drain()
    assert abs(rig.samples[-1].velocity_m_s) < 1e-3 and rig.samples[-1].position_m < 0.7
    assert [s.state for s in rig.seen_events if s.state.value >= MoveState.FAULT.value] == []
    assert rig.master.drives[0].status().following  # the bridge braked; the drive never left enabled
