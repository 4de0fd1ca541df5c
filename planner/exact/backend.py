"""The exact solver's entry point, :func:`solve_exact`, and its back-end adapter :class:`ExactBackend`."""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from ...model import AxisParams, EnergyAccounting, Move, move_energy
from ...model.deadline import Deadline, DeadlineError, SolveLimitError
from ...model.params import forward_axis
from ..evaluation import finish, is_zero_move, zero_move_result
from ..problem import Case, MoveProblem
from ..result import PlanResult, SolveStatus
from .energy import braking_weight, law_energy, optimal_speed_ratio
from .law_model import law_model
from .min_time import min_feasible_duration, solve_min_time
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
    params = forward_axis(params, problem.x1_m - problem.x0_m)  # the move's forward law φ_s
    limit = torque_limit(problem.law, params)
    if problem.case is Case.MIN_TIME:
        return solve_min_time(problem, params, limit, deadline)
    return solve_time_energy(problem, params, limit, D, deadline)


_SCAN_DURATIONS = 48
"""durations scanned (geometrically over the feasible ones) where the exact proofs do not hold"""


def proofs_hold(problem: MoveProblem, params: AxisParams) -> bool:
    """Whether the exact back-end's proofs cover the move: always for minimum time and for signed
    energy; for the positive and absolute accountings only where the move's forward law is ≥ 0 at
    rest (c ≥ 0). With c < 0 the accelerating half can return power too, and the braking energy R(T)
    is no longer convex: such a move is minimised by a scan and Brent's method instead
    (:meth:`ExactBackend._by_search`)."""
    if problem.case is Case.MIN_TIME or params.energy_accounting is EnergyAccounting.SIGNED:
        return True
    axis = forward_axis(params, problem.x1_m - problem.x0_m)
    return axis.a1 + axis.f0 >= 0.0


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
        optimum's start table (all cached), so that no solve pays for them; for both directions of
        an axis whose friction differs by direction."""
        for direction in (1.0, -1.0) if not params.friction.is_symmetric else (1.0,):
            axis = forward_axis(params, direction)
            torque_limit(problem.law, axis)
            if problem.case is Case.MIN_TIME_ENERGY:
                optimal_speed_ratio(problem.law, axis, problem.omega)
                c = braking_weight(params.energy_accounting)
                if c > 0.0 and axis.a1 + axis.f0 >= 0.0:
                    START_TABLES.prepare(problem.law, axis, problem.omega, c)

    def solve(self, problem: MoveProblem, params: AxisParams) -> PlanResult:
        if not proofs_hold(problem, params):
            if is_zero_move(problem, params):
                return zero_move_result(problem, params, self.name)
            return self._by_search(problem, params)
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
        energy: float | None = sol.energy_j
        axis = forward_axis(params, problem.distance_m)
        if math.isnan(sol.energy_j):  # minimum time: the energy of the answer, from the same law model
            D = abs(problem.distance_m)
            if axis.a1 + axis.f0 >= 0.0 or params.energy_accounting is EnergyAccounting.SIGNED:
                energy = law_energy(law_model(problem.law, axis), D, sol.duration_s, params.energy_accounting)
            else:  # power flows back on both halves: the model's integral (proofs_hold)
                energy = None
        result = finish(
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
        if result.max_violation > 0.0:  # pragma: no cover - the proofs exclude it; a guard, not a path
            return dataclasses.replace(
                result,
                status=SolveStatus.FAILED,
                message=f"exact: the plan breaks a limit at the 1 kHz samples by {result.max_violation:.3g}",
            )
        return result

    def _by_search(self, problem: MoveProblem, params: AxisParams) -> PlanResult:
        """A move the exact proofs do not cover (:func:`proofs_hold`): its objective, the model's own
        energy integral, minimised over the feasible durations (proved, as for any exact solve) by a
        scan of :data:`_SCAN_DURATIONS` durations and Brent's method around the best. No certificate:
        the objective need not be convex there."""
        from scipy.optimize import minimize_scalar

        t0 = time.perf_counter()
        problem.check_stroke(params)
        axis = forward_axis(params, problem.distance_m)
        feasible = min_feasible_duration(problem, axis, torque_limit(problem.law, axis)).duration_s
        lo, hi = max(feasible, problem.t_min_s), problem.t_max_s

        def objective(t: float) -> float:
            move = Move(problem.x0_m, problem.x1_m, t, problem.law)
            return problem.omega * t + (1.0 - problem.omega) * move_energy(move, params)

        ts = np.geomspace(lo, hi, _SCAN_DURATIONS) if hi > lo else np.array([lo])
        values = [objective(float(t)) for t in ts]
        k = int(np.argmin(values))
        best, best_j = float(ts[k]), values[k]
        if ts.size > 1:
            a, b = float(ts[max(k - 1, 0)]), float(ts[min(k + 1, ts.size - 1)])
            found = minimize_scalar(objective, bounds=(a, b), method="bounded", options={"xatol": 1e-9 * b})
            if found.fun < best_j:
                best = float(found.x)
        return finish(
            problem,
            params,
            solver=self.name,
            status=SolveStatus.CONVERGED,
            duration_s=best,
            iterations=0,
            solve_time_s=time.perf_counter() - t0,
            message="exact: a load helps this move (c < 0) and the accounting counts braking: the "
            "model's objective minimised over the proved feasible durations (scan and Brent; no certificate)",
        )
