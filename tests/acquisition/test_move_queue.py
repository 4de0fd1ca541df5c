"""Move validation (table of rejections) and queue timing (no idle tick between queued moves)."""

import pytest
from axisflow.acquisition import MoveCommand, MoveQueue, MoveRejectedError
from axisflow.model import AxisParams

# a fixed axis (the paper's geometry), so the tests do not depend on the packaged defaults
PARAMS = AxisParams(
    m=20.0, J_m=1.5e-4, J_g=5e-5, J_p=2e-4, r=0.03, i_r=10.0, L=0.8,
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
    queue = MoveQueue(PARAMS.replace(tau_max=0.2), 0.2, T0, "a0")
    with pytest.raises(MoveRejectedError, match=r"peak motor torque 0.7\d* N·m exceeds tau_max = 0.2 N·m"):
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


def test_feed_forward_matches_eq1():
    from axisflow.model import cart_force

    params = PARAMS
    queue = MoveQueue(params, 0.2, T0, "a0")
    queue.submit(_move(0.2, 0.6, 1.0), 0)
    sp = queue.setpoint(300)
    assert sp.force_ff_n == pytest.approx(float(cart_force(sp.velocity_m_s, sp.acceleration_m_s2, params)))


def test_a_move_shorter_than_a_tick_is_checked_along_its_course():
    """At 1 kHz alone a 1 ms move has samples at 0 and 1 ms, where it is at rest; its torque peaks
    between them."""
    from axisflow.model import Move, check_limits, polynomial_law

    queue = MoveQueue(PARAMS, 0.2, T0, "a0")
    cmd = _move(0.2, 0.2003, 0.001)  # peak velocity 0.56 m/s: within v_max
    sampled = check_limits(Move(0.2, 0.2003, 0.001, polynomial_law("poly5")), PARAMS)
    assert sampled.samples == 2 and sampled.peak_torque_nm == 0.0  # what 1 kHz alone sees
    with pytest.raises(MoveRejectedError, match=r"peak motor torque \d+\.?\d* N·m exceeds tau_max = 3.0 N·m"):
        queue.submit(cmd, 0)


def test_moves_longer_than_an_hour_are_refused():
    queue = MoveQueue(PARAMS, 0.2, T0, "a0")
    with pytest.raises(MoveRejectedError, match=r"duration_s = 3700.0 s exceeds the longest move, 3600 s"):
        queue.submit(_move(0.2, 0.3, 3700.0), 0)


def test_a_gone_sender_loses_its_moves_not_started_and_those_queued_after_them():
    queue = MoveQueue(PARAMS, 0.2, T0, "a0")
    a, b = b"A" * 16, b"B" * 16
    queue.submit(_move(0.2, 0.4, 1.0, move_id=1), 0, a)  # ticks 0..1000
    queue.submit(_move(0.4, 0.5, 1.0, move_id=2), 0, b)  # 1000..2000
    queue.submit(_move(0.5, 0.3, 1.0, move_id=3), 0, a)  # 2000..3000
    queue.submit(_move(0.3, 0.6, 1.0, move_id=4), 0, b)  # 3000..4000
    assert queue.drop_sender(b"C" * 16, 10) == []
    dropped = queue.drop_sender(a, 500)  # move 1 runs: kept; move 3 and what follows it: dropped
    assert [q.command.move_id for q in dropped] == [3, 4]
    assert len(queue) == 2 and queue.end_position_m == pytest.approx(0.5)
    dropped = queue.drop_sender(b, 1000)  # move 2 starts at tick 1000, not yet run: dropped
    assert [q.command.move_id for q in dropped] == [2]
    assert queue.end_position_m == pytest.approx(0.4)
    assert [queue.setpoint(k).position_m for k in (999, 1000, 1500)] == [
        pytest.approx(0.4, abs=1e-8),  # the last in-motion sample of move 1
        0.4,  # then the axis holds at its end
        0.4,
    ]


def test_the_queue_holds_a_bounded_number_of_moves(monkeypatch):
    monkeypatch.setattr("axisflow.acquisition.move_queue.MAX_QUEUED_MOVES", 3)
    queue = MoveQueue(PARAMS, 0.2, T0, "a0")
    for k in range(3):
        x0, x1 = (0.2, 0.3) if k % 2 == 0 else (0.3, 0.2)
        queue.submit(_move(x0, x1, 0.5, move_id=k), 0)
    with pytest.raises(MoveRejectedError, match=r"move 9: the queue is full \(3 moves\)"):
        queue.submit(_move(0.3, 0.2, 0.5, move_id=9), 0)


def test_a_negative_jump_tolerance_is_refused():
    with pytest.raises(MoveRejectedError, match=r"jump tolerance = -1.0 m must be >= 0 m"):
        MoveQueue(PARAMS, 0.2, T0, "a0", jump_tolerance_m=-1.0)
