"""Exact back-end: the paper's one-variable problem solved by its structure, with a certificate.

A move of length D = |x1 − x0| > 0 along a symmetric law s(u) in time T has, in the frame where it
runs forward, velocity v = β·s'(u) with β = D/T, and needs the cart force (eq. 1, the friction sign
closed at the end points, as IPOPT's nodes do)

    F(u, T) = M·D·s''(u)/T² + φ(β·s'(u)),      φ(v) = a1 + a2·v + a3·atan(a4·v),  u ∈ [0, 1].

* Case 1, min T (:mod:`.min_time`): feasibility is monotone in T, so T* = max(T_min, T_v, T_τ) with
  T_v = c_v·D/v_max and T_τ the root of max_u F = F_max by Newton's method (:mod:`.torque_limit`);
  the certificate is a bracket (t_lower_s, t_upper_s] with t_lower_s proved infeasible.
* Case 2, min ω·T + (1 − ω)·E(T) (:mod:`.time_energy`): J is convex in T for every energy
  accounting (:mod:`.energy`); the signed optimum is D/β*(law, ω) projected on the feasible durations,
  and braking energy moves the optimum right of it, to the root of dJ/dT (:mod:`.objective`, started
  from a prepared table, :mod:`.start_table`). The certificate is a bracket of that root and the gap
  to a lower bound from the tangents of J (:mod:`.proofs`), or, at a bound or a limit, the sign of
  dJ/dT there.

Modules, bottom up: :mod:`.law_model` (the law and axis prepared once), :mod:`.torque_limit`,
:mod:`.energy`, :mod:`.min_time`, :mod:`.objective`, :mod:`.start_table`, :mod:`.proofs`,
:mod:`.time_energy`, :mod:`.solution` (what a solve returns) and :mod:`.backend` (:func:`solve_exact`
and :class:`ExactBackend`). docs/planner.md has the derivations.
"""

from .backend import ExactBackend, solve_exact
from .energy import law_energy, optimal_speed_ratio
from .law_model import LawModel, law_model
from .min_time import FeasibleDuration, min_feasible_duration
from .solution import Active, ExactSolution

__all__ = [
    "Active",
    "ExactBackend",
    "ExactSolution",
    "FeasibleDuration",
    "LawModel",
    "law_energy",
    "law_model",
    "min_feasible_duration",
    "optimal_speed_ratio",
    "solve_exact",
]
