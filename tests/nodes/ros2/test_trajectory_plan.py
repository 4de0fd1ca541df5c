"""Way points planned into moves: the planner's plan for untimed points, the law at the asked duration
on the tick grid for timed ones, refused below the law's minimum time — the threshold checked against
the 1 kHz limit check (an independent bisection), real planner solves."""

from __future__ import annotations

import math

import pytest
from axisflow.model import EXECUTION_PERIOD_S, Move, check_limits, default_params, move_ticks, polynomial_law
from axisflow.planner import Case, ExactBackend, MoveProblem, make_backend

from axisflow.nodes.ros2.errors import TrajectoryRefusedError
from axisflow.nodes.ros2.settings import MotionSettings
from axisflow.nodes.ros2.trajectory_plan import FIXED_DURATION, TrajectoryPlanner
from axisflow.nodes.ros2.trajectory_request import TrajectoryRequest, WayPoint


@pytest.fixture(scope="module")
def params():
    return default_params()


@pytest.fixture(scope="module")
def planner(params):
    p = TrajectoryPlanner(make_backend("exact"), params, MotionSettings())
    p.prepare()
    return p


def request(*points):
    return TrajectoryRequest(tuple(WayPoint(x, t) for x, t in points))


def test_untimed_points_are_the_planners_moves(planner, params):
    plan = planner.plan(request((0.3, None), (0.1, None)), 0.0)
    for move, (x0, x1) in zip(plan.moves, [(0.0, 0.3), (0.3, 0.1)], strict=True):
        expected = ExactBackend().solve(MoveProblem(x0, x1, polynomial_law("poly5"), Case.MIN_TIME), params)
        assert move.duration_s == expected.duration_s and move.energy_j == expected.energy_j
        assert not move.timed and move.plan.solver == "exact"
    assert plan.moves[1].end_tick == move_ticks(plan.moves[0].duration_s) + move_ticks(
        plan.moves[1].duration_s
    )


def test_timed_points_arrive_on_the_first_tick_at_or_after_their_time(planner):
    plan = planner.plan(request((0.3, None), (0.1, 2.0004), (0.6, 4.5)), 0.0)
    first, second, third = plan.moves
    assert second.end_tick == 2001 and third.end_tick == 4500  # never accumulating the rounding
    assert second.duration_s == pytest.approx((2001 - first.end_tick) * EXECUTION_PERIOD_S, abs=1e-12)
    assert third.duration_s == pytest.approx(2.499, abs=1e-12)
    assert second.timed and second.plan.solver == FIXED_DURATION
    assert second.plan.max_violation == 0.0 and third.plan.max_violation == 0.0
    assert plan.duration_s == pytest.approx(4.5)


def test_a_timed_point_where_the_axis_is_holds_it(planner):
    plan = planner.plan(request((0.2, 1.0), (0.2, 1.75)), 0.2)
    assert [(m.start_m, m.end_m, m.duration_s) for m in plan.moves] == [(0.2, 0.2, 1.0), (0.2, 0.2, 0.75)]
    assert all(m.sent for m in plan.moves)


def test_an_untimed_repeated_point_is_a_zero_move_not_sent(planner):
    plan = planner.plan(request((0.4, None), (0.4, None)), 0.0)
    assert plan.moves[0].sent and not plan.moves[1].sent
    assert plan.moves[1].end_tick == plan.moves[0].end_tick


def _limit_bisection(x0: float, x1: float, params) -> float:
    """The shortest duration (to 1 µs) at which the poly5 move meets the limits at the 1 kHz samples:
    the limit check itself, not the planner."""
    lo, hi = 1e-3, 10.0
    while hi - lo > 1e-6:
        mid = 0.5 * (lo + hi)
        if check_limits(Move(x0, x1, mid, polynomial_law("poly5")), params).ok:
            hi = mid
        else:
            lo = mid
    return hi


@pytest.mark.parametrize(("x0", "x1"), [(0.0, 0.5), (0.7, 0.65), (0.1, 0.8)])
def test_the_refusal_threshold_is_the_laws_minimum_time(planner, params, x0, x1):
    t_min = _limit_bisection(x0, x1, params)
    slow_enough = math.ceil((t_min + 2e-3) * 1e3) / 1e3
    ok = planner.plan(request((x1, slow_enough)), x0)
    assert ok.moves[0].duration_s == pytest.approx(slow_enough)
    too_fast = math.floor((t_min - 2e-3) * 1e3) / 1e3
    with pytest.raises(TrajectoryRefusedError) as refused:
        planner.plan(request((x1, too_fast)), x0)
    text = str(refused.value)
    assert f"point 0 asks to arrive {too_fast:.6g} s after the start" in text
    assert "faster than the fastest poly5 move" in text and "tau_max = 4.0 N·m" in text
    fastest = float(text.split("fastest poly5 move, ")[1].split(" s")[0])
    assert fastest == pytest.approx(t_min, abs=2e-3)


@pytest.mark.parametrize(
    ("points", "start", "says"),
    [
        (((0.9, None),), 0.0, "point 0: position 0.9 m is outside the stroke [0, 0.8] m"),
        (
            ((0.3, 2.0), (0.1, 1.5)),
            0.0,
            "point 1 asks to arrive at 1.5 s, but the axis reaches point 0 only at 2 s",
        ),
        (((0.3, None), (0.1, 1e-4)), 0.0, "point 1 asks to arrive at 0.0001 s"),
        (((0.3, 4000.0),), 0.0, "a move of 4000 s is longer than the longest move, 3600 s"),
        (((0.3, None), (0.5, 0.7), (0.6, 0.75)), 0.0, "point 1"),
    ],
)
def test_a_refusal_names_the_point_the_value_and_the_limit(planner, points, start, says):
    with pytest.raises(TrajectoryRefusedError) as refused:
        planner.plan(request(*points), start)
    assert says in str(refused.value)


def test_ipopt_plans_the_untimed_points_with_its_cap(params):
    planner = TrajectoryPlanner(
        make_backend("ipopt", max_iter=10), params, MotionSettings(Case.MIN_TIME_ENERGY)
    )
    planner.prepare()
    plan = planner.plan(request((0.5, None), (0.2, 7.0)), 0.1)
    assert plan.moves[0].plan.solver == "ipopt" and plan.moves[0].plan.max_violation == 0.0
    assert plan.moves[1].plan.solver == FIXED_DURATION and plan.moves[1].end_tick == 7000
