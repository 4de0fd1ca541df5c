"""Case 2, minimum ω·T + (1 − ω)·E(T): the global minimiser over the feasible durations, certified.

J is convex in T for all three accountings (:mod:`.energy`) and feasibility is monotone in T
(:mod:`.torque_limit`), so the answer comes in two stages:

1. **The signed optimum T_s.** With signed energy, dJ/dT = 0 at T = D/β* (:func:`.energy.
   optimal_speed_ratio`); T_s is its projection on [T_min, T_max], raised to the smallest feasible
   duration T_feas when it breaks a limit (checked with one peak evaluation; T_feas is computed only
   then). With signed energy T_s is the answer.
2. **Braking energy** (positive / absolute: J = J_s + (1 − ω)·c·R, R ≥ 0 non-increasing in T). J is
   non-increasing on [T_feas, T_s], so the minimiser is T_s when dJ/dT(T_s) ≥ 0 or R(T_s) = 0 (then
   J = J_s from T_s on), and otherwise the root of dJ/dT right of T_s (:func:`.objective.slope_root`),
   or T_max if J still falls there. When a prepared start table (:mod:`.start_table`) gives a T₀ with
   dJ/dT(T₀) < 0 (directly, after its Newton step, or after one secant probe aimed just left of the
   root), the minimiser lies right of T₀ by convexity and T_s needs no evaluation at all.

Certificates (:class:`~axisflow.planner.certificates.TimeEnergyCertificate`): at an interior optimum a
bracket of the root of dJ/dT and ``gap_j`` from the tangent bound (:mod:`.proofs`). For an optimum
without braking energy the bracket is taken on the signed objective J_s ≤ J (equal at T_s), which
bounds min J as well. At a bound or a limit, gap 0 and dJ/dT of the sign that makes that end the
minimiser; a limit adds ``t_infeasible_s``, a duration proved to break it.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

from ...model import AxisParams, EnergyAccounting
from ...model.deadline import Deadline
from ..certificates import TimeEnergyCertificate
from ..problem import MoveProblem
from .energy import braking_weight, optimal_speed_ratio, signed_energy, signed_energy_slope
from .law_model import LawModel
from .min_time import min_feasible_duration
from .objective import ObjectiveSlope, SlopeRoot, StartGuess, slope_root
from .proofs import bracket_certificate, tangent_lower_bound
from .solution import Active, ExactSolution
from .start_table import START_TABLES
from .torque_limit import TorqueLimit


def solve_time_energy(
    problem: MoveProblem, params: AxisParams, limit: TorqueLimit, D: float, deadline: Deadline | None = None
) -> ExactSolution:
    """Case 2 for a move of length D > 0 (see the module docstring)."""
    beta = optimal_speed_ratio(problem.law, params, problem.omega)
    t_s, active, t_infeasible = _signed_start(problem, params, limit, D, beta, deadline)
    if params.energy_accounting is EnergyAccounting.SIGNED:
        sol = _signed_answer(problem.omega, limit.model, D, t_s, active)
    else:
        sol = _BrakingSearch(problem, params, limit.model, D, beta, deadline).solve(t_s, active)
    if t_infeasible is not None and sol.duration_s == t_s:
        # a limit decides: shorter durations are proved out
        assert isinstance(sol.certificate, TimeEnergyCertificate)  # what both answers above give
        proof = dataclasses.replace(sol.certificate, t_infeasible_s=t_infeasible)
        sol = dataclasses.replace(sol, certificate=proof)
    return sol


def _signed_start(
    problem: MoveProblem,
    params: AxisParams,
    limit: TorqueLimit,
    D: float,
    beta: float,
    deadline: Deadline | None,
) -> tuple[float, Active, float | None]:
    """(T_s, what decides it, a proved-infeasible duration when a limit does): D/β* projected on the
    bounds, or the smallest feasible duration when that breaks a limit."""
    t_free = D / beta if beta > 0.0 else math.inf
    t_c = min(max(t_free, problem.t_min_s), problem.t_max_s)
    active = Active.OPTIMUM if t_c == t_free else (Active.T_MIN if t_c == problem.t_min_s else Active.T_MAX)
    if problem.law.peak_velocity_factor * D <= params.v_max * t_c and limit.within(1.0 / t_c, D):
        return t_c, active, None
    t_s, t_below, active = min_feasible_duration(problem, params, limit, deadline)
    return t_s, active, t_below if active in (Active.VELOCITY, Active.TORQUE) else None


def _signed_objective(lm: LawModel, D: float, omega: float) -> Callable[[float], tuple[float, float]]:
    """x ↦ (J_s, dJ_s/dT) at x: the objective with signed energy."""

    def value_and_slope(x: float) -> tuple[float, float]:
        return (
            omega * x + (1 - omega) * signed_energy(lm, D, x),
            omega + (1 - omega) * signed_energy_slope(lm, D, x),
        )

    return value_and_slope


def _signed_answer(omega: float, lm: LawModel, D: float, t_s: float, active: Active) -> ExactSolution:
    """T_s with signed energy: a bracket at the optimum; at a bound or a limit, dJ/dT there has the
    sign that, by convexity, makes T_s the minimiser."""
    e = signed_energy(lm, D, t_s)
    j = omega * t_s + (1 - omega) * e
    slope = omega + (1.0 - omega) * signed_energy_slope(lm, D, t_s)
    if active is Active.OPTIMUM:
        certificate = bracket_certificate(_signed_objective(lm, D, omega), t_s, j, slope)
    else:
        certificate = TimeEnergyCertificate(gap_j=0.0, dJ_dT=slope)
    return ExactSolution(t_s, j, e, active, certificate)


class _BrakingSearch:
    """The minimiser of J = J_s + (1 − ω)·c·R right of T_s, in small steps (module docstring, 2.)."""

    def __init__(
        self,
        problem: MoveProblem,
        params: AxisParams,
        lm: LawModel,
        D: float,
        beta: float,
        deadline: Deadline | None = None,
    ) -> None:
        self.problem, self.params, self.lm, self.D, self.beta = problem, params, lm, D, beta
        self.deadline = deadline
        self.omega, self.t_max = problem.omega, problem.t_max_s
        self.c = braking_weight(params.energy_accounting)
        self.slope = ObjectiveSlope(lm, D, problem.omega, self.c)

    def solve(self, t_s: float, active: Active) -> ExactSolution:
        guess = self._guess(t_s)
        left = self._left_of_root(t_s, guess) if guess is not None else None
        if left is None:
            g_s, r_s = self.slope(t_s)
            if r_s == 0.0 or t_s >= self.t_max or self.omega >= 1.0 or g_s >= 0.0:
                return self._at_signed_optimum(t_s, active, g_s, r_s)
            left = t_s, g_s
        root = slope_root(self.slope, left[0], left[1], self.t_max, guess, self.deadline)
        if root.unbounded:
            g_max, r_max = self.slope(self.t_max)
            if g_max <= 0.0:
                return self._at_t_max(g_max, r_max)
            a = root.t_lower_s  # pragma: no cover - not reached
            g_a = self.slope(a)[0]  # pragma: no cover
            root = slope_root(self.slope, a, g_a, self.t_max, None, self.deadline)  # pragma: no cover
        return self._interior(root)

    def _guess(self, t_s: float) -> StartGuess | None:
        """The prepared start table's T₀ when it lies in (T_s, T_max) (never built here)."""
        if not (0.0 < self.beta < math.inf and t_s < self.t_max):
            return None
        table = START_TABLES.get(self.problem.law, self.params, self.omega, self.c)
        guess = table.guess(self.D, self.D / self.beta) if table is not None else None
        if guess is None or not (t_s < guess.t0_s < self.t_max and guess.curvature > 0.0):
            return None
        return guess

    def _left_of_root(self, t_s: float, guess: StartGuess) -> tuple[float, float] | None:
        """A duration right of T_s where dJ/dT < 0, and the slope there: T₀, its Newton step, or a
        secant probe aimed just left of the root; None when none of them is."""
        slope = self.slope
        t0, g0 = guess.t0_s, slope(guess.t0_s)[0]
        if g0 < 0.0:
            return t0, g0
        x1 = t0 - g0 / guess.curvature
        if not (g0 > 0.0 and t_s < x1):
            return None
        g1 = slope(x1)[0]
        if g1 < 0.0:
            return x1, g1
        if not (g1 > 0.0 and g1 < g0):
            return None
        # still right of the root: a secant probe aimed just left of it
        nx = x1 - g1 * (x1 - t0) / (g1 - g0)
        x2 = nx - max(1e-11 * nx, 4.0 * abs(nx - x1) * abs(nx - t0) / nx)
        if t_s < x2:
            g2 = slope(x2)[0]
            if g2 < 0.0:
                return x2, g2
        return None

    def _at_signed_optimum(self, t_s: float, active: Active, g_s: float, r_s: float) -> ExactSolution:
        """T_s is the global minimiser (dJ/dT(T_s) ≥ 0, or R = 0 there): its certificate."""
        e, j = self._energy_and_objective(t_s, r_s)
        if active is not Active.OPTIMUM:
            certificate = TimeEnergyCertificate(gap_j=0.0, dJ_dT=g_s)
        elif r_s == 0.0:
            # J = J_s + (1 − ω)·c·R ≥ J_s everywhere and J(T_s) = J_s(T_s): a bound on min J_s
            # bounds min J, so the signed bracket (no braking evaluations) certifies T_s
            certificate = bracket_certificate(_signed_objective(self.lm, self.D, self.omega), t_s, j, g_s)
        else:
            certificate = bracket_certificate(self.slope.value_and_slope, t_s, j, g_s)
        return ExactSolution(t_s, j, e, active, certificate)

    def _at_t_max(self, g_max: float, r_max: float) -> ExactSolution:
        """dJ/dT ≤ 0 up to T_max: the bound is the minimiser."""
        e, j = self._energy_and_objective(self.t_max, r_max)
        return ExactSolution(self.t_max, j, e, Active.T_MAX, TimeEnergyCertificate(gap_j=0.0, dJ_dT=g_max))

    def _interior(self, root: SlopeRoot) -> ExactSolution:
        """The better end of the bracket [a, b] of the root of dJ/dT, and the tangent bound."""
        a, b = root.t_lower_s, root.t_upper_s
        ga, ra = self.slope(a)
        gb, rb = self.slope(b)
        ea, ja = self._energy_and_objective(a, ra)
        eb, jb = self._energy_and_objective(b, rb)
        lb = tangent_lower_bound(a, b, ja, jb, ga, gb)
        t_opt, j_opt, e_opt = (a, ja, ea) if ja <= jb else (b, jb, eb)
        certificate = TimeEnergyCertificate(
            gap_j=max(j_opt - lb, 0.0), dJ_dT=root.slope, t_lower_s=a, t_upper_s=b
        )
        return ExactSolution(t_opt, j_opt, e_opt, Active.OPTIMUM, certificate)

    def _energy_and_objective(self, t: float, r: float) -> tuple[float, float]:
        """(E, J) at t, R(t) = r already evaluated: E = E_s + c·R, J = ω·t + (1 − ω)·E."""
        e = signed_energy(self.lm, self.D, t) + self.c * r
        return e, self.omega * t + (1.0 - self.omega) * e
