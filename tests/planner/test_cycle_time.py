"""A cycle of moves at a given cycle time: move by move, or the ω that meets the total."""

import dataclasses
import math

import pytest
from axisflow.model import Move, default_params, move_energy, polynomial_law
from axisflow.planner.cycle_time import MatchStatus, match_cycle_time, plan_at_durations

MOVES = [(0.1, 0.62), (0.62, 0.55), (0.55, 0.02), (0.02, 0.3), (0.3, 0.3 + 1e-8), (0.3, 0.79)]


def test_move_by_move_takes_each_duration_or_the_fastest_the_law_can():
    p = default_params()
    durations = [1.1, 0.5, 0.2, 0.9, 0.0, 1.4]  # 0.53 m in 0.2 s is beyond the torque limit
    plan = plan_at_durations(MOVES, "poly5", durations, p)
    assert plan.slower_moves == (2,)
    for k, (r, t) in enumerate(zip(plan.results, durations, strict=True)):
        if k == 2:
            assert r.duration_s > t and r.max_violation == 0.0
        else:
            assert r.duration_s == pytest.approx(t, rel=1e-12)
    assert plan.results[4].zero_move


def test_the_matched_omega_spends_the_least_energy_on_the_cycle_time():
    p = default_params()
    durations = [1.1, 0.5, 0.9, 0.9, 0.0, 1.4]
    by_move = plan_at_durations(MOVES, "poly3", durations, p)
    match = match_cycle_time(MOVES, "poly3", by_move.total_time_s, p)
    assert match.status is MatchStatus.MATCHED
    assert match.plan.total_time_s == pytest.approx(by_move.total_time_s, rel=1e-9)
    assert match.plan.total_energy_j < by_move.total_energy_j
    # no shift of time between two moves lowers the total energy (the constrained optimum)
    law = polynomial_law("poly3")
    r = [x for x in match.plan.results if not x.zero_move]
    base = [move_energy(Move(x.problem.x0_m, x.problem.x1_m, x.duration_s, law), p) for x in r]
    for i, j in ((0, 1), (1, 3), (2, 4)):
        for dt in (-0.01, 0.01):
            moved = list(base)
            for k, sign in ((i, 1), (j, -1)):
                x = r[k]
                moved[k] = move_energy(Move(x.problem.x0_m, x.problem.x1_m, x.duration_s + sign * dt, law), p)
            assert math.fsum(moved) >= math.fsum(base)


def test_a_cycle_time_below_the_laws_fastest_cannot_be_met():
    p = default_params()
    match = match_cycle_time(MOVES, "poly7", 1.0, p)
    assert match.status is MatchStatus.TOO_SLOW and match.omega == 1.0
    assert match.plan.total_time_s > 1.0
    # a slower axis takes longer still at ω = 1
    slow = match_cycle_time(MOVES, "poly7", 1.0, dataclasses.replace(p, tau_max=2.0))
    assert slow.plan.total_time_s > match.plan.total_time_s
