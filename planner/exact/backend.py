"""The exact solver's entry point, :func:`solve_exact`, and its back-end adapter :class:`ExactBackend`."""

from __future__ import annotations

import math
import time

from ...model import AxisParams
from ..evaluation import finish, objective
from ..problem import Case, MoveProblem
from ..result import PlanResult, SolveStatus
from .energy import braking_weight, law_energy, optimal_speed_ratio
from .law_model import law_model
from .min_time import solve_min_time
from .solution import Active, ExactSolution
from .start_table import START_TABLES
from .time_energy import solve_time_energy
from .torque_limit import torque_limit


def solve_exact(problem: MoveProblem, params: AxisParams) -> ExactSolution:
    """Solve one move exactly: the duration, what decides it and its certificate (no 1 kHz scoring);
    the hot path of :class:`ExactBackend`. Reads the start tables that set-up prepared, never builds
    one (the law's own tables are built on first use, ~10 ms, unless prepared)."""
    problem.check_stroke(params)
    D = abs(problem.x1_m - problem.x0_m)
    if D == 0.0:
        t = problem.t_min_s
        return ExactSolution(t, objective(problem, t, 0.0), 0.0, Active.ZERO_LENGTH, None)
    limit = torque_limit(problem.law, params)
    if problem.case is Case.MIN_TIME:
        return solve_min_time(problem, params, limit)
    return solve_time_energy(problem, params, limit, D)


class ExactBackend:
    """Exact back-end (structure + Newton + a certificate); ~10–100 µs per solve in CPython."""

    name = "exact"

    def prepare(self, problem: MoveProblem, params: AxisParams) -> None:
        """Build the law's tables and, for case 2, the optimal speed ratio for ω and the braking
        optimum's start table (all cached), so that no solve pays for them."""
        torque_limit(problem.law, params)
        if problem.case is Case.MIN_TIME_ENERGY:
            optimal_speed_ratio(problem.law, params, problem.omega)
            c = braking_weight(params.energy_accounting)
            if c > 0.0:
                START_TABLES.prepare(problem.law, params, problem.omega, c)

    def solve(self, problem: MoveProblem, params: AxisParams) -> PlanResult:
        t0 = time.perf_counter()
        sol = solve_exact(problem, params)
        elapsed = time.perf_counter() - t0
        energy = sol.energy_j
        if math.isnan(energy):  # minimum time: the energy of the answer, from the same law model
            D = abs(problem.distance_m)
            energy = law_energy(law_model(problem.law, params), D, sol.duration_s, params.energy_accounting)
        return finish(
            problem,
            params,
            solver=self.name,
            status=SolveStatus.CONVERGED,
            duration_s=sol.duration_s,
            iterations=0,
            solve_time_s=elapsed,
            message=f"exact; active: {sol.active}",
            certificate=sol.certificate,
            energy_j=energy,
        )
