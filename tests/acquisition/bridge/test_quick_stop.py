"""The quick stop: the bridge abandons its queue and brakes the running move to rest within the torque
limit, inside the stroke, then holds; distance and time against the axis's physical minimum."""

import numpy as np
import pytest
from axisflow.acquisition import (
    AxisKeys,
    BridgeConfig,
    MoveSender,
    MoveState,
    SimulatedAxis,
    ZenohOptions,
    load_plant,
    open_session,
)
from axisflow.acquisition.bridge.bridge import Bridge
from axisflow.acquisition.wire.quick_stop import STOP_MOVE_ID
from axisflow.model import default_params, stop_profile
from axisflow.planner import Case, MoveProblem, solve_exact
from axisflow.planner.reference_laws import _Phases

from axisflow.deploy.processes import wait_until

P = default_params()
T0 = 1_700_000_000_000_000_000


def test_the_stop_profile_is_the_full_force_braking_of_the_reference_laws():
    for v0 in (1.5, 0.9, -0.6, 0.05):
        fastest = stop_profile(0.4, v0, P)
        t_ref, x_ref = _Phases(P).brake(abs(v0))  # the reference laws' braking integrals, by quadrature
        assert fastest.distance_m == pytest.approx(x_ref, rel=1e-5)  # RK4 at 1 ms against quadrature
        assert fastest.time_s == pytest.approx(t_ref, rel=2e-3, abs=2e-5)
        traj = fastest.trajectory
        assert traj.velocity_m_s[0] == v0 and traj.velocity_m_s[-1] == 0.0
        assert np.all(np.sign(traj.velocity_m_s[:-1]) == np.sign(v0))  # no reversal
    margin = stop_profile(0.4, 1.5, P, force_fraction=0.9)
    assert margin.distance_m > stop_profile(0.4, 1.5, P).distance_m


def _step_until(bridge, sender, move_id, state, trace=None, timeout_s=20.0):
    """Step the bridge until the sender has the status; ``trace`` gets the plant's (x, v) after each
    tick."""

    def got() -> list:
        bridge.step()
        if trace is not None:
            trace[bridge.tick - 1] = (bridge.drive.position_m, bridge.drive.velocity_m_s)
        sender.poll_status()
        return [s for s in sender.statuses if s.move_id == move_id and s.state is state]

    if not wait_until(got, timeout_s, 0.0002):
        pytest.fail(f"no {state.name} of move {move_id}: {sender.statuses}")
    return next(s for s in sender.statuses if s.move_id == move_id and s.state is state)


def test_a_fast_move_is_braked_to_rest_and_the_queue_dropped(port):
    keys = AxisKeys("a0")
    plant = load_plant(None, P)
    drive = SimulatedAxis(plant, P, T0, axis="a0")
    fastest_move = solve_exact(MoveProblem(0.0, 0.8, "poly5", Case.MIN_TIME), P).duration_s
    with (
        open_session(ZenohOptions.loopback(listen_port=port)) as session,
        Bridge(session, drive, P, BridgeConfig(keys=keys, speed=0.0)) as bridge,
        open_session(ZenohOptions.loopback(connect_port=port)) as planner,
        MoveSender(planner, keys) as sender,
    ):
        assert sender.wait_for_bridge(10.0)
        first = sender.send(0.0, 0.8, fastest_move, law="poly5")
        second = sender.send(0.8, 0.2, 1.0, law="poly5")
        accepted = _step_until(bridge, sender, second.move_id, MoveState.ACCEPTED)
        while bridge.tick < accepted.start_tick - round(fastest_move * 1000 * 0.6):  # before the top speed
            bridge.step()
        # the plant's (x, v) after each tick, from the last one before the stop is sent (the bridge
        # may take the request on the very next tick)
        trace = {bridge.tick - 1: (drive.position_m, drive.velocity_m_s)}
        sender.stop("test")
        stopped = _step_until(bridge, sender, STOP_MOVE_ID, MoveState.STOPPED, trace)
        x_stop, v_stop = trace[stopped.start_tick - 1]  # where the plant was when braking began
        for _ in range(500):  # hold
            bridge.step()
        statuses = {(s.move_id, s.state) for s in sender.statuses}
    assert (first.move_id, MoveState.STOPPED) in statuses and (second.move_id, MoveState.DROPPED) in statuses
    assert (first.move_id, MoveState.COMPLETED) not in statuses
    assert bridge.report.quick_stops == 1 and bridge.report.moves_dropped == 1
    # the plant came to rest inside the stroke, about as fast as the axis can
    assert drive.velocity_m_s == 0.0 and 0.0 < drive.position_m < 0.8
    physical = stop_profile(x_stop, v_stop, plant.axis)  # the true axis at full force
    distance, ticks = drive.position_m - x_stop, stopped.end_tick - stopped.start_tick
    assert v_stop > 1.0
    assert physical.distance_m <= distance <= 1.35 * physical.distance_m
    assert ticks * 1e-3 <= 1.25 * physical.time_s + 0.002
    assert "physical minimum" in stopped.text
