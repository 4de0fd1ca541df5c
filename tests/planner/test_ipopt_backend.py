import math

import numpy as np
import pytest
from axisflow.model import EnergyAccounting, MoveError, default_params, polynomial_law
from axisflow.planner import Case, InfeasibleMoveError, MoveProblem, SolveStatus, make_backend
from axisflow.planner.ipopt_backend import IpoptBackend, IpoptSettings

from .reference import best_time_energy_duration, smallest_feasible_duration

LAWS = ["poly3", "poly5", "poly7"]


@pytest.fixture(scope="module")
def params():
    return default_params()


def _moves(seed, n):
    rng = np.random.default_rng(seed)
    pts = rng.uniform(0.0, 0.8, (n, 2))
    pts[0] = (0.0, 0.8)  # a full-stroke move
    pts[1] = (0.40, 0.41)  # a very short one
    return [tuple(p) for p in pts]


@pytest.mark.parametrize("law", LAWS)
def test_min_time_matches_an_independent_search_for_the_smallest_feasible_duration(law, params):
    backend = make_backend("ipopt", max_iter=200)
    for x0, x1 in _moves(11, 6):
        r = backend.solve(MoveProblem(x0, x1, law, Case.MIN_TIME), params)
        ref = smallest_feasible_duration(x0, x1, polynomial_law(law), params)
        assert r.status is SolveStatus.CONVERGED, r.message
        # IPOPT plans 0.1 % inside the limits: never faster than the true minimum, at most ~0.2 % slower
        assert ref * (1 - 1e-6) <= r.duration_s <= ref * 1.002, (x0, x1, r.duration_s, ref)
        assert r.max_violation == 0.0


@pytest.mark.parametrize("law", LAWS)
@pytest.mark.slow
def test_min_time_energy_matches_a_direct_minimisation(law):
    p = default_params().replace(energy_accounting="signed")
    backend = make_backend("ipopt", max_iter=200)
    for x0, x1 in _moves(5, 4):
        problem = MoveProblem(x0, x1, law, Case.MIN_TIME_ENERGY, omega=0.9)
        r = backend.solve(problem, p)
        ref_T = best_time_energy_duration(x0, x1, polynomial_law(law), p, 0.9, 0.3, 20.0)
        ref = MoveProblem(x0, x1, law, Case.MIN_TIME_ENERGY, omega=0.9)
        assert r.status is SolveStatus.CONVERGED, r.message
        # objective within 1e-6 relative of the reference minimum (the duration is flat near the optimum)
        from axisflow.model import Move, move_energy
        from axisflow.planner.evaluation import objective

        ref_obj = objective(ref, ref_T, move_energy(Move(x0, x1, ref_T, problem.law), p))
        assert r.objective <= ref_obj * (1 + 1e-6)
        assert r.duration_s == pytest.approx(ref_T, rel=2e-3)


@pytest.mark.parametrize("case", list(Case))
@pytest.mark.parametrize("accounting", list(EnergyAccounting))
def test_converged_solves_never_violate_the_limits_at_1khz(case, accounting):
    p = default_params().replace(energy_accounting=accounting)
    backend = make_backend("ipopt")  # the paper's cap of 10 iterations
    converged = 0
    for law in LAWS:
        for x0, x1 in _moves(7, 8):
            r = backend.solve(MoveProblem(x0, x1, law, case), p)
            assert r.iterations <= 10
            assert r.solve_time_s > 0
            assert np.isfinite(r.energy_j) and r.energy_j > 0
            if r.status is SolveStatus.CONVERGED:
                converged += 1
                assert r.max_violation == 0.0, (law, x0, x1, r)
    assert converged >= 6


def test_result_object_reports_the_iteration_cap():
    backend = make_backend("ipopt", max_iter=1)
    r = backend.solve(MoveProblem(0.0, 0.8, "poly5", Case.MIN_TIME_ENERGY), default_params())
    assert r.status is SolveStatus.ITERATION_CAP
    assert r.iterations == 1
    assert r.message == "Maximum_Iterations_Exceeded"


def test_omega_one_is_min_time_within_the_case_2_bounds(params):
    backend = make_backend("ipopt", max_iter=200)
    r2 = backend.solve(MoveProblem(0.1, 0.6, "poly5", Case.MIN_TIME_ENERGY, omega=1.0), params)
    r1 = backend.solve(MoveProblem(0.1, 0.6, "poly5", Case.MIN_TIME), params)
    assert r2.duration_s == pytest.approx(r1.duration_s, rel=1e-6)


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"x0_m": -0.1, "x1_m": 0.5}, MoveError, r"x0_m = -0.1 m is outside the stroke \[0, 0.8\] m"),
        ({"x0_m": 0.1, "x1_m": 0.9}, MoveError, r"x1_m = 0.9 m is outside the stroke"),
        ({"x0_m": float("nan"), "x1_m": 0.5}, MoveError, r"x0_m = nan m is not a finite number"),
        ({"x0_m": 0.1, "x1_m": float("inf")}, MoveError, r"x1_m = inf m is not a finite number"),
        ({"x0_m": 0.1, "x1_m": 0.5, "omega": 1.5}, MoveError, r"omega = 1.5 is outside \[0, 1\]"),
        ({"x0_m": 0.1, "x1_m": 0.5, "omega": -0.1}, MoveError, r"omega = -0.1 is outside \[0, 1\]"),
        (
            {"x0_m": 0.1, "x1_m": 0.5, "t_min_s": 2.0, "t_max_s": 1.0},
            MoveError,
            r"duration bounds are empty: t_min_s = 2.0 s > t_max_s = 1.0 s",
        ),
        ({"x0_m": 0.1, "x1_m": 0.5, "t_min_s": 0.0}, MoveError, r"t_min_s = 0.0 s must be > 0 s"),
        (
            {"x0_m": 0.0, "x1_m": 0.8, "t_max_s": 0.2},
            InfeasibleMoveError,
            r"no duration in \[0.1, 0.2\] s keeps the poly5 move 0 m → 0.8 m within the limits: "
            r".*v_max = [0-9.]+ m/s",
        ),
    ],
)
def test_bad_inputs_get_clear_errors(kwargs, error, match, params):
    backend = make_backend("ipopt")
    with pytest.raises(error, match=match):
        problem = MoveProblem(law="poly5", **kwargs)
        backend.solve(problem, params)


def test_unknown_solver_is_named():
    with pytest.raises(MoveError, match="unknown solver 'snopt'"):
        make_backend("snopt")


def test_ipopt_past_its_wall_time_is_a_deadline_status():
    params = default_params()
    problem = MoveProblem(0.1, 0.5, "poly5", Case.MIN_TIME_ENERGY)
    result = IpoptBackend(IpoptSettings(max_wall_time_s=1e-9)).solve(problem, params)
    assert result.status is SolveStatus.DEADLINE and result.message == "Maximum_WallTime_Exceeded"


def test_ipopt_refuses_a_wall_time_that_is_not_a_bound():
    with pytest.raises(MoveError, match=r"max_wall_time_s = inf s must be finite and > 0 s"):
        IpoptSettings(max_wall_time_s=math.inf)
