"""Independent references for the planner tests: a plain search over durations (no CasADi)."""

from __future__ import annotations

import numpy as np
from axisflow.model import Move, check_limits, move_energy
from scipy.optimize import minimize_scalar


def smallest_feasible_duration(x0, x1, law, params, lo=0.1, hi=3.0, tol=1e-7):
    """Smallest duration whose 1 kHz samples meet the limits: a dense scan, then bisection."""

    def ok(T):
        return check_limits(Move(x0, x1, T, law), params).ok

    grid = np.geomspace(lo, hi, 400)
    feasible = [T for T in grid if ok(T)]
    if not feasible:
        return None
    k = int(np.searchsorted(grid, feasible[0]))
    if k == 0:
        return lo
    a, b = grid[k - 1], grid[k]
    while b - a > tol * b:
        mid = 0.5 * (a + b)
        a, b = (a, mid) if ok(mid) else (mid, b)
    return b


def best_time_energy_duration(x0, x1, law, params, omega, lo, hi):
    """Minimiser of ω·T + (1 − ω)·E(T) over the feasible durations by a grid and a bounded refine."""
    t_feas = smallest_feasible_duration(x0, x1, law, params, lo, hi)

    def f(T):
        return omega * T + (1 - omega) * move_energy(Move(x0, x1, T, law), params)

    grid = np.geomspace(t_feas, hi, 300)
    vals = [f(T) for T in grid]
    k = int(np.argmin(vals))
    a, b = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
    res = minimize_scalar(f, bounds=(a, b), method="bounded", options={"xatol": 1e-9})
    return res.x if res.fun <= vals[k] else grid[k]
