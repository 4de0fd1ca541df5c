"""The paper's optimiser: CasADi + IPOPT on the one-variable problem, iteration cap 10 by default.

The NLP in the duration T (bounds T_min ≤ T ≤ T_max):

    case 1:  min w0·T
    case 2:  min ω·T + (1 − ω)·T·Σ_k w_k·g(F_k·ẋ_k)        (Simpson weights w_k over N+1 nodes)
    s.t.     c_v·|d| − v_max·T ≤ 0                          (peak velocity, exact: c_v = max|s'|)
             −τ_lim ≤ (r/i_r)·F_k ≤ τ_lim                   (motor torque at the nodes u_k = k/N,
                                                              and 8 graded towards each end)

in the move's forward frame: ẋ_k = D·s'(u_k)/T ≥ 0, ẍ_k = D·s''(u_k)/T² with D = |d|, and F_k =
M_eq·ẍ_k + φ_s(ẋ_k), φ_s the forward law of the move's direction s = sign(d) (its Coulomb sign just
inside the move; :func:`~axisflow.model.params.forward_axis`): the force along the motion, whose
magnitude and power F·ẋ are the move's own. The limits are tightened by ``limit_margin`` (0.1 % by
default) so that the
node-discretised, bound-relaxed IPOPT solution still meets the true limits at every 1 kHz sample.
The NLP is built once per (law, case, accounting, settings) with the move and the axis as CasADi
parameters, so a solve costs one IPOPT call.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from functools import lru_cache

import casadi as ca
import numpy as np

from ..model import AxisParams, EnergyAccounting, MoveError, PolynomialLaw, friction_expression
from ..model.params import forward_axis
from .evaluation import finish, is_zero_move, require_feasible_bounds, zero_move_result
from .problem import Case, MoveProblem
from .result import PlanResult, SolveStatus

_STATUS = {
    "Solve_Succeeded": SolveStatus.CONVERGED,
    "Solved_To_Acceptable_Level": SolveStatus.CONVERGED,
    "Maximum_Iterations_Exceeded": SolveStatus.ITERATION_CAP,
    "Infeasible_Problem_Detected": SolveStatus.INFEASIBLE,
    "Maximum_WallTime_Exceeded": SolveStatus.DEADLINE,
    "Maximum_CpuTime_Exceeded": SolveStatus.DEADLINE,
}


@dataclass(frozen=True)
class IpoptSettings:
    """Settings of the IPOPT back-end."""

    max_iter: int = 10
    """iteration cap (the paper: 10)"""
    tol: float = 1e-6
    """IPOPT's convergence tolerance (on the scaled problem; T is in seconds)"""
    nodes: int = 100
    """number of intervals of the constraint/quadrature grid (even)"""
    limit_margin: float = 1e-3
    """relative tightening of the velocity and torque limits inside the NLP"""
    max_wall_time_s: float = 1.0
    """IPOPT's wall-clock deadline per solve [s] (its ``max_wall_time``; a capped solve takes ~5 ms):
    past it the result has the status :attr:`SolveStatus.DEADLINE` and IPOPT's last iterate"""

    def __post_init__(self) -> None:
        if self.max_iter < 1:
            raise MoveError(f"IPOPT max_iter = {self.max_iter} must be >= 1")
        if not 0.0 < self.max_wall_time_s < math.inf:
            raise MoveError(f"IPOPT max_wall_time_s = {self.max_wall_time_s} s must be finite and > 0 s")
        if self.nodes < 2 or self.nodes % 2:
            raise MoveError(f"IPOPT nodes = {self.nodes} must be an even number >= 2")
        if not 0.0 <= self.limit_margin < 0.5:
            raise MoveError(f"IPOPT limit_margin = {self.limit_margin} must be in [0, 0.5)")


_END_NODES = 8
"""extra torque-constraint nodes graded towards each end of the move, in (1e-4, 1/N): where ẋ → 0 the
low-speed friction a3·atan(a4·ẋ) climbs within a small fraction of the move (with a large a4), and
with poly3's non-zero acceleration at the ends the torque peaks there, between the uniform nodes"""


def _constraint_nodes(n: int) -> np.ndarray:
    """u of the torque constraints: the N + 1 uniform nodes and :data:`_END_NODES` graded towards each
    end."""
    near = np.geomspace(1e-4, 1.0 / n, _END_NODES + 1)[:-1]
    return np.concatenate([np.linspace(0.0, 1.0, n + 1), near, 1.0 - near])


def _simpson_weights(n: int) -> np.ndarray:
    w = np.ones(n + 1)
    w[1:-1:2] = 4.0
    w[2:-1:2] = 2.0
    return w / (3.0 * n)


@lru_cache(maxsize=64)
def _build(
    law: PolynomialLaw, case: Case, accounting: EnergyAccounting, settings: IpoptSettings
) -> ca.Function:
    u = _constraint_nodes(settings.nodes)  # the first N + 1: the uniform grid of the quadrature
    s1 = ca.DM(law.shape(u, 1))
    s2 = ca.DM(law.shape(u, 2))
    T = ca.SX.sym("T")
    # parameters: D, D, 1 (the forward frame), M_eq, the forward axis's a1..a4 (forward_axis),
    # k = 1/force_per_torque, v_lim, tau_lim, omega, w0, f0 along the motion, the Coulomb sign at u = 1
    p = ca.SX.sym("p", 15)
    d, dabs, sgn, M, a1, a2, a3, a4, k_tau, v_lim, _tau_lim, omega, w0, f0, sign_end = ca.vertsplit(p)
    v = d * s1 / T
    a = d * s2 / T**2
    # the Coulomb sign is that of the motion at every node but the last, u = 1, where the move is at
    # rest and the 1 kHz check sees sign 0 (sign_end = 0 where that matters: a load along the motion)
    signs = ca.vertcat(ca.DM.ones(settings.nodes, 1), sign_end, ca.DM.ones(u.size - settings.nodes - 1, 1))
    force = M * a + friction_expression(v, sgn * signs, a1, a2, a3, a4, atan=ca.atan, f0=f0)

    g = ca.vertcat(law.peak_velocity_factor * dabs - v_lim * T, k_tau * force)
    if case is Case.MIN_TIME:
        f = w0 * T
    else:
        grid = settings.nodes + 1
        power = force[:grid] * v[:grid]
        if accounting is EnergyAccounting.POSITIVE:
            power = ca.fmax(power, 0)
        elif accounting is EnergyAccounting.ABSOLUTE:
            power = ca.fabs(power)
        energy = T * ca.dot(ca.DM(_simpson_weights(settings.nodes)), power)
        f = omega * T + (1 - omega) * energy
    opts: dict[str, bool | int | float | str] = {
        "print_time": False,
        "ipopt.print_level": 0,
        "ipopt.sb": "yes",
        "ipopt.max_iter": settings.max_iter,
        "ipopt.tol": settings.tol,
        "ipopt.max_wall_time": settings.max_wall_time_s,
    }
    return ca.nlpsol(
        f"axisflow_{law.name}_{case.name.lower()}", "ipopt", {"x": T, "p": p, "f": f, "g": g}, opts
    )


def _nlp(problem: MoveProblem, params: AxisParams, settings: IpoptSettings) -> ca.Function:
    """The cached NLP of the problem's law and case, the axis's accounting and ``settings``; minimum
    time has no energy term, so its three accountings share one NLP."""
    energy = problem.case is Case.MIN_TIME_ENERGY
    accounting = params.energy_accounting if energy else EnergyAccounting.SIGNED
    return _build(problem.law, problem.case, accounting, settings)


def initial_guess(problem: MoveProblem, params: AxisParams) -> float:
    """Starting duration, clipped into the bounds.

    Case 1: the larger of the velocity-limited and the torque-limited (inertia plus Coulomb and
    saturated low-speed friction) estimates, which lies close to the optimum. Case 2: the geometric
    mean of the bounds when that is longer, since time-energy optima lie at moderate speeds. (Both
    measured on the default axis: ~9 iterations to converge for case 1, ~7 for case 2.)
    """
    dabs = abs(problem.distance_m)
    t_v = problem.law.peak_velocity_factor * dabs / params.v_max
    law = params.forward(problem.distance_m)
    f_free = params.f_max - law.c - law.a3 * math.pi / 2
    t_a = math.sqrt(problem.law.peak_acceleration_factor * dabs * params.M_eq / f_free) if f_free > 0 else 0.0
    guess = max(t_v, t_a, problem.t_min_s)
    if problem.case is Case.MIN_TIME_ENERGY:
        guess = max(guess, math.sqrt(problem.t_min_s * problem.t_max_s))
    return min(guess, problem.t_max_s)


class IpoptBackend:
    """CasADi + IPOPT back-end, as published (iteration cap 10)."""

    name = "ipopt"

    def __init__(self, settings: IpoptSettings | None = None) -> None:
        self.settings = settings or IpoptSettings()

    def prepare(self, problem: MoveProblem, params: AxisParams) -> None:
        """Build (and cache) the NLP for this law/case/accounting so a later solve is timed alone."""
        _nlp(problem, params, self.settings)

    def solve(self, problem: MoveProblem, params: AxisParams) -> PlanResult:
        if is_zero_move(problem, params):
            return zero_move_result(problem, params, self.name)
        require_feasible_bounds(problem, params)
        d = abs(problem.distance_m)
        axis = forward_axis(params, problem.distance_m)
        nlp = _nlp(problem, params, self.settings)
        keep = 1.0 - self.settings.limit_margin
        pvals = [
            d,
            d,
            1.0,
            params.M_eq,
            axis.a1,
            axis.a2,
            axis.a3,
            axis.a4,
            params.transmission.metres_per_radian,
            params.v_max * keep,
            params.tau_max * keep,
            problem.omega,
            problem.w0,
            axis.f0,
            0.0 if axis.f0 else 1.0,
        ]
        constraints = self.settings.nodes + 1 + 2 * _END_NODES
        t0 = time.perf_counter()
        sol = nlp(
            x0=initial_guess(problem, params),
            p=pvals,
            lbx=problem.t_min_s,
            ubx=problem.t_max_s,
            lbg=ca.vertcat(-ca.inf, -ca.DM.ones(constraints) * pvals[10]),
            ubg=ca.vertcat(0.0, ca.DM.ones(constraints) * pvals[10]),
        )
        elapsed = time.perf_counter() - t0
        stats = nlp.stats()
        raw = str(stats.get("return_status", "unknown"))
        status = _STATUS.get(raw, SolveStatus.FAILED)
        return finish(
            problem,
            params,
            solver=self.name,
            status=status,
            # IPOPT relaxes bounds by ~1e-8 (bound_relax_factor): return a duration inside them
            duration_s=min(max(float(sol["x"]), problem.t_min_s), problem.t_max_s),
            iterations=int(stats.get("iter_count", -1)),
            solve_time_s=elapsed,
            message=raw,
        )
