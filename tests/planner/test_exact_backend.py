"""The exact back-end against independent references: a dense continuous-time search, a brute-force
minimisation with the precise energy integral, and a converged CasADi + IPOPT."""

import math

import numpy as np
import pytest
from axisflow.model import (
    EnergyAccounting,
    Move,
    MoveError,
    ParameterError,
    default_params,
    forward_friction,
    move_energy,
    polynomial_law,
)
from axisflow.planner import (
    Case,
    InfeasibleMoveError,
    MinTimeCertificate,
    MoveProblem,
    SolveStatus,
    TimeEnergyCertificate,
    make_backend,
)
from axisflow.planner.evaluation import objective
from axisflow.planner.exact import Active, ExactBackend, solve_exact

LAWS = ["poly3", "poly5", "poly7"]
U = np.linspace(0.0, 1.0, 20001)


@pytest.fixture(scope="module")
def params():
    return default_params()


def _moves(seed, n):
    rng = np.random.default_rng(seed)
    pts = rng.uniform(0.0, 0.8, (n, 2))
    pts[0] = (0.0, 0.8)  # full stroke
    pts[1] = (0.8, 0.0)  # full stroke, backwards
    pts[2] = (0.40, 0.4003)  # very short
    return [tuple(float(x) for x in p) for p in pts]


def dense_ok(x0, x1, law, T, params):
    """Continuous-time limit check on a dense grid (friction sign closed at the ends, as eq. 1 inside)."""
    d = abs(x1 - x0)
    v = d / T * law.shape(U, 1)
    force = params.M_eq * d / T**2 * law.shape(U, 2) + forward_friction(v, params)
    return np.abs(force).max() <= params.f_max * (1 + 1e-9) and v.max() <= params.v_max * (1 + 1e-12)


def refined_peak_force(D, law, T, params):
    """max over u of the cart force of a move of length D in T: a dense grid, then a bounded
    scalar search around the grid's best point (to ~1e-15 in u)."""
    from scipy.optimize import minimize_scalar

    def force(u):
        v = D / T * law.shape(u, 1)
        return params.M_eq * D / T**2 * law.shape(u, 2) + forward_friction(v, params)

    k = int(np.argmax(force(U)))
    lo, hi = U[max(k - 1, 0)], U[min(k + 1, U.size - 1)]
    res = minimize_scalar(
        lambda u: -float(force(u)), bounds=(lo, hi), method="bounded", options={"xatol": 1e-15}
    )
    return max(float(force(U[k])), -res.fun)


def dense_smallest(x0, x1, law, params, lo, hi):
    """Bisection on the dense check (feasibility is monotone in T)."""
    if dense_ok(x0, x1, law, lo, params):
        return lo
    a, b = lo, hi
    while b - a > 1e-11 * b:
        m = 0.5 * (a + b)
        a, b = (a, m) if dense_ok(x0, x1, law, m, params) else (m, b)
    return b


@pytest.mark.parametrize("law", LAWS)
def test_min_time_is_the_smallest_duration_meeting_the_limits_in_continuous_time(law, params):
    poly = polynomial_law(law)
    for x0, x1 in _moves(3, 12):
        sol = solve_exact(MoveProblem(x0, x1, law, Case.MIN_TIME), params)
        ref = dense_smallest(x0, x1, poly, params, 0.1, 3.0)
        # the dense grid may miss the exact peak by ~1e-9 relative; the solver uses the analytic extremum
        assert sol.duration_s == pytest.approx(ref, rel=1e-7), (x0, x1)
        assert dense_ok(x0, x1, poly, sol.duration_s, params)
        cert = sol.certificate
        assert isinstance(cert, MinTimeCertificate)
        assert cert.t_upper_s == sol.duration_s
        if sol.active is not Active.T_MIN:
            assert 0 < cert.gap_s <= 1e-9 * sol.duration_s
            assert not dense_ok(x0, x1, poly, cert.t_lower_s * (1 - 1e-8), params)


@pytest.mark.parametrize("accounting", list(EnergyAccounting))
@pytest.mark.parametrize("law", LAWS)
@pytest.mark.slow
def test_min_time_energy_is_the_global_minimiser(law, accounting):
    p = default_params().replace(energy_accounting=accounting)
    poly = polynomial_law(law)
    for x0, x1 in _moves(5, 5):
        problem = MoveProblem(x0, x1, law, Case.MIN_TIME_ENERGY, omega=0.9)
        sol = solve_exact(problem, p)
        t_feas = dense_smallest(x0, x1, poly, p, 0.3, 20.0)

        def f(T, x0=x0, x1=x1, problem=problem):
            return objective(problem, T, move_energy(Move(x0, x1, T, poly), p))

        grid = np.geomspace(t_feas, 20.0, 200)
        best = min(f(T) for T in grid)
        assert sol.objective == pytest.approx(f(sol.duration_s), rel=1e-9)
        assert sol.objective <= best * (1 + 1e-9), (x0, x1)
        assert isinstance(sol.certificate, TimeEnergyCertificate)
        assert sol.certificate.gap_j <= 1e-8 * abs(sol.objective)
        assert sol.duration_s >= t_feas * (1 - 1e-7)


def test_a_short_move_with_braking_energy_has_an_interior_optimum_and_a_tight_gap():
    p = default_params().replace(energy_accounting="absolute")
    sol = solve_exact(MoveProblem(0.30, 0.33, "poly3", Case.MIN_TIME_ENERGY), p)
    assert sol.certificate.has_bracket  # the regula-falsi branch ran
    a, b = sol.certificate.t_lower_s, sol.certificate.t_upper_s
    assert a <= sol.duration_s <= b and b - a <= 1e-9 * b
    assert sol.certificate.gap_j <= 1e-9 * sol.objective


@pytest.mark.parametrize("accounting", ["positive", "absolute"])
@pytest.mark.parametrize("law", LAWS)
def test_the_start_table_changes_the_path_not_the_answer(law, accounting):
    """Short moves with braking energy: the table-started root search and the plain secant from T_s
    reach the same optimum, and every certificate is a proved bracket of the root of dJ/dT."""
    from axisflow.planner.exact import law_model
    from axisflow.planner.exact.objective import ObjectiveSlope, slope_root
    from axisflow.planner.exact.start_table import START_TABLES

    p = default_params().replace(energy_accounting=accounting)
    c = 1.0 if accounting == "positive" else 2.0
    lm = law_model(polynomial_law(law), p)
    make_backend("exact").prepare(MoveProblem(0.3, 0.33, law, Case.MIN_TIME_ENERGY), p)
    omega = MoveProblem(0.3, 0.33, law, Case.MIN_TIME_ENERGY).omega
    assert START_TABLES.get(polynomial_law(law), p, omega, c)  # solves below start from the table
    interior = 0
    for D in np.geomspace(0.02, 0.07, 60):
        problem = MoveProblem(0.3, 0.3 + float(D), law, Case.MIN_TIME_ENERGY)
        sol = solve_exact(problem, p)
        if not sol.certificate.has_bracket:
            continue
        interior += 1
        a, b = sol.certificate.t_lower_s, sol.certificate.t_upper_s
        assert a <= sol.duration_s <= b and b - a <= 1e-10 * b
        slope = ObjectiveSlope(lm, float(D), problem.omega, c)
        # (a fresh evaluation starts its Newton iterations elsewhere: equal to rounding, ~1e-15)
        assert slope(a)[0] <= 1e-12 and slope(b)[0] >= -1e-12
        assert sol.certificate.gap_j <= 1e-9 * sol.objective
        # unguided: from the smallest feasible duration at or above the signed optimum
        t_s = max(float(D) / _beta(problem, p), problem.t_min_s, _t_feas(problem, p))
        g_s = slope(t_s)[0]
        if g_s < 0.0:
            a2, b2, _, _ = slope_root(
                ObjectiveSlope(lm, float(D), problem.omega, c), t_s, g_s, problem.t_max_s
            )
            assert max(a, a2) <= min(b, b2) * (1 + 1e-10)  # the two proved brackets overlap
    assert interior >= 5


def _beta(problem, p):
    from axisflow.planner.exact import optimal_speed_ratio

    return optimal_speed_ratio(problem.law, p, problem.omega)


def _t_feas(problem, p):
    from axisflow.planner.exact import min_feasible_duration

    return min_feasible_duration(problem, p).duration_s


@pytest.mark.parametrize("accounting", list(EnergyAccounting))
def test_exact_never_violates_a_limit_at_1khz(accounting):
    p = default_params().replace(energy_accounting=accounting)
    backend = make_backend("exact")
    for i, (x0, x1) in enumerate(_moves(9, 30)):
        for case in Case:
            r = backend.solve(MoveProblem(x0, x1, LAWS[i % 3], case), p)
            assert r.status is SolveStatus.CONVERGED
            assert r.max_violation == 0.0
            assert r.solver == "exact" and r.certificate is not None


@pytest.mark.slow
def test_agreement_with_a_converged_ipopt_on_a_few_hundred_moves():
    """The agreement study of the benchmark, on 216 moves: all laws, both cases, all accountings."""
    from axisflow.benchmarks.planner import REFERENCE_IPOPT, random_moves

    exact = make_backend("exact")
    ref = make_backend("ipopt", **REFERENCE_IPOPT)
    base = default_params()
    converged = matched = kinked = 0
    for i, (x0, x1) in enumerate(random_moves(216, 7, base.L)):
        law = LAWS[i % 3]
        case = Case.MIN_TIME if (i // 3) % 2 == 0 else Case.MIN_TIME_ENERGY
        p = base.replace(energy_accounting=list(EnergyAccounting)[(i // 6) % 3])
        problem = MoveProblem(x0, x1, law, case)
        e = exact.solve(problem, p)
        r = ref.solve(problem, p)
        assert e.max_violation == 0.0
        if not r.success:
            continue
        converged += 1
        rel = abs(e.duration_s - r.duration_s) / r.duration_s
        matched += rel <= 1e-6
        if case is Case.MIN_TIME_ENERGY:
            assert e.objective <= r.objective * (1 + 1e-9), (x0, x1, law, p.energy_accounting)
            if rel > 1e-6:
                # only where braking energy is counted: IPOPT's Simpson sum of max(P, 0) or |P| has a
                # kink, which moves its optimum of a flat objective; the exact one is strictly lower
                assert p.energy_accounting is not EnergyAccounting.SIGNED and rel < 1e-3
                assert e.objective < r.objective
                kinked += 1
        else:
            # IPOPT checks the torque at 2001 nodes only; where it is shorter it is over the limit
            assert rel <= 1e-6
            if r.duration_s < e.duration_s:
                assert not dense_ok(x0, x1, polynomial_law(law), r.duration_s, p)
    assert converged >= 200
    assert matched + kinked == converged and kinked <= 10


def test_zero_length_move_and_infeasible_bounds(params):
    sol = solve_exact(MoveProblem(0.4, 0.4, "poly5", Case.MIN_TIME), params)
    assert sol.duration_s == 0.0 and sol.active is Active.ZERO_LENGTH and sol.certificate is None
    with pytest.raises(
        InfeasibleMoveError, match=r"no duration in \[0.1, 0.2\] s keeps the poly5 move 0 m → 0.8 m"
    ):
        solve_exact(MoveProblem(0.0, 0.8, "poly5", Case.MIN_TIME, t_max_s=0.2), params)
    with pytest.raises(MoveError, match=r"x1_m = 0.9 m is outside the stroke"):
        make_backend("exact").solve(MoveProblem(0.1, 0.9, "poly5"), params)
    with pytest.raises(MoveError, match="the exact solver takes no options"):
        make_backend("exact", max_iter=3)


def test_an_axis_whose_torque_limit_cannot_beat_coulomb_friction_is_refused(params):
    """F_max ≤ a1 leaves no move to plan: the parameters themselves are refused."""
    with pytest.raises(
        ParameterError, match=r"F_max = tau_max·i_r/r = 62.5 N, not above the Coulomb friction"
    ):
        params.replace(tau_max=0.25)


def test_an_axis_just_above_coulomb_friction_plans_or_says_infeasible(params):
    """F_max = 75 N > a1 = 72 N: the axis creeps (friction-limited); a long move does not fit 3 s."""
    weak = params.replace(tau_max=0.3)
    with pytest.raises(InfeasibleMoveError, match=r"no duration in \[0.1, 3.0\] s"):
        make_backend("exact").solve(MoveProblem(0.1, 0.5, "poly5"), weak)


def test_duration_bounds_beyond_the_longest_move_are_refused():
    with pytest.raises(MoveError, match=r"t_max_s = 1e\+300 s exceeds the longest move, 3600 s"):
        MoveProblem(0.1, 0.5, "poly5", t_max_s=1e300)


def test_omega_limits(params):
    fast = solve_exact(MoveProblem(0.1, 0.6, "poly5", Case.MIN_TIME_ENERGY, omega=1.0), params)
    t1 = solve_exact(MoveProblem(0.1, 0.6, "poly5", Case.MIN_TIME, t_min_s=0.3, t_max_s=20.0), params)
    assert fast.duration_s == pytest.approx(t1.duration_s, rel=1e-12)
    slow = solve_exact(MoveProblem(0.1, 0.6, "poly5", Case.MIN_TIME_ENERGY, omega=0.0), params)
    assert slow.duration_s == 20.0
    assert math.isfinite(slow.energy_j)


@pytest.mark.parametrize("accounting", list(EnergyAccounting))
def test_the_law_model_energy_is_the_model_energy(accounting):
    """ExactBackend scores its results with the law model's energy: the same number as move_energy."""
    from axisflow.planner.exact import law_energy, law_model

    p = default_params().replace(energy_accounting=accounting)
    rng = np.random.default_rng(11)
    for law in LAWS:
        lm = law_model(polynomial_law(law), p)
        for _ in range(60):
            D = float(10 ** rng.uniform(-6, math.log10(0.8)))
            T = float(10 ** rng.uniform(-1.3, 1.3))
            ref = move_energy(Move(0.0, D, T, polynomial_law(law)), p)
            assert law_energy(lm, D, T, accounting) == pytest.approx(ref, rel=1e-9), (law, D, T)


@pytest.mark.parametrize(
    ("accounting", "x0", "x1", "T", "peak"),
    [
        ("positive", 0.29780470663007236, 0.7126240786160225, 0.897652537438027, 0.22428104457734527),
        ("absolute", 0.1565222639562568, 0.5913974992269536, 0.9234075409596703, 0.22317234798535307),
    ],
)
def test_a_braking_evaluation_started_at_the_margins_peak_keeps_that_peak(accounting, x0, x1, T, peak):
    """poly7's braking margin h has two maxima on [0, 1/2] here, the second one below zero. Started
    from a hint one Newton step from the first (as a root search's previous evaluation leaves it), the
    peak search landed exactly on it (h' = 0) and then bisected away to the second: no braking energy
    (a solve with it was 4e-4 off in energy and not the optimum). Now it keeps the peak it reached."""
    from axisflow.planner.exact import law_model
    from axisflow.planner.exact.energy import braking_energy_and_slope

    p = default_params().replace(energy_accounting=accounting)
    lm = law_model(polynomial_law("poly7"), p)
    D = x1 - x0
    hinted = braking_energy_and_slope(lm, D, T, [0.2, peak, 0.24])
    assert hinted == pytest.approx(braking_energy_and_slope(lm, D, T), rel=1e-12)
    c = 1.0 if accounting == "positive" else 2.0
    signed = move_energy(Move(x0, x1, T, polynomial_law("poly7")), p.replace(energy_accounting="signed"))
    ref = move_energy(Move(x0, x1, T, polynomial_law("poly7")), p)
    assert hinted[0] > 0.0 and signed + c * hinted[0] == pytest.approx(ref, rel=1e-9)


def test_without_viscous_friction_a_heavy_time_weight_means_the_fastest_feasible_move(params):
    """a2 = 0 bounds ψ(β) by a3/a4: for ω/(1 − ω) above it, J (signed energy) rises with T
    everywhere (β* = ∞)."""
    p = params.replace(a2=0.0, energy_accounting="signed")
    sol = solve_exact(MoveProblem(0.2, 0.6, "poly5", Case.MIN_TIME_ENERGY, omega=0.95), p)
    fastest = solve_exact(MoveProblem(0.2, 0.6, "poly5", Case.MIN_TIME, t_min_s=0.3, t_max_s=20.0), p)
    assert sol.duration_s == pytest.approx(fastest.duration_s, rel=1e-12)
    assert sol.certificate.dJ_dT > 0.0 and sol.certificate.gap_j == 0.0
    no_friction_but_coulomb = params.replace(a2=0.0, a3=0.0)
    for omega in (0.1, 0.5, 0.9):
        sol = solve_exact(
            MoveProblem(0.2, 0.6, "poly7", Case.MIN_TIME_ENERGY, omega=omega), no_friction_but_coulomb
        )
        assert math.isfinite(sol.objective)


def test_certificates_prove_what_they_claim(params):
    poly = polynomial_law("poly5")
    # minimum time decided by the lower bound: nothing shorter is allowed, the gap is zero
    short = solve_exact(MoveProblem(0.2, 0.201, "poly5", Case.MIN_TIME), params)
    assert short.active is Active.T_MIN
    assert short.certificate == MinTimeCertificate(t_lower_s=0.1, t_upper_s=0.1)
    assert short.certificate.to_dict() == {"t_lower_s": 0.1, "t_upper_s": 0.1, "gap_s": 0.0}
    # time-energy decided by the torque limit: a proved-infeasible duration just below (the peak force
    # found independently: a dense grid, then a bounded search around its best point)
    tight = solve_exact(MoveProblem(0.0, 0.8, "poly5", Case.MIN_TIME_ENERGY, omega=0.999), params)
    assert tight.active is Active.TORQUE
    below = tight.certificate.t_infeasible_s
    assert below < tight.duration_s
    assert refined_peak_force(0.8, poly, below, params) > params.f_max
    assert refined_peak_force(0.8, poly, tight.duration_s, params) <= params.f_max * (1 + 1e-12)
    # minimum time decided by the velocity limit: the peak velocity c_v·D/t, as computed, breaks v_max
    # at t_lower_s and meets it at the answer
    for law in LAWS:
        fast = params.replace(v_max=0.3)
        sol = solve_exact(MoveProblem(0.0, 0.8, law, Case.MIN_TIME, t_max_s=20.0), fast)
        assert sol.active is Active.VELOCITY
        c_v = polynomial_law(law).peak_velocity_factor
        assert c_v * 0.8 / sol.certificate.t_lower_s > fast.v_max >= c_v * 0.8 / sol.duration_s
    # an interior optimum (signed energy): a bracket of the root of dJ/dT and a tiny gap
    p = params.replace(energy_accounting="signed")
    inner = solve_exact(MoveProblem(0.2, 0.6, "poly5", Case.MIN_TIME_ENERGY), p)
    c = inner.certificate
    assert inner.active is Active.OPTIMUM
    assert c.t_lower_s < inner.duration_s < c.t_upper_s <= c.t_lower_s * (1 + 1e-8)
    assert 0.0 <= c.gap_j <= 1e-12 * inner.objective


@pytest.mark.parametrize(
    "problem",
    [
        MoveProblem(0.1, 0.5, "poly5", Case.MIN_TIME),  # the torque limit's Newton solve
        MoveProblem(0.05, 0.1, "poly3", Case.MIN_TIME_ENERGY),  # the secant search of the braking optimum
    ],
    ids=["min-time", "min-time-energy"],
)
def test_a_solve_past_its_deadline_is_a_status_with_the_slowest_duration(params, problem):
    """The deadline is checked inside the solver's loops (a closed-form answer has none to check);
    past it the result says so, with T_max as its duration (never a hang)."""
    result = ExactBackend(deadline_s=1e-12).solve(problem, params)
    assert result.status is SolveStatus.DEADLINE and not result.success
    assert result.duration_s == problem.t_max_s and result.max_violation == 0.0
    assert "ran past its deadline of 1e-12 s" in result.message


def test_a_zero_move_has_nothing_to_execute(params):
    result = make_backend("exact").solve(MoveProblem(0.3, 0.3 + 1e-6, "poly5"), params)
    assert result.zero_move and result.duration_s == 0.0 and result.energy_j == 0.0
    with pytest.raises(MoveError, match=r"is a zero move \(shorter than one encoder count\)"):
        _ = result.move
    one_count = 2 * math.pi * params.r / 131072
    assert not make_backend("exact").solve(MoveProblem(0.3, 0.3 + one_count, "poly5"), params).zero_move
