"""Start tables of the braking optimum: where a case-2 root search with braking energy begins.

Per (law, axis, ω, accounting), the unconstrained optimum T_opt of a move of length D (no bounds, no
limits, the braking energy counted c times) and T·d²J/dT² there, over log D: as T_opt·β*/D (1 where
no braking energy is counted at the optimum, since then T_opt = D/β*) at 16 log-spaced D in
[1e-7·L, 1e-3·L) and 48 in [1e-3·L, L], every base interval with braking at either end split in 8
(the braking optimum turns on over a narrow range of D, ~12 % wide for poly5). Each node is solved
by :func:`.objective.slope_root` from T = D/β*, started from the previous node; d²J/dT² by a central
difference. A solve interpolates the table (quadratic in log D: T_opt to ~1e-5), evaluates dJ/dT
exactly at that T₀ and takes a Newton step with the tabulated curvature (~1e-8): typically 3 exact
evaluations close the bracket instead of 5–9 from T_s.

A table takes 20–60 ms to build. :meth:`StartTables.prepare` (called by ``ExactBackend.prepare``)
builds it; a solve only reads :data:`START_TABLES` and, without a table, starts from T_s, so an online
loop never sees a hidden set-up cost. The table only chooses where to evaluate: the bracket and the
certificate come from exact evaluations.
"""

from __future__ import annotations

import bisect
import itertools
import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ...model import AxisParams, PolynomialLaw
from .energy import optimal_speed_ratio
from .law_model import LawModel, law_model
from .objective import ObjectiveSlope, StartGuess, slope_root

_BASE_NODES = 48
"""base nodes over [1e-3·L, L] (16 more over [1e-7·L, 1e-3·L))"""
_REFINE = 8
"""sub-intervals per base interval where the optimum has braking energy"""


@dataclass(frozen=True)
class StartTable:
    """The braking optimum over log D (see the module docstring)."""

    log_d: tuple[float, ...]
    log_ratio: tuple[float, ...]
    """log(T_opt·β*/D), > 0 where the optimum has braking energy"""
    log_curvature: tuple[float, ...]
    """log(T·d²J/dT²) at T_opt"""
    log_d_braking_end: float
    """log D above which no node has braking energy at its optimum (no guess there)"""

    def guess(self, D: float, t_free: float) -> StartGuess | None:
        """(T₀, d²J/dT²(T₀)) for a move of length D, t_free = D/β*; None outside the table."""
        log_d, log_r = self.log_d, self.log_ratio
        x = math.log(D)
        if not log_d[0] <= x <= self.log_d_braking_end:
            return None
        k = min(bisect.bisect_right(log_d, x) - 1, len(log_d) - 2)
        w = (x - log_d[k]) / (log_d[k + 1] - log_d[k])
        lr = log_r[k] + w * (log_r[k + 1] - log_r[k])
        # quadratic through the nearest three nodes where the optimum has braking (log_r > 0)
        j = k - 1 if w < 0.5 and k > 0 else min(k, len(log_d) - 3)
        if j >= 0 and log_r[j] > 0.0 and log_r[j + 1] > 0.0 and log_r[j + 2] > 0.0:
            x0, x1, x2 = log_d[j], log_d[j + 1], log_d[j + 2]
            lr = (
                log_r[j] * (x - x1) * (x - x2) / ((x0 - x1) * (x0 - x2))
                + log_r[j + 1] * (x - x0) * (x - x2) / ((x1 - x0) * (x1 - x2))
                + log_r[j + 2] * (x - x0) * (x - x1) / ((x2 - x0) * (x2 - x1))
            )
        t0 = t_free * math.exp(lr)
        log_s = self.log_curvature
        return StartGuess(t0, math.exp(log_s[k] + w * (log_s[k + 1] - log_s[k])) / t0)


def _optimum_node(
    lm: LawModel, D: float, beta: float, omega: float, c: float, previous: tuple[float, float] | None
) -> tuple[float, float] | None:
    """(T_opt·β*/D, T·d²J/dT²) of the unconstrained optimum of a move of length D, the search
    started from the previous node's (ratio, T·d²J/dT²); None where d²J/dT² ≤ 0 (no node)."""
    t_s = D / beta
    slope = ObjectiveSlope(lm, D, omega, c)
    g_s, r_s = slope(t_s)
    t_opt = t_s
    if r_s > 0.0 and g_s < 0.0:
        guess = StartGuess(t_s * previous[0], previous[1] / t_s) if previous else None
        root = slope_root(slope, t_s, g_s, math.inf, guess)
        if root.unbounded:  # pragma: no cover - J is bounded below by ω·T
            return None
        t_opt = 0.5 * (root.t_lower_s + root.t_upper_s)
    h = 1e-5 * t_opt
    curvature = (slope(t_opt + h)[0] - slope(t_opt - h)[0]) / (2.0 * h)
    return (t_opt / t_s, t_opt * curvature) if curvature > 0.0 else None


@lru_cache(maxsize=512)
def build_start_table(law: PolynomialLaw, params: AxisParams, omega: float, c: float) -> StartTable | None:
    """The start table of (law, axis, ω, c) (cached), or None when no move has braking energy at
    its optimum (or ω gives no finite, positive β*)."""
    beta = optimal_speed_ratio(law, params, omega)
    if not 0.0 < beta < math.inf:
        return None
    lm = law_model(law, params)
    nodes: dict[float, tuple[float, float]] = {}

    def solve_nodes(ds: np.ndarray, previous: tuple[float, float] | None) -> None:
        for D in ds:
            node = _optimum_node(lm, float(D), beta, omega, c, previous)
            if node is not None:
                nodes[float(D)] = previous = node

    base = params.L * np.concatenate(
        [np.geomspace(1e-7, 1e-3, 16, endpoint=False), np.geomspace(1e-3, 1.0, _BASE_NODES)]
    )
    solve_nodes(base, None)
    if not any(r > 1.0 for r, _ in nodes.values()):
        return None
    for lo, hi in itertools.pairwise(base):
        if nodes.get(float(lo), (1.0,))[0] > 1.0 or nodes.get(float(hi), (1.0,))[0] > 1.0:
            solve_nodes(np.geomspace(lo, hi, _REFINE + 1)[1:-1], nodes.get(float(lo)))
    ds = sorted(nodes)
    if len(ds) < 3:
        return None
    k = max(i for i, D in enumerate(ds) if nodes[D][0] > 1.0)
    return StartTable(
        tuple(math.log(D) for D in ds),
        tuple(math.log(nodes[D][0]) for D in ds),
        tuple(math.log(nodes[D][1]) for D in ds),
        math.log(ds[min(k + 1, len(ds) - 1)]),
    )


class StartTables:
    """The start tables that set-up has built, by (law, axis, ω, c); solves only read them."""

    def __init__(self, capacity: int = 512) -> None:
        self._capacity = capacity
        self._tables: dict[tuple[PolynomialLaw, AxisParams, float, float], StartTable | None] = {}

    def prepare(self, law: PolynomialLaw, params: AxisParams, omega: float, c: float) -> None:
        """Build (or find) the table of (law, axis, ω, c) and keep it for the solves (the oldest
        entry goes when more than ``capacity`` are kept)."""
        key = (law, params, omega, c)
        if key not in self._tables:
            self._tables[key] = build_start_table(law, params, omega, c)
            if len(self._tables) > self._capacity:
                del self._tables[next(iter(self._tables))]

    def get(self, law: PolynomialLaw, params: AxisParams, omega: float, c: float) -> StartTable | None:
        """The prepared table, or None (not prepared, or no move has braking at its optimum)."""
        return self._tables.get((law, params, omega, c))


START_TABLES = StartTables()
"""the process-wide start tables, filled by ``ExactBackend.prepare``"""
