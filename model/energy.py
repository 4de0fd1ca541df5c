"""Mechanical energy of a move, E = ∫ g(F·ẋ) dt, under an explicit accounting g (eq. 3).

* signed:   g(P) = P        (the formula as printed; braking is refunded)
* positive: g(P) = max(P,0) (no regeneration; the default, see docs/parameters.md)
* absolute: g(P) = |P|

For a rest-to-rest move the inertial part of the signed integral vanishes (kinetic energy is returned),
leaving friction work: a1·|d| + a2·d²/T·∫s'² du + a3·∫atan(a4·ẋ)·ẋ dt. The other accountings have no
closed form, so the integral is evaluated numerically: the power's sign changes are located (so the
kinks of max/abs fall on panel edges) and each smooth piece is integrated by Gauss–Legendre
quadrature, accurate to ~1e-12 relative.
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import pairwise

import numpy as np

from .dynamics import cart_force, mechanical_power
from .motion_laws import Motion, Move
from .params import AxisParams, EnergyAccounting

_GL_NODES, _GL_WEIGHTS = np.polynomial.legendre.leggauss(32)
_SCAN_POINTS = 513
_END_SCAN = np.geomspace(1e-13, 1e-3, 21)
_SCAN_U = np.unique(np.concatenate([np.linspace(0.0, 1.0, _SCAN_POINTS)[1:-1], _END_SCAN, 1.0 - _END_SCAN]))
"""where P(u) is scanned for sign changes: evenly, plus geometrically towards both ends"""
_PANELS_PER_PIECE = 4


def count_power(power_w: np.ndarray, accounting: EnergyAccounting) -> np.ndarray:
    """Apply the accounting g to a power signal [W]."""
    p = np.asarray(power_w, dtype=float)
    if accounting is EnergyAccounting.POSITIVE:
        return np.maximum(p, 0.0)
    if accounting is EnergyAccounting.ABSOLUTE:
        return np.abs(p)
    return p


def _power_of_u(move: Move, params: AxisParams):
    """P(u) = F·ẋ along the move as a function of normalised time u ∈ [0, 1]."""
    d, T, law = move.distance_m, move.duration_s, move.law

    def power(u: np.ndarray) -> np.ndarray:
        v = d / T * law.shape(u, 1)
        return cart_force(v, d / T**2 * law.shape(u, 2), params) * v

    return power


def _gauss(f, a: float, b: float, panels: int) -> float:  # noqa: ANN001
    edges = np.linspace(a, b, panels + 1)
    total = 0.0
    for lo, hi in pairwise(edges):
        half = 0.5 * (hi - lo)
        total += half * float(np.dot(_GL_WEIGHTS, f(lo + half * (_GL_NODES + 1.0))))
    return total


def move_energy(move: Move, params: AxisParams, accounting: EnergyAccounting | None = None) -> float:
    """Mechanical energy [J] of a move under ``accounting`` (default: the parameters' own)."""
    acc = params.energy_accounting if accounting is None else EnergyAccounting(accounting)
    if move.distance_m == 0.0:
        return 0.0
    return _accounted_integral(_power_of_u(move, params), acc) * move.duration_s


def motion_energy(
    motion: Motion,
    params: AxisParams,
    breaks_s: Sequence[float] | np.ndarray,
    accounting: EnergyAccounting | None = None,
) -> float:
    """Mechanical energy [J] of any rest-to-rest motion whose kinematics are smooth between
    consecutive ``breaks_s`` (the times [s] where a phase ends: a trapezoid's ramp and cruise, an
    S-curve's seven phases; the first 0, the last the duration), under ``accounting`` (default: the
    parameters' own).

    Each piece is integrated as :func:`move_energy` integrates a polynomial move, P = F·ẋ by eq. (1)
    from the motion's own velocity and acceleration, its sign changes located, so an acceleration that
    jumps at a break (a trapezoid's) costs nothing in accuracy."""
    acc = params.energy_accounting if accounting is None else EnergyAccounting(accounting)
    total = 0.0
    for lo, hi in pairwise(float(t) for t in breaks_s):
        if hi <= lo:
            continue

        def power(u: np.ndarray, lo: float = lo, hi: float = hi) -> np.ndarray:
            s = motion.sample(lo + (hi - lo) * np.asarray(u, dtype=float))
            return mechanical_power(s.velocity_m_s, s.acceleration_m_s2, params)

        total += _accounted_integral(power, acc) * (hi - lo)
    return total


def _accounted_integral(power, acc: EnergyAccounting) -> float:  # noqa: ANN001 - ndarray -> ndarray
    """∫₀¹ g(P(u)) du of a power P(u) that is smooth on [0, 1]."""
    # sign changes of P(u) split [0, 1] into pieces where g is smooth; the scan is dense next to the
    # ends too, where a short braking lobe (poly3 ends with ẍ ≠ 0 while ẋ → 0) would hide between
    # two evenly spaced samples. The end points themselves (ẋ = 0, P = 0) are left out; an interior
    # sample exactly at zero is a cut itself.
    u = _SCAN_U
    p = power(u)
    from scipy.optimize import brentq  # scipy loads on first use, not when the model is imported

    sign = np.sign(p)
    cuts = [0.0]
    for i in np.flatnonzero((sign[:-1] * sign[1:] < 0) | (sign[:-1] == 0.0)):
        if sign[i] == 0.0:
            cuts.append(float(u[i]))
        else:
            cuts.append(brentq(lambda x: float(power(np.array(x))), u[i], u[i + 1], xtol=1e-15))
    cuts.append(1.0)
    total = 0.0
    for lo, hi in pairwise(cuts):
        piece = _gauss(power, lo, hi, _PANELS_PER_PIECE)
        if acc is EnergyAccounting.POSITIVE:
            piece = max(piece, 0.0)
        elif acc is EnergyAccounting.ABSOLUTE:
            piece = abs(piece)
        total += piece
    return total


def trace_energy(
    velocity_m_s: np.ndarray, force_n: np.ndarray, dt_s: float, accounting: EnergyAccounting
) -> float:
    """Energy [J] of sampled force and velocity at a fixed step (trapezoidal rule on g(F·ẋ))."""
    p = count_power(np.asarray(force_n) * np.asarray(velocity_m_s), accounting)
    if p.size < 2:
        return 0.0
    return float(dt_s * (p.sum() - 0.5 * (p[0] + p[-1])))


def trace_energy_at(
    t_s: np.ndarray, velocity_m_s: np.ndarray, force_n: np.ndarray, accounting: EnergyAccounting
) -> float:
    """Energy [J] of force and velocity sampled at increasing times ``t_s`` [s], not necessarily evenly
    (a trace with a sample missing here and there): the trapezoidal rule on g(F·ẋ) over each step.
    With even steps it is :func:`trace_energy`."""
    p = count_power(np.asarray(force_n) * np.asarray(velocity_m_s), accounting)
    if p.size < 2:
        return 0.0
    return float(np.dot(np.diff(np.asarray(t_s, dtype=float)), 0.5 * (p[1:] + p[:-1])))


def energy_error_pct(planned_j: float, measured_j: float) -> float | None:
    """The paper's energy error E% = (E_th − E_exp)/E_th·100 of a planned energy E_th and a measured
    one E_exp [%]; None when nothing was planned (E_th = 0)."""
    if planned_j == 0.0:
        return None
    return (planned_j - measured_j) / planned_j * 100.0
