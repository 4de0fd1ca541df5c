"""Move validation (table of rejections) and queue timing (no idle tick between queued moves)."""

import math

import numpy as np
import pytest
from axisflow.acquisition import MoveCommand, MoveQueue, MoveRejectedError
from axisflow.acquisition.bridge.move_queue import SETPOINT_BLOCK_TICKS
from axisflow.acquisition.drives.drive import Setpoint
from axisflow.acquisition.wire.messages import SAMPLED_LAW, Knots
from axisflow.identification.excitation import design_excitation
from axisflow.model import EXECUTION_PERIOD_S, AxisParams, cart_force, default_params
from axisflow.model.transmission import Belt

# a fixed axis (the paper's geometry), so the tests do not depend on the packaged defaults
PARAMS = AxisParams(
    m=20.0, transmission=Belt(J_m=1.5e-4, J_g=5e-5, J_p=2e-4, r=0.03, i_r=10.0), L=0.8,
    a1=100.0, a2=50.0, a3=20.0, a4=50.0, v_max=1.0, tau_max=3.0,
)  # fmt: skip
T0 = 1_700_000_000_000_000_000
MS = 1_000_000


def _move(x0, x1, duration_s, law="poly5", start_ns=0, move_id=1, axis="a0"):
    return MoveCommand(0, axis, move_id, start_ns, law, x0, x1, duration_s)


@pytest.mark.parametrize(
    ("cmd", "match"),
    [
        (_move(0.2, 0.9, 2.0), r"end_position_m = 0.9 m is outside the stroke \[0, 0.8\] m"),
        (_move(0.3, 0.5, 1.0), r"jumps 0.1 m from the axis's position 0.2 m"),
        (_move(0.2, 0.7, 0.3), r"peak velocity 3.125 m/s exceeds v_max = 1.0 m/s"),
        (_move(0.2, 0.5, 1.0, law="poly9"), "unknown motion law 'poly9'"),
        (_move(0.2, 0.5, 0.0), "duration_s = 0.0 s must be > 0 s"),
        (_move(0.2, 0.5, 1.0, axis="a1"), "addressed to axis 'a1', this drive is 'a0'"),
        (_move(0.2, 0.5, 1.0, start_ns=T0 - 5 * MS), "5 ms before the end of the queued moves"),
    ],
)
def test_rejections_name_value_and_limit(cmd, match):
    queue = MoveQueue(PARAMS, 0.2, T0, "a0")
    with pytest.raises(MoveRejectedError, match=match):
        queue.submit(cmd, 0)
    assert len(queue) == 0


def test_torque_limit_rejects():
    queue = MoveQueue(PARAMS.replace(tau_max=0.5), 0.2, T0, "a0")  # F_max = 167 N > a1 = 100 N
    with pytest.raises(MoveRejectedError, match=r"peak motor torque 0.7\d* N·m exceeds tau_max = 0.5 N·m"):
        queue.submit(_move(0.2, 0.6, 1.0), 0)


def test_appended_moves_run_back_to_back_without_idle_tick():
    queue = MoveQueue(PARAMS, 0.2, T0, "a0")
    a = queue.submit(_move(0.2, 0.6, 1.0, move_id=1), 10)
    b = queue.submit(_move(0.6, 0.3, 0.8005, move_id=2), 20)
    assert (a.start_tick, a.end_tick) == (10, 1010)
    assert (b.start_tick, b.end_tick) == (1010, 1811)  # 800.5 ms -> 801 ticks
    positions = [queue.setpoint(k).position_m for k in range(1900)]
    velocities = [queue.setpoint(k).velocity_m_s for k in range(1900, 1901)]
    assert positions[:11] == [0.2] * 11
    assert positions[1010] == pytest.approx(0.6)
    assert positions[1011] < 0.6  # the second move is already moving on the next tick
    assert positions[1811] == pytest.approx(0.3)
    assert velocities == [0.0]
    assert queue.completed == 2


def test_timed_start_holds_until_its_stamp():
    queue = MoveQueue(PARAMS, 0.2, T0, "a0")
    q = queue.submit(_move(0.2, 0.4, 0.5, start_ns=T0 + 100 * MS), 0)
    assert q.start_tick == 100
    assert queue.setpoint(50).position_m == 0.2
    assert queue.setpoint(101).position_m > 0.2


def test_feed_forward_is_eq1_of_the_poly5_sample():
    """The setpoint of tick 300 of a 1 s poly5 move 0.2 → 0.6 m, and its feed-forward force, written
    out by hand (x = x0 + d·(10u³ − 15u⁴ + 6u⁵), eq. (1) with the test axis's numbers)."""
    queue = MoveQueue(PARAMS, 0.2, T0, "a0")
    queue.submit(_move(0.2, 0.6, 1.0), 0)
    sp = queue.setpoint(300)
    u, d, T = 0.3, 0.4, 1.0
    x = 0.2 + d * (10 * u**3 - 15 * u**4 + 6 * u**5)
    v = d / T * (30 * u**2 - 60 * u**3 + 30 * u**4)
    a = d / T**2 * (60 * u - 180 * u**2 + 120 * u**3)
    m_eq = 20.0 + ((1.5e-4 + 5e-5) * 10.0**2 + 2 * 2e-4) / 0.03**2  # m + ((J_m + J_g)·i_r² + 2·J_p)/r²
    force = m_eq * a + 100.0 * 1.0 + 50.0 * v + 20.0 * math.atan(50.0 * v)
    assert (sp.position_m, sp.velocity_m_s, sp.acceleration_m_s2) == pytest.approx((x, v, a), rel=1e-12)
    assert sp.force_ff_n == pytest.approx(force, rel=1e-12)
    assert queue.setpoint(1000).velocity_m_s == 0.0 and queue.setpoint(1000).force_ff_n == 0.0  # at rest


def _sampled(t, x, v, a, move_id=5):
    from axisflow.acquisition.wire.messages import SAMPLED_LAW, Knots

    return MoveCommand(
        0, "a0", move_id, 0, SAMPLED_LAW, float(x[0]), float(x[-1]), float(t[-1]), Knots(t, x, v, a)
    )


def _cosine(x0, amplitude_m, freq_hz, periods, step_s=0.001):
    """x = x0 + A·(1 − cos ωt): at rest at both ends after whole periods."""
    w = 2 * math.pi * freq_hz
    t = np.arange(0.0, periods / freq_hz + step_s / 2, step_s)
    t[-1] = periods / freq_hz
    v = amplitude_m * w * np.sin(w * t)
    v[0] = v[-1] = 0.0
    return t, x0 + amplitude_m * (1 - np.cos(w * t)), v, amplitude_m * w * w * np.cos(w * t)


def test_a_sampled_move_runs_its_knots_at_the_ticks():
    t, x, v, a = _cosine(0.2, 0.1, 1.0, 2)
    queue = MoveQueue(PARAMS, 0.2, T0, "a0")
    q = queue.submit(_sampled(t, x, v, a), 0)
    assert (q.start_tick, q.end_tick) == (0, 2000)
    got = [queue.setpoint(k) for k in range(2001)]
    assert [s.position_m for s in got[:-1]] == pytest.approx(x[:-1], abs=1e-15)
    assert [s.velocity_m_s for s in got[:-1]] == pytest.approx(v[:-1], abs=1e-12)
    assert got[-1].position_m == pytest.approx(0.2, abs=1e-15) and got[-1].velocity_m_s == 0.0


@pytest.mark.parametrize(
    ("knots", "match"),
    [
        (_cosine(0.5, 0.2, 0.5, 1), r"path reaches 0.5 … 0.9 m, outside the stroke \[0, 0.8\] m"),
        (_cosine(0.2, 0.1, 2.0, 1), r"peak velocity 1.2566\d* m/s exceeds v_max = 1.0 m/s"),
        (_cosine(0.2, 0.001, 30.0, 3), r"peak motor torque \d+(\.\d+)? N·m exceeds tau_max = 3.0 N·m"),
    ],
    ids=["leaves-the-stroke", "too-fast", "too-much-torque"],
)
def test_a_sampled_move_is_validated_at_every_sample(knots, match):
    queue = MoveQueue(PARAMS, float(knots[1][0]), T0, "a0")
    with pytest.raises(MoveRejectedError, match=match):
        queue.submit(_sampled(*knots), 0)


def test_a_sampled_move_must_agree_with_its_own_end_points():
    from axisflow.acquisition.wire.messages import SAMPLED_LAW, Knots

    t, x, v, a = _cosine(0.2, 0.1, 1.0, 1)
    cmd = MoveCommand(0, "a0", 6, 0, SAMPLED_LAW, 0.2, 0.3, 1.0, Knots(t, x, v, a))
    with pytest.raises(MoveRejectedError, match=r"move 6: end_position_m = 0.3 differs from its knots' 0.2"):
        MoveQueue(PARAMS, 0.2, T0, "a0").submit(cmd, 0)
    with pytest.raises(MoveRejectedError, match="move 1: law 'sampled' needs knots"):
        MoveQueue(PARAMS, 0.2, T0, "a0").submit(_move(0.2, 0.3, 1.0, law="sampled"), 0)


def test_sampled_moves_fill_the_queue_to_its_knot_budget_and_no_further(monkeypatch):
    from axisflow.acquisition.bridge import move_queue

    t, x, v, a = _cosine(0.2, 0.1, 1.0, 2)  # 2 s at 1 ms: 2001 knots each, ending where they start
    monkeypatch.setattr(move_queue, "MAX_QUEUED_KNOTS", 5000)
    queue = MoveQueue(PARAMS, 0.2, T0, "a0")
    first = queue.submit(_sampled(t, x, v, a), 0)
    queue.submit(_sampled(t, x, v, a), 0)
    assert queue.queued_knots == 2 * len(t)
    with pytest.raises(
        MoveRejectedError, match=r"its 2001 knots and the 4002 queued would pass the limit of 5000"
    ):
        queue.submit(_sampled(t, x, v, a), 0)
    queue.submit(_move(0.2, 0.3, 1.0), 0)  # a polynomial move has no knots: the budget does not bind it
    for k in range(first.end_tick + 1):  # the first move runs out and leaves the queue
        queue.advance(k)
    assert queue.queued_knots == len(t)
    later = queue.submit(_sampled(*_cosine(0.3, 0.1, 1.0, 2)), first.end_tick)  # fits the budget now
    assert queue.queued_knots == 2 * len(t) and later.start_tick > first.end_tick
    # the count is kept as moves leave: a dropped sender's moves, a quick stop's abandoned queue
    now = first.end_tick + 10  # the second sampled move runs
    queue.advance(now)
    queue.drop_sender(b"", now)  # drops the polynomial move and the later sampled one
    assert queue.queued_knots == len(t) == _knots_in(queue)
    stop = queue.quick_stop(now + 500)  # brakes the running sampled move with a sampled profile
    assert stop.braking is not None and queue.queued_knots == len(stop.braking.command.knots)
    assert queue.queued_knots == _knots_in(queue)


def _knots_in(queue: MoveQueue) -> int:
    """The knots of the moves in the queue, counted from scratch."""
    return sum(len(q.command.knots) for q in queue._queue if q.command.knots is not None)


def _one_tick_at_a_time(move, offset: int, params):
    """The setpoint of a tick as the queue computed it before it sampled moves by blocks."""
    s = move.sample(offset * EXECUTION_PERIOD_S)
    v, a = float(s.velocity_m_s), float(s.acceleration_m_s2)
    return Setpoint(float(s.position_m), v, a, float(cart_force(v, a, params)))


@pytest.mark.parametrize("law", ["poly3", "poly5", "poly7", "sampled"])
def test_block_sampled_setpoints_equal_one_tick_at_a_time_bit_for_bit(law):
    params = default_params()
    if law == "sampled":  # a burst of the identification excitation (knots 1 ms apart)
        traj = design_excitation(params).trajectories()[1]
        knots = Knots.of(traj)
        cmd = MoveCommand(0, "a0", 1, 0, SAMPLED_LAW, traj.x0_m, traj.x1_m, traj.duration_s, knots)
    else:
        cmd = _move(0.1, 0.7, 2.5, law)
    q = MoveQueue(params, cmd.start_position_m, 0, "a0")
    queued = q.submit(cmd, 0)
    assert queued.end_tick - queued.start_tick > 2 * SETPOINT_BLOCK_TICKS  # several blocks
    for tick in range(queued.start_tick, queued.end_tick + 2):
        step = q.advance(tick)
        if tick < queued.end_tick:
            expected = _one_tick_at_a_time(queued.move, tick - queued.start_tick, params)
        else:
            expected = Setpoint(queued.move.x1_m, 0.0, 0.0, 0.0)  # held at the end point
        assert step.setpoint == expected, tick
        sample = expected.to_sample(0, "a0", params)
        assert step.motor == (sample.motor_angle_rad, sample.motor_speed_rad_s, sample.motor_torque_nm)
