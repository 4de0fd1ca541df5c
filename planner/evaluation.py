"""Back-end independent evaluation of a planned duration: objective, energy, limits, feasibility.

Every back-end reports its result through :func:`finish`, so durations from different solvers are
scored by the same precise energy integral and the same 1 kHz limit check.
"""

from __future__ import annotations

import numpy as np

from ..model import AxisParams, Move, check_limits, move_energy
from ..model.encoder import axis_resolution_m
from .certificates import Certificate
from .errors import InfeasibleMoveError
from .problem import Case, MoveProblem
from .result import PlanResult, SolveStatus

_SCAN_DURATIONS = 64


def objective(problem: MoveProblem, duration_s: float, energy_j: float) -> float:
    """Value of eq. (2) or (3) at a duration, given the move's energy."""
    if problem.case is Case.MIN_TIME:
        return problem.w0 * duration_s
    return problem.omega * duration_s + (1.0 - problem.omega) * energy_j


def is_zero_move(problem: MoveProblem, params: AxisParams) -> bool:
    """Whether the move is shorter than one encoder count (:mod:`axisflow.model.encoder`)."""
    return abs(problem.distance_m) < axis_resolution_m(params)


def zero_move_result(problem: MoveProblem, params: AxisParams, solver: str) -> PlanResult:
    """The plan of a move shorter than one encoder count: a **zero move**, nothing to execute.

    The drive cannot resolve the distance (nor could it tell whether a move of it ran), so the
    answer is certain and needs no solve: duration 0 s, energy 0 J, objective 0, no violation, status
    converged. A sender sends nothing for it; the next move starts from the way point after it, which
    lies within one count of the axis (far inside the bridge's jump tolerance).
    """
    problem.check_stroke(params)
    return PlanResult(
        problem=problem,
        solver=solver,
        status=SolveStatus.CONVERGED,
        duration_s=0.0,
        objective=0.0,
        energy_j=0.0,
        iterations=0,
        solve_time_s=0.0,
        max_violation=0.0,
        message=(
            f"zero move: |x1 - x0| = {abs(problem.distance_m):.3g} m is shorter than one encoder count "
            f"({axis_resolution_m(params):.4g} m): nothing to execute"
        ),
    )


def require_feasible_bounds(problem: MoveProblem, params: AxisParams) -> None:
    """Raise :class:`InfeasibleMoveError` if no duration in the bounds meets the limits.

    The stroke is checked first; then the upper bound and a geometric scan of the bounds are checked
    at the 1 kHz execution samples.
    """
    problem.check_stroke(params)
    if problem.distance_m == 0.0:
        return
    candidates = np.geomspace(problem.t_min_s, problem.t_max_s, _SCAN_DURATIONS)[::-1]
    first = None
    for t in candidates:
        report = check_limits(Move(problem.x0_m, problem.x1_m, float(t), problem.law), params)
        if report.ok:
            return
        first = first or report
    assert first is not None
    raise InfeasibleMoveError(
        f"no duration in [{problem.t_min_s}, {problem.t_max_s}] s keeps the {problem.law.name} move "
        f"{problem.x0_m:.6g} m → {problem.x1_m:.6g} m within the limits: at t_max_s = {problem.t_max_s} s "
        f"the peak velocity is {first.peak_velocity_m_s:.4g} m/s (v_max = {params.v_max} m/s) and the peak "
        f"motor torque {first.peak_torque_nm:.4g} N·m (tau_max = {params.tau_max} N·m)"
    )


def finish(
    problem: MoveProblem,
    params: AxisParams,
    *,
    solver: str,
    status: SolveStatus,
    duration_s: float,
    iterations: int,
    solve_time_s: float,
    message: str = "",
    certificate: Certificate | None = None,
    energy_j: float | None = None,
) -> PlanResult:
    """Score a duration with the precise energy integral (unless the back-end computed the energy
    itself, ``energy_j``) and the 1 kHz limit check."""
    move = Move(problem.x0_m, problem.x1_m, duration_s, problem.law)
    energy = move_energy(move, params) if energy_j is None else energy_j
    return PlanResult(
        problem=problem,
        solver=solver,
        status=status,
        duration_s=float(duration_s),
        objective=objective(problem, duration_s, energy),
        energy_j=energy,
        iterations=iterations,
        solve_time_s=solve_time_s,
        max_violation=check_limits(move, params).max_violation,
        message=message,
        certificate=certificate,
    )
