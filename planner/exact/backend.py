"""The exact solver's entry point, :func:`solve_exact`, and its back-end adapter :class:`ExactBackend`."""

from __future__ import annotations

import math
import time

from ...model import AxisParams
from ...model.deadline import Deadline, DeadlineError, SolveLimitError
from ..evaluation import finish, is_zero_move, zero_move_result
from ..problem import Case, MoveProblem
from ..result import PlanResult, SolveStatus
from .energy import braking_weight, law_energy, optimal_speed_ratio
from .law_model import law_model
from .min_time import solve_min_time
from .solution import Active, ExactSolution
from .start_table import START_TABLES
from .time_energy import solve_time_energy
from .torque_limit import torque_limit

DEFAULT_DEADLINE_S = 1.0
"""the exact solve's wall-clock deadline [s]: a solve takes 10–100 µs, so reaching it means a loop went
wrong, never a slow machine (every loop is capped in steps as well)"""


def solve_exact(problem: MoveProblem, params: AxisParams, deadline: Deadline | None = None) -> ExactSolution:
    """Solve one move exactly: the duration, what decides it and its certificate (no 1 kHz scoring);
    the hot path of :class:`ExactBackend`. Reads the start tables that set-up prepared, never builds
    one (the law's own tables are built on first use, ~10 ms, unless prepared).

    A move shorter than one encoder count is a zero move (duration 0, :data:`Active.ZERO_LENGTH`).
    Raises :class:`~axisflow.model.deadline.SolveLimitError` when a loop reaches its cap or the
    ``deadline`` passes.
    """
    problem.check_stroke(params)
    if is_zero_move(problem, params):
        return ExactSolution(0.0, 0.0, 0.0, Active.ZERO_LENGTH, None)
    D = abs(problem.x1_m - problem.x0_m)
    limit = torque_limit(problem.law, params)
    if problem.case is Case.MIN_TIME:
        return solve_min_time(problem, params, limit, deadline)
    return solve_time_energy(problem, params, limit, D, deadline)


class ExactBackend:
    """Exact back-end (structure + Newton + a certificate); ~10–100 µs per solve in CPython.

    ``deadline_s`` bounds one solve's wall time; at it (or at a loop's step cap) the result has the
    status :attr:`SolveStatus.DEADLINE` (:attr:`SolveStatus.ITERATION_CAP`), the duration T_max.
    """

    name = "exact"

    def __init__(self, deadline_s: float = DEFAULT_DEADLINE_S) -> None:
        if not deadline_s > 0.0:
            raise ValueError(f"deadline_s = {deadline_s} s must be > 0 s")
        self.deadline_s = deadline_s

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
        try:
            sol = solve_exact(problem, params, Deadline(self.deadline_s, "the exact solve"))
        except SolveLimitError as exc:
            status = SolveStatus.DEADLINE if isinstance(exc, DeadlineError) else SolveStatus.ITERATION_CAP
            elapsed = time.perf_counter() - t0
            return finish(
                problem,
                params,
                solver=self.name,
                status=status,
                duration_s=problem.t_max_s,
                iterations=0,
                solve_time_s=elapsed,
                message=f"exact: {exc}; returned T_max",
            )
        elapsed = time.perf_counter() - t0
        if sol.active is Active.ZERO_LENGTH:
            return zero_move_result(problem, params, self.name)
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
