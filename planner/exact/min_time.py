"""Case 1, minimum time: the smallest duration that meets the limits, with a proved bracket.

Feasibility is monotone in T (see :mod:`.torque_limit`), so the answer is

    T* = max(T_min, T_v, T_τ),     T_v = c_v·D/v_max  (c_v = max s', closed form),

or infeasible if T* > T_max. The certificate is a bracket (t_lower_s, t_upper_s]: t_upper_s = T* meets
every limit, t_lower_s breaks one. When the torque limit decides, F > F_max at t_lower_s =
T*·(1 − 1e-11) at the analytic peak; when the velocity limit decides, the bracket is a few
floating-point steps, the peak velocity c_v·D/t checked as computed; when T_min decides, nothing
shorter is allowed: t_lower_s = t_upper_s = T_min and the gap is 0.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from ...model import AxisParams
from ...model.deadline import Deadline, iteration_cap
from ..certificates import MinTimeCertificate
from ..errors import InfeasibleMoveError
from ..problem import MoveProblem
from .solution import Active, ExactSolution
from .torque_limit import TorqueLimit, torque_limit


class FeasibleDuration(NamedTuple):
    """The smallest feasible duration in the bounds, what decides it, and a duration below it
    proved infeasible (0 when the lower bound T_min decides)."""

    duration_s: float
    infeasible_below_s: float
    active: Active


def min_feasible_duration(
    problem: MoveProblem,
    params: AxisParams,
    limit: TorqueLimit | None = None,
    deadline: Deadline | None = None,
) -> FeasibleDuration:
    """max(T_min, T_v, T_τ) with its proof; raises :class:`InfeasibleMoveError` when it is above
    T_max (the message names both durations and both limits)."""
    limit = limit or torque_limit(problem.law, params)
    D = abs(problem.x1_m - problem.x0_m)
    t_v = problem.law.peak_velocity_factor * D / params.v_max
    t_tau, t_tau_low, _ = limit.duration(D, deadline)
    t_min, t_max = problem.t_min_s, problem.t_max_s
    if t_min >= t_v and t_min >= t_tau:
        bound = FeasibleDuration(t_min, 0.0, Active.T_MIN)
    elif t_v >= t_tau:
        bound = _velocity_bracket(problem.law.peak_velocity_factor * D, params.v_max, t_v)
    else:
        bound = FeasibleDuration(t_tau, t_tau_low, Active.TORQUE)
    if bound.duration_s > t_max:
        raise InfeasibleMoveError(
            f"no duration in [{t_min}, {t_max}] s keeps the {problem.law.name} move {problem.x0_m:.6g} m → "
            f"{problem.x1_m:.6g} m within the limits: it needs T >= {bound.duration_s:.6g} s "
            f"(velocity: {t_v:.6g} s at v_max = {params.v_max} m/s; torque: {t_tau:.6g} s at "
            f"tau_max = {params.tau_max} N·m)"
        )
    return bound


_ULP_STEPS = 64
"""the cap of the floating-point steps of the velocity bracket (a correctly rounded c_v·D/v_max needs
one or two)"""


def _velocity_bracket(peak_distance_m: float, v_max: float, t_v: float) -> FeasibleDuration:
    """T_v = c_v·D/v_max moved by floating-point steps until the peak velocity c_v·D/t, as computed,
    meets v_max at the duration and breaks it just below (the proof)."""
    t = t_v
    for _ in range(_ULP_STEPS):
        if peak_distance_m / t <= v_max:
            break
        t = math.nextafter(t, math.inf)
    else:
        raise iteration_cap("the velocity bracket (duration side)", _ULP_STEPS)
    below = math.nextafter(t, 0.0)
    for _ in range(_ULP_STEPS):
        if peak_distance_m / below > v_max:
            return FeasibleDuration(t, below, Active.VELOCITY)
        below = math.nextafter(below, 0.0)
    raise iteration_cap("the velocity bracket (infeasible side)", _ULP_STEPS)


def solve_min_time(
    problem: MoveProblem, params: AxisParams, limit: TorqueLimit, deadline: Deadline | None = None
) -> ExactSolution:
    """Case 1 for a move of non-zero length: T* and its bracket (the energy is left to the caller)."""
    t, below, active = min_feasible_duration(problem, params, limit, deadline)
    if active is Active.T_MIN:  # nothing shorter is allowed: the bound itself is the proof
        below = t
    return ExactSolution(t, problem.w0 * t, math.nan, active, MinTimeCertificate(below, t))
