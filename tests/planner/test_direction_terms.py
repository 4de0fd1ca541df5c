"""Moves on axes whose friction differs by direction or carries a constant force: each direction is
planned with its own forward law, both back-ends meet the limits at the 1 kHz samples, and a load
that helps a move makes the braking half decide its minimum time."""

import pytest
from axisflow.model import EnergyAccounting, Move, check_limits, default_params, polynomial_law
from axisflow.model.params import forward_axis
from axisflow.planner import MoveProblem
from axisflow.planner.exact import ExactBackend
from axisflow.planner.exact.torque_limit import torque_limit
from axisflow.planner.ipopt_backend import IpoptBackend

UPHILL = default_params().replace(f0=250.0, da1=-15.0, da2=40.0)
"""+x rises: the motor lifts towards +x and is helped back (c = 72 - 15 - 250 < 0 towards -x)"""
MOVES = [(0.1, 0.7), (0.7, 0.1), (0.4, 0.45), (0.45, 0.4)]


@pytest.mark.parametrize("accounting", list(EnergyAccounting))
@pytest.mark.parametrize("case", ["min-time", "min-time-energy"])
@pytest.mark.parametrize("law", ["poly3", "poly5", "poly7"])
def test_both_back_ends_meet_the_limits_both_ways(law, case, accounting):
    params = UPHILL.replace(energy_accounting=accounting)
    exact, ipopt = ExactBackend(), IpoptBackend()
    for x0, x1 in MOVES:
        problem = MoveProblem(x0, x1, law, case)
        a, b = exact.solve(problem, params), ipopt.solve(problem, params)
        assert a.status == "converged" and a.max_violation == 0.0, (x0, x1, a.message)
        assert b.max_violation == 0.0, (x0, x1, b.message)
        if b.status == "converged":
            assert a.objective <= b.objective * (1 + 1e-6), (x0, x1)


def test_the_directions_differ_and_the_exact_plan_is_that_directions_optimum():
    law = polynomial_law("poly5")
    up = ExactBackend().solve(MoveProblem(0.1, 0.7, law, "min-time"), UPHILL)
    down = ExactBackend().solve(MoveProblem(0.7, 0.1, law, "min-time"), UPHILL)
    assert up.duration_s != pytest.approx(down.duration_s, rel=1e-3)
    for result, (x0, x1) in ((up, (0.1, 0.7)), (down, (0.7, 0.1))):
        shorter = Move(x0, x1, result.duration_s * (1 - 1e-6), law)
        assert check_limits(Move(x0, x1, result.duration_s, law), UPHILL).ok
        assert not check_limits(shorter, UPHILL, min_points=20001).ok  # the limit binds: minimal


def test_a_helping_load_makes_the_braking_half_decide_the_minimum_time():
    law = polynomial_law("poly5")
    steep = default_params().replace(f0=600.0)  # 600 N pull towards -x, 72 N of Coulomb friction
    axis = forward_axis(steep, -1.0)
    assert axis.a1 + axis.f0 < 0.0  # c < 0 along this move
    limit = torque_limit(law, axis)
    assert limit.braking is not None
    D = 0.6
    driving_only = limit._duration(D, None)[0]
    both = limit.duration(D)[0]
    assert both > driving_only  # the braking half needs the longer move
    assert check_limits(Move(0.7, 0.1, both, law), steep).torque_violation == 0.0
    assert check_limits(Move(0.7, 0.1, driving_only, law), steep).torque_violation > 0.0
    result = ExactBackend().solve(MoveProblem(0.7, 0.1, law, "min-time"), steep)
    assert result.duration_s >= both and result.max_violation == 0.0


def test_the_time_energy_case_with_a_helping_load_and_no_regeneration_is_searched_not_certified():
    problem = MoveProblem(0.7, 0.1, "poly5", "min-time-energy")
    result = ExactBackend().solve(problem, UPHILL)  # positive accounting, c < 0 this way
    assert "no certificate" in result.message and result.max_violation == 0.0
    signed = ExactBackend().solve(problem, UPHILL.replace(energy_accounting="signed"))
    assert signed.certificate is not None  # signed energy: the exact proofs hold
