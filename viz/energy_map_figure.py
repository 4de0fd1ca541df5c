"""The paper's Fig. 4a: mechanical energy of a poly5 move over its travel d and execution time T.

E(d, T) = ∫₀ᵀ g(F·ẋ) dt is :func:`axisflow.model.move_energy` of the rest-to-rest poly5 move of length
d in time T, g the parameters' energy accounting (the default: positive power only). It is drawn as
filled contours over d ∈ (0, L] and the feasible T ∈ [T_min(d), 10 s], with

* the minimum-time limit T_min(d): below it the velocity or torque limit is broken (hatched) — the
  exact planner's case-1 duration with the duration bounds opened (0.001–3600 s);
* the minimum time-energy optimum T*(d) for ω = 0.9 (eq. 3, the exact planner's case-2 duration with
  the paper's bounds 0.3–20 s), the duration the planner picks for each d; the point at d = 0.4 m is
  the move of Fig. 4b.

The grid follows the limit: in each column d_j the times run from T_min(d_j) to the top, closer
together near the limit where E changes fastest, so the contours reach the limit without gaps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model import AxisParams, Move, move_energy, polynomial_law
from ..planner import DEFAULT_OMEGA, Case, MoveProblem, solve_exact
from .png import png_bytes, pyplot

LAW = "poly5"
T_TOP_S = 10.0
"""the longest execution time drawn [s]"""
GRID = (48, 48)
"""points in d and in T"""
MARKED_DISTANCE_M = 0.4
"""the distance of the move of Fig. 4b, marked on the optimum"""


@dataclass(frozen=True)
class EnergyMap:
    """E [J] on a grid that follows the limit: ``energy_j[i, j]`` at ``distance_m[j]`` and
    ``duration_s[i, j]`` (shape (nT, nd)); the minimum-time limit and the time-energy optimum [s] at
    the distances ``curve_distance_m``."""

    distance_m: np.ndarray
    duration_s: np.ndarray
    energy_j: np.ndarray
    curve_distance_m: np.ndarray
    t_min_s: np.ndarray
    t_opt_s: np.ndarray
    omega: float


def _duration(params: AxisParams, d: float, case: Case, omega: float) -> float:
    law = polynomial_law(LAW)
    if case is Case.MIN_TIME:
        problem = MoveProblem(0.0, d, law, case, t_min_s=1e-3, t_max_s=3600.0)
    else:
        problem = MoveProblem(0.0, d, law, case, omega)
    return solve_exact(problem, params).duration_s


def energy_map(params: AxisParams, omega: float = DEFAULT_OMEGA, grid: tuple[int, int] = GRID) -> EnergyMap:
    """The data of the figure (see the module docstring)."""
    law = polynomial_law(LAW)
    curve_d = np.linspace(params.L / 200, params.L, 200)
    t_min = np.array([_duration(params, d, Case.MIN_TIME, omega) for d in curve_d])
    t_opt = np.array([_duration(params, d, Case.MIN_TIME_ENERGY, omega) for d in curve_d])
    d = np.linspace(params.L / 200, params.L, grid[0])
    s = np.linspace(0.0, 1.0, grid[1]) ** 2  # denser near the limit
    lowest = np.array([_duration(params, di, Case.MIN_TIME, omega) for di in d])
    T = lowest[None, :] + s[:, None] * (T_TOP_S - lowest[None, :])
    energy = np.array(
        [[move_energy(Move(0.0, d[j], T[i, j], law), params) for j in range(len(d))] for i in range(len(s))]
    )
    return EnergyMap(d, T, energy, curve_d, t_min, t_opt, omega)


def energy_map_png(data: EnergyMap, params: AxisParams) -> bytes:
    """The figure as PNG bytes."""
    from matplotlib.ticker import MaxNLocator

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8.5, 5.6))
    X = np.broadcast_to(data.distance_m, data.duration_s.shape)
    levels = MaxNLocator(24).tick_values(0.0, float(data.energy_j.max()))
    filled = ax.contourf(X, data.duration_s, data.energy_j, levels=levels, cmap="viridis")
    lines = ax.contour(
        X, data.duration_s, data.energy_j, levels=levels[::4], colors="white", linewidths=0.5, alpha=0.7
    )
    ax.clabel(lines, fmt="%.0f J", fontsize=7)
    fig.colorbar(filled, ax=ax, label=f"mechanical energy E [J] ({params.energy_accounting.value} power)")
    ax.fill_between(
        data.curve_distance_m,
        0.0,
        data.t_min_s,
        facecolor="white",
        edgecolor="0.6",
        hatch="///",
        lw=0,
        label="infeasible: over v_max or tau_max",
    )
    ax.plot(data.curve_distance_m, data.t_min_s, color="tab:red", lw=2, label="minimum-time limit T_min(d)")
    ax.plot(
        data.curve_distance_m,
        data.t_opt_s,
        color="white",
        lw=2.2,
        ls="--",
        label=f"min time-energy optimum T*(d), ω = {data.omega:g}",
    )
    t_mark = float(np.interp(MARKED_DISTANCE_M, data.curve_distance_m, data.t_opt_s))
    ax.plot([MARKED_DISTANCE_M], [t_mark], "o", color="white", mec="black", ms=7)
    ax.annotate(
        f"T* = {t_mark:.2f} s at d = {MARKED_DISTANCE_M:g} m (Fig. 4b)",
        (MARKED_DISTANCE_M, t_mark),
        xytext=(12, -14),
        textcoords="offset points",
        color="white",
        fontsize=8,
    )
    ax.set_xlim(0.0, params.L)
    ax.set_ylim(0.0, T_TOP_S)
    ax.set_xlabel("travelled distance d [m]")
    ax.set_ylabel("execution time T [s]")
    ax.set_title(
        f"Fig. 4a — energy of a {LAW} move, E(d, T) = ∫ g(F·ẋ) dt with eq. (1), L = {params.L:g} m",
        fontsize=10,
    )
    ax.legend(loc="upper left", fontsize=8, framealpha=0.85)
    fig.tight_layout()
    return png_bytes(fig)
