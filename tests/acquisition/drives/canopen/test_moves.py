"""Moves through the adapter and the simulated drive in lock-step: the plant follows as it does behind
the built-in simulated axis (same setpoints, the drive's quantisation and one bus cycle of latency),
samples come in the drive's units converted back, with the polarity and zero of the configuration, and
at slower bus cycles the drive interpolates."""

from dataclasses import replace

import numpy as np
import pytest
from axisflow.acquisition.drives.drive import Setpoint
from axisflow.acquisition.drives.sim_axis import SimulatedAxis
from axisflow.model import Move, cart_force, default_params, polynomial_law

MOVE = Move(0.1, 0.5, 0.8, polynomial_law("poly5"))
PARAMS = default_params()


def _setpoints(start_tick):
    def at(tick):
        s = MOVE.sample(min(max(tick - start_tick, 0) * 1e-3, MOVE.duration_s))
        v, a = float(s.velocity_m_s), float(s.acceleration_m_s2)
        return Setpoint(float(s.position_m), v, a, float(cart_force(v, a, PARAMS)))

    return at


def _run(canbus, runner, config, ticks=1200):
    canbus.plant = replace(canbus.plant, simulation=replace(canbus.plant.simulation, initial_position_m=0.1))
    sim = canbus.sim(config)
    master = canbus.master(config)
    run = runner(master)
    start = master.cycle.clock.tick
    for _ in range(ticks):
        run.tick([_setpoints(start)])
    return sim, master, run, start


def test_a_move_tracks_like_the_built_in_simulated_axis(canbus, runner):
    config = canbus.config()
    _sim, master, run, start = _run(canbus, runner, config)
    samples = run.samples[0]
    # the reference: the same plant behind the built-in axis, fed the same setpoints tick by tick
    reference = SimulatedAxis(canbus.plant, canbus.params, 0)
    at = _setpoints(start)
    reference_x = []
    for tick in range(start, start + 1200):
        reference_x.append(reference.read().position_m)
        reference.apply(at(tick))
    ticks = [(s.stamp_ns - canbus_t0(master)) // 1_000_000 for s in samples]
    measured = dict(zip(ticks, (s.position_m for s in samples), strict=True))
    common = [t for t in range(start, start + 1199) if t in measured]
    gap = max(abs(measured[t] - reference_x[t - start]) for t in common)
    assert len(common) > 1150
    assert gap < 5e-6  # the drive's quantisation of target (0.19 µm) and feed-forward (1.3 mN·m) only
    assert samples[-1].position_m == pytest.approx(0.5, abs=1e-4)
    assert run.kinds() == [] and all(s.following and s.commanded for s in run.statuses[0])


def canbus_t0(master):
    return master.cycle.clock.start_stamp_ns


def test_samples_are_in_the_drives_units_stamped_when_measured(canbus, runner):
    config = canbus.config()
    _sim, master, run, _start = _run(canbus, runner, config, ticks=400)
    drive = master.drives[0]
    u = drive.units
    samples = run.samples[0]
    stamps = np.array([s.stamp_ns for s in samples])
    assert set(np.diff(stamps)) == {1_000_000}  # one fresh sample per tick, 1 ms apart
    # a sample read at tick k was measured at the SYNC of tick k − 1 (one bus cycle of latency); the
    # last tick run was clock.tick − 1
    assert (stamps[-1] - canbus_t0(master)) // 1_000_000 == master.cycle.clock.tick - 2
    counts = np.array([s.position_m for s in samples]) / u.metres_per_count
    torques = np.array([s.motor_torque_nm for s in samples]) / u.newton_metres_per_unit
    assert np.allclose(counts, np.round(counts), atol=1e-6) and np.allclose(
        torques, np.round(torques), atol=1e-6
    )
    assert len(set(np.round(torques))) > 20  # and they vary: real measurements


def test_a_reversed_motor_with_its_zero_elsewhere_moves_the_cart_the_same_way(canbus, runner):
    config = canbus.config({"node_id": 5, "axis": "a0", "direction": -1, "zero_counts": 1_000_000})
    sim, master, run, _ = _run(canbus, runner, config)
    assert run.samples[0][-1].position_m == pytest.approx(0.5, abs=1e-4)
    raw = int.from_bytes(master.drives[0].node.sdo.upload(0x6064, 0), "little", signed=True)
    expected = 1_000_000 - round(0.5 / master.drives[0].units.metres_per_count)
    assert raw < 1_000_000 and abs(raw - expected) < 600  # the counts fell as the cart moved to +x
    assert sim.axis.position_m == pytest.approx(0.5, abs=1e-4)


def test_at_250_hz_the_drive_is_commanded_every_fourth_tick_and_interpolates(canbus, runner):
    config = canbus.config(cycle_hz=250)
    _sim, _master, run, _ = _run(canbus, runner, config)
    statuses = run.statuses[0]
    assert sum(s.commanded for s in statuses) == len(statuses) // 4
    samples = run.samples[0]
    assert set(np.diff([s.stamp_ns for s in samples])) == {4_000_000}
    assert samples[-1].position_m == pytest.approx(0.5, abs=2e-4)
