"""Faults, comm loss, the drive's own quick stop and several drives on one bus, against simulated
drives on a virtual bus in lock-step (the master reports; the bridge's reaction is
test_bridge_canopen.py's)."""

import pytest
from axisflow.acquisition.drives.canopen.cia402 import State
from axisflow.acquisition.drives.canopen.sim_drive import FaultPlan
from axisflow.acquisition.drives.drive import DriveEventKind as K
from axisflow.acquisition.drives.drive import Setpoint
from axisflow.model import Move, polynomial_law


def test_an_injected_fault_is_reported_with_its_code_and_reset(canbus, runner, hold_at):
    config = canbus.config()
    sim = canbus.sim(config, faults=FaultPlan(fault_at_s=0.2, fault_code=0x2310))
    master = canbus.master(config)
    run = runner(master)
    x = master.drives[0].read().position_m
    run.until(lambda: K.FAULT in run.kinds(), [hold_at(x)])
    fault = run.events[0][-1]
    assert (fault.error_code, fault.error_register) == (0x2310, 0x03)
    assert (
        "drive node 5 (axis a0) faulted (fault" in fault.text
        and "0x2310 continuous over-current" in fault.text
    )
    assert sim.state is State.FAULT and not master.drives[0].status().following
    fresh_before = len(run.samples[0])
    for _ in range(20):
        run.tick([hold_at(x)])
    assert len(run.samples[0]) == fresh_before + 20  # a faulted drive still measures: samples go on
    master.drives[0].reset_fault()
    run.until(lambda: run.kinds()[-1] is K.ENABLED, [hold_at(x)])
    assert sim.state is State.OPERATION_ENABLED and master.drives[0].status().following
    assert int.from_bytes(master.drives[0].node.sdo.upload(0x603F, 0), "little") == 0


def test_a_following_error_faults_the_drive_with_0x8611(canbus, runner, hold_at):
    config = canbus.config({"node_id": 5, "axis": "a0", "following_error_window_m": 1e-4,
                            "following_error_timeout_ms": 5})  # fmt: skip
    canbus.sim(config)
    master = canbus.master(config)
    run = runner(master)
    run.until(lambda: K.FAULT in run.kinds(), [hold_at(0.05)])  # a 5 cm jump of the target
    assert run.events[0][-1].error_code == 0x8611 and "following error" in run.events[0][-1].text


@pytest.mark.slow
def test_a_silent_drive_is_comm_lost_quick_stopped_and_back_after_a_reset(canbus, runner, hold_at, until):
    config = canbus.config()
    sim = canbus.sim(config, faults=FaultPlan(silent_at_s=0.1, silent_for_s=0.4))
    master = canbus.master(config)
    run = runner(master)
    drive = master.drives[0]
    x = drive.read().position_m
    run.until(lambda: K.COMM_LOST in run.kinds(), [hold_at(x)])
    lost = run.events[0][-1]
    assert "no process data (TPDO 1, COB-ID 0x185)" in lost.text
    n = len(run.samples[0])
    for _ in range(50):
        run.tick([hold_at(x)])
    assert len(run.samples[0]) == n  # nothing fresh while it is silent
    assert not any(s.fresh for s in run.statuses[0][-50:])
    until(lambda: sim.state is State.QUICK_STOP_ACTIVE)  # it still hears the master's quick stop
    drive.reset_fault()
    run.until(lambda: K.FAULT in run.kinds(), [hold_at(x)])
    assert "fault reset failed" in run.events[0][-1].text  # a reset of a silent drive fails at once
    run.until(lambda: K.WARNING in run.kinds(), [hold_at(x)])
    assert "answers again" in run.events[0][-1].text and len(run.samples[0]) > n
    drive.reset_fault()
    run.until(lambda: run.kinds()[-1] is K.ENABLED, [hold_at(x)])
    assert sim.state is State.OPERATION_ENABLED


def test_closing_the_master_quick_stops_and_switches_off_the_drive(canbus, runner):
    config = canbus.config()
    sim = canbus.sim(config)
    master = canbus.master(config)
    run = runner(master)
    move, start = Move(0.0, 0.6, 1.2, polynomial_law("poly5")), master.cycle.clock.tick

    def along(tick):
        s = move.sample((tick - start) * 1e-3)
        return Setpoint(float(s.position_m), float(s.velocity_m_s), 0.0, 0.0)

    for _ in range(600):  # at the top speed (0.94 m/s) when the master closes
        run.tick([along])
    assert sim.axis.velocity_m_s > 0.8
    master.close()
    assert sim.state is State.SWITCH_ON_DISABLED and sim.axis.velocity_m_s == 0.0
    assert not sim.operational  # NMT pre-operational


def test_several_drives_share_one_sync_and_keep_their_own_faults(canbus, runner, hold_at):
    config = canbus.config({"node_id": 1, "axis": "a0"}, {"node_id": 2, "axis": "a1"})
    canbus.sim(config, 0)
    sim1 = canbus.sim(config, 1, FaultPlan(fault_at_s=0.3, fault_code=0x3210))
    master = canbus.master(config)
    listener = canbus.listener()
    run = runner(master)
    ids = []
    for _ in range(100):
        run.tick([hold_at(0.0), hold_at(0.0)])
        while (frame := listener.recv(0)) is not None:
            ids.append(frame.arbitration_id)
    while (frame := listener.recv(0.05)) is not None:
        ids.append(frame.arbitration_id)
    assert ids.count(0x080) == 100  # one SYNC per cycle for both
    for cob in (0x201, 0x301, 0x181, 0x281, 0x202, 0x302, 0x182, 0x282):
        assert ids.count(cob) == 100, hex(cob)
    run.until(lambda: K.FAULT in run.kinds(1), [hold_at(0.0), hold_at(0.0)])
    assert run.events[1][-1].error_code == 0x3210 and sim1.state is State.FAULT
    for _ in range(50):
        run.tick([hold_at(0.0), hold_at(0.0)])
    assert run.kinds(0) == [] and master.drives[0].status().following  # axis a0 goes on
