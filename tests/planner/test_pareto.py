import itertools

import numpy as np
import pytest
from axisflow.model import MoveError, default_params
from axisflow.planner import Case, MoveProblem
from axisflow.planner.exact import solve_exact
from axisflow.planner.pareto import check_omegas, sweep, time_optimal_point


@pytest.fixture(scope="module")
def points():
    return np.random.default_rng(3).uniform(0.0, 0.8, 12)


@pytest.mark.parametrize("accounting", ["signed", "positive", "absolute"])
def test_the_curve_trades_time_for_energy(points, accounting):
    params = default_params().replace(energy_accounting=accounting)
    curve = sweep(points, "poly5", params, omegas=[0.0, 0.5, 0.8, 0.9, 0.95, 1.0])
    times = [p.total_time_s for p in curve.points]
    energies = [p.total_energy_j for p in curve.points]
    # more weight on time: never slower, never cheaper (each move is solved to its global optimum)
    assert all(a >= b * (1 - 1e-12) for a, b in itertools.pairwise(times))
    assert all(a <= b * (1 + 1e-12) for a, b in itertools.pairwise(energies))
    assert times[0] == pytest.approx(20.0 * (len(points) - 1))  # ω = 0: the slowest allowed moves
    fastest = sum(
        solve_exact(MoveProblem(a, b, "poly5", Case.MIN_TIME, t_min_s=0.3, t_max_s=20.0), params).duration_s
        for a, b in itertools.pairwise(points)
    )
    assert times[-1] == pytest.approx(fastest, rel=1e-12)


def test_the_limit_is_faster_than_every_law(points):
    params = default_params()
    bang = time_optimal_point(points, params)
    for law in ("poly3", "poly5", "poly7"):
        fastest = sweep(points, law, params, omegas=[1.0]).points[0]
        assert bang.total_time_s < fastest.total_time_s


@pytest.mark.parametrize(
    ("omegas", "match"),
    [
        ([], "the ω sweep is empty"),
        ([0.5, 1.2], r"omega = 1.2 is outside \[0, 1\]"),
        ([float("nan")], "omega = nan"),
    ],
)
def test_bad_sweeps(omegas, match):
    with pytest.raises(MoveError, match=match):
        check_omegas(omegas)
