"""Properties of the planner (hypothesis, derandomized), both back-ends, every law and case: on any
axis inside the documented parameter ranges, any x0, x1 in [0, L] and ω in [0, 1], a solve returns
(within a bounded time: pytest-timeout per test, never an endless loop) a result whose limits hold at
the 1 kHz samples, or refuses the move as infeasible with a message naming the durations; end points
outside the stroke are refused naming the value."""

from __future__ import annotations

import math
import re

import pytest
from axisflow.model import Move, MoveError, check_limits
from axisflow.model.encoder import encoder_resolution_m
from axisflow.planner import Case, InfeasibleMoveError, MoveProblem, SolveStatus, make_backend
from axisflow.planner.exact.backend import ExactBackend
from axisflow.planner.ipopt_backend import IpoptBackend, IpoptSettings
from hypothesis import event, given, settings
from hypothesis import strategies as st

from ..model.axis_strategies import axis_params, sibling_params

LAWS = ("poly3", "poly5", "poly7")


@st.composite
def moves(draw: st.DrawFn):
    """(params, problem): an axis inside the ranges (half of them siblings of the default axis) and a
    move inside its stroke. Four in five moves
    have a log-uniform length in [1e-4·L, L]; the fifth ends within four encoder counts of its start
    (zero moves and the shortest real ones)."""
    params = draw(st.one_of(axis_params(), sibling_params()))
    L = params.L
    count = encoder_resolution_m(params.r)
    D = draw(
        st.one_of(
            *[st.floats(-4.0, 0.0).map(lambda e: L * 10.0**e)] * 4,
            st.floats(0.0, min(4.0 * count, L)),
        )
    )
    x0 = draw(st.floats(0.0, max(L - D, 0.0)))
    x0, x1 = (x0, min(x0 + D, L)) if draw(st.booleans()) else (min(x0 + D, L), x0)
    law = draw(st.sampled_from(LAWS))
    case = draw(st.sampled_from(list(Case)))
    omega = draw(st.one_of(st.sampled_from([0.0, 0.9, 1.0]), st.floats(0.0, 1.0)))
    return params, MoveProblem(x0, x1, law, case, omega=omega)


def _holds(result, problem, params) -> None:
    """A result that meets the limits at the 1 kHz samples, checked here independently of the solver's
    own report, or a zero move."""
    if result.zero_move:
        assert abs(problem.distance_m) < encoder_resolution_m(params.r)
        assert result.energy_j == 0.0 and result.max_violation == 0.0
        return
    assert problem.t_min_s <= result.duration_s <= problem.t_max_s
    move = Move(problem.x0_m, problem.x1_m, result.duration_s, problem.law)
    report = check_limits(move, params)
    assert report.max_violation == result.max_violation
    assert math.isfinite(result.energy_j) and math.isfinite(result.objective)


@pytest.mark.timeout(180)
@settings(max_examples=400, derandomize=True, deadline=None, database=None)
@given(moves())
@pytest.mark.slow
def test_exact_plans_every_move_inside_the_ranges_within_the_limits(case):
    params, problem = case
    try:
        result = ExactBackend().solve(problem, params)
    except InfeasibleMoveError as exc:
        assert f"no duration in [{problem.t_min_s}, {problem.t_max_s}] s" in str(exc)
        event("infeasible")
        return
    event("zero move" if result.zero_move else result.message)
    assert result.status is SolveStatus.CONVERGED, result.message
    _holds(result, problem, params)
    assert result.max_violation == 0.0


@pytest.mark.timeout(180)
@settings(max_examples=120, derandomize=True, deadline=None, database=None)
@given(
    sibling_params(),
    st.floats(0.05, 1.0),
    st.floats(0.0, 1.0),
    st.sampled_from(LAWS),
    st.floats(0.5, 1.0),
)
@pytest.mark.slow
def test_exact_time_energy_optima_on_sibling_axes(params, d_frac, x_frac, law, omega):
    """Case 2 on axes like the default, moves of 5–100 % of the stroke: interior optima, the braking
    search and its start tables (prepared as the online planner does) all within the limits."""
    D = d_frac * params.L
    x0 = x_frac * (params.L - D)
    problem = MoveProblem(x0, x0 + D, law, Case.MIN_TIME_ENERGY, omega=omega)
    backend = ExactBackend()
    try:
        backend.prepare(problem, params)
        result = backend.solve(problem, params)
    except InfeasibleMoveError:
        event("infeasible")
        return
    event(result.message)
    assert result.status is SolveStatus.CONVERGED, result.message
    _holds(result, problem, params)
    assert result.max_violation == 0.0


@pytest.mark.timeout(180)
@settings(max_examples=100, derandomize=True, deadline=None, database=None)
@given(moves())
def test_ipopt_plans_every_move_inside_the_ranges_or_says_why_not(case):
    """IPOPT (the paper's cap of 10 iterations, its wall-time deadline): a converged result meets the
    limits; a capped one reports its true violation; a deadline is a status, never a hang."""
    params, problem = case
    try:
        result = IpoptBackend(IpoptSettings()).solve(problem, params)
    except InfeasibleMoveError as exc:
        assert f"no duration in [{problem.t_min_s}, {problem.t_max_s}] s" in str(exc)
        event("infeasible")
        return
    event("zero move" if result.zero_move else result.status.value)
    assert result.status in set(SolveStatus)
    _holds(result, problem, params)
    if result.status is SolveStatus.CONVERGED:
        assert result.max_violation == 0.0, result.message


@pytest.mark.timeout(120)
@settings(max_examples=80, derandomize=True, deadline=None, database=None)
@given(axis_params(), st.floats(allow_nan=False, allow_infinity=False), st.sampled_from(["exact", "ipopt"]))
def test_an_end_point_outside_the_stroke_is_refused_naming_it(params, x1, solver):
    if 0.0 <= x1 <= params.L:
        x1 = params.L + max(abs(x1), 1e-3)
    with pytest.raises(
        MoveError, match=re.escape(f"x1_m = {x1!r} m is outside the stroke [0, {params.L}] m")
    ):
        make_backend(solver).solve(MoveProblem(0.0, x1, "poly5"), params)
