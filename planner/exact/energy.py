"""The energy of a move along a law, in closed form and fixed quadratures, and its T-derivative.

**Signed energy** is friction work (the kinetic energy is returned at rest):

    E_s(T) = a1·D + a2·D²·I2/T + a3·D·Φ(a4·β),   β = D/T,  I2 = ∫s'²,  Φ(k) = ∫₀¹ s'·atan(k·s') du,
    dE_s/dT = −β²·(a2·I2 + a3·a4·Φ'(a4·β)),       Φ'(k) = ∫₀¹ s'²/(1 + k²s'²) du,

by graded Gauss–Legendre (~1e-13 relative). E_s is convex in T (for Φ: x²Φ''(x) + 2xΦ'(x) =
2x∫s'²/(1 + x²s'²)² ≥ 0). In J = ω·T + (1 − ω)·E_s, dJ/dT = 0 ⇔ ψ(β) := β²·(a2·I2 + a3·a4·Φ'(a4·β))
= ω/(1 − ω) with ψ increasing: the unconstrained optimum is T = D/β*(law, ω), one cached scalar per
ω (:func:`optimal_speed_ratio`).

**Braking energy.** The ``positive`` and ``absolute`` accountings add c·R(T) (c = 1, 2), R the
braking (regenerable) energy. Mapped to u ∈ [0, 1/2] from the move's end (u = 1 − t/T), the power
the cart returns is D·β·s'·h⁺ with the braking margin

    h(u) = A·s''(u) − φ(β·s'(u)),   A = M·β²/D,      R = D·∫ h⁺(u)·s'(u) du.

As a function of β, h is convex (M·β²·s''/D is, and −a3·atan(a4·β·s') is convex for β ≥ 0) and
increasing where positive, so h⁺ and R are convex and non-decreasing in β; β = D/T is convex in T,
hence R(T), and J = J_s + (1 − ω)·c·R, are convex in T for all three accountings. The interval where
h > 0 is located by Newton's method (h's peak, then its roots) and integrated by 16-point
Gauss–Legendre on panels graded towards its start, next to the move's end where atan(a4·β·s') turns
sharply, so the kink of h⁺ falls on the panel edges. Since h vanishes at the ends of that interval,
dR/dT = D·∫ ∂h/∂T·s' du with ∂h/∂T = (−2A·s'' + φ'(β·s')·β·s')/T. Agreement with the model's
``move_energy`` ≤ 1e-9 relative (tested).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from functools import lru_cache

import numpy as np

from ...model import AxisParams, EnergyAccounting, PolynomialLaw
from ...model.deadline import iteration_cap
from .law_model import NEWTON_MAX_STEPS, LawModel, horner, law_model

_BRENT_STEPS = 200
"""the cap of Brent's method on ψ(β) = ω/(1 − ω)"""
_BEYOND_ANY_SPEED = 1e6
"""β above this many v_max is no feasible speed ratio (the peak velocity c_v·β ≥ β exceeds v_max)"""

_GL16_X, _GL16_W = np.polynomial.legendre.leggauss(16)
_GL16_X1 = _GL16_X + 1.0
_POWERS = np.arange(16, dtype=float)
_GRADED_EDGES = (0.0, 1e-5, 1e-4, 1e-3, 1e-2, 0.05, 0.2, 0.5, 1.0)
_GRADED_X = np.concatenate([lo + 0.5 * (hi - lo) * _GL16_X1 for lo, hi in itertools.pairwise(_GRADED_EDGES)])
_GRADED_W = np.concatenate([0.5 * (hi - lo) * _GL16_W for lo, hi in itertools.pairwise(_GRADED_EDGES)])
"""16-point Gauss–Legendre on [0, 1], panels graded towards 0"""


def braking_weight(accounting: EnergyAccounting) -> float:
    """c in E = E_s + c·R: 0 for signed energy, 1 for positive, 2 for absolute."""
    if accounting is EnergyAccounting.SIGNED:
        return 0.0
    return 1.0 if accounting is EnergyAccounting.POSITIVE else 2.0


def phi(lm: LawModel, k: float) -> float:
    """Φ(k) = ∫₀¹ s'·atan(k·s') du (graded Gauss–Legendre, symmetric halves)."""
    s = lm.half_s1
    return float(np.dot(lm.half_w, s * np.arctan(k * s)))


def phi_prime(lm: LawModel, k: float) -> float:
    """Φ'(k) = ∫₀¹ s'²/(1 + k²s'²) du."""
    s = lm.half_s1
    return float(np.dot(lm.half_w, s * s / (1.0 + (k * s) ** 2)))


def signed_energy(lm: LawModel, D: float, T: float) -> float:
    """E_s(T) [J] = a1·D + a2·D²·I2/T + a3·D·Φ(a4·D/T): the friction work of the move."""
    return lm.a1 * D + lm.a2 * D * D * lm.I2 / T + lm.a3 * D * phi(lm, lm.a4 * D / T)


def signed_energy_slope(lm: LawModel, D: float, T: float) -> float:
    """dE_s/dT [J/s] = −(D/T)²·(a2·I2 + a3·a4·Φ'(a4·D/T))."""
    b = D / T
    return -b * b * (lm.a2 * lm.I2 + lm.a3 * lm.a4 * phi_prime(lm, lm.a4 * b))


def law_energy(lm: LawModel, D: float, T: float, accounting: EnergyAccounting) -> float:
    """E [J] of the move under ``accounting``: E_s + c·R; the same quantity as the model's
    :func:`axisflow.model.move_energy`, from this law's quadratures."""
    e = signed_energy(lm, D, T)
    if accounting is EnergyAccounting.SIGNED:
        return e
    return e + braking_weight(accounting) * braking_energy_and_slope(lm, D, T)[0]


def braking_margin(
    lm: LawModel, A: float, beta: float
) -> tuple[Callable[[float], tuple[float, float, float]], Callable[[float], tuple[float, float]]]:
    """Two scalar functions of u ∈ [0, 1/2] for the margin h = A·s'' − φ(β·s'):
    ``value(u)`` = (h, h', s'') and ``bend(u)`` = (h', h''), with h' = A·s''' − φ'·β·s'' and
    h'' = A·s'''' − φ''·(β·s'')² − φ'·β·s''' (φ', φ'' at v = β·s')."""
    a1, a2, a3, a4 = lm.a1, lm.a2, lm.a3, lm.a4
    c1, c2, c3, c4 = lm.c1, lm.c2, lm.c3, lm.c4
    # φ, φ', φ'' of model/friction.py (ForwardLaw.value, .slope, .curvature) are
    # inlined below: these run in the Newton steps of every braking evaluation, where numpy calls on
    # scalars would cost several times the evaluation (tests/planner/test_inlined_friction.py)

    def value(u: float) -> tuple[float, float, float]:
        s1, s2, s3 = horner(c1, u), horner(c2, u), horner(c3, u)
        v = beta * s1
        z = a4 * v
        fp = a2 + a3 * a4 / (1.0 + z * z)
        return A * s2 - a1 - a2 * v - a3 * math.atan(z), A * s3 - fp * beta * s2, s2

    def bend(u: float) -> tuple[float, float]:
        s1, s2, s3, s4 = horner(c1, u), horner(c2, u), horner(c3, u), horner(c4, u)
        v = beta * s1
        z = a4 * v
        q = 1.0 / (1.0 + z * z)
        fp = a2 + a3 * a4 * q
        fpp = -2.0 * a3 * a4 * a4 * z * q * q
        return A * s3 - fp * beta * s2, A * s4 - fpp * (beta * s2) ** 2 - fp * beta * s3

    return value, bend


def braking_energy_and_slope(
    lm: LawModel, D: float, T: float, hint: list[float] | None = None
) -> tuple[float, float]:
    """R(T) [J] and dR/dT [J/s] (see the module docstring).

    ``hint`` (a list, updated in place) carries [lo, peak, hi] of the previous call with the same
    D, where the Newton iterations then start.
    """
    beta = D / T
    A = lm.M * beta * beta / D
    value, bend = braking_margin(lm, A, beta)
    h0, h0_u, _ = value(0.0)
    u_peak = 0.0 if h0_u < 0.0 else _margin_peak(bend, hint[1] if hint else lm.u_acc_peak)
    h_peak = value(u_peak)[0]
    if h_peak <= 0.0:
        return 0.0, 0.0
    lo = 0.0 if h0 > 0.0 else _margin_root(value, 0.0, h0, u_peak, hint[0] if hint else -1.0)
    hi = _margin_root(value, u_peak, h_peak, 0.5, hint[2] if hint else -1.0)
    if hint is not None:
        hint[:] = [lo, u_peak, hi]
    # panels graded towards lo: the end of the move (u = 0), where atan(a4·β·s') turns sharply, is
    # at or next to it
    x, wq = lo + (hi - lo) * _GRADED_X, (hi - lo) * _GRADED_W
    s = np.power.outer(x, _POWERS[: lm.s12.shape[0]]) @ lm.s12  # s', s'' at the nodes
    s1, s2 = s[:, 0], s[:, 1]
    v = beta * s1
    h = A * s2 - lm.forward.value(v)
    np.maximum(h, 0.0, out=h)
    dh = lm.forward.slope(v) * v - 2.0 * A * s2  # T·∂h/∂T
    w = D * wq * s1
    return float(w @ h), float(w @ dh) / T


def _margin_peak(bend: Callable[[float], tuple[float, float]], u: float) -> float:
    """The peak of h on [0, 1/2] (h' > 0 at 0): safeguarded Newton on h' = 0 from u."""
    lo, hi = 0.0, 0.5
    for _ in range(NEWTON_MAX_STEPS):
        hu, huu = bend(u)
        if hu > 0.0:
            lo = u
        else:
            hi = u
        new = u - hu / huu if huu < 0.0 else -1.0
        if huu < 0.0 and abs(new - u) <= 1e-12:  # converged, also when u is now an end of [lo, hi]
            return min(max(new, lo), hi)
        if not lo < new < hi:
            new = 0.5 * (lo + hi)
        if abs(new - u) <= 1e-12 or hi - lo <= 1e-13:
            return new
        u = new
    return u


def _margin_root(
    value: Callable[[float], tuple[float, float, float]], a: float, fa: float, b: float, x0: float
) -> float:
    """The zero of h between a and b, where h changes sign (fa = h(a); safeguarded Newton from x0)."""
    x = x0 if a < x0 < b else 0.5 * (a + b)
    for _ in range(NEWTON_MAX_STEPS):
        fx, dx, _ = value(x)
        if (fx > 0.0) == (fa > 0.0):
            a, fa = x, fx
        else:
            b = x
        new = x - fx / dx if dx != 0.0 else -1.0
        if abs(new - x) <= 1e-15:  # converged, also when the step is below x's last bit and x is an end
            return min(max(new, min(a, b)), max(a, b))
        if not min(a, b) < new < max(a, b):
            new = 0.5 * (a + b)
        if abs(new - x) <= 1e-15 or abs(b - a) <= 1e-15:
            return new
        x = new
    return x


@lru_cache(maxsize=1024)
def optimal_speed_ratio(law: PolynomialLaw, params: AxisParams, omega: float) -> float:
    """β* [m/s]: the root of ψ(β) = β²·(a2·I2 + a3·a4·Φ'(a4·β)) = ω/(1 − ω) (ψ is increasing).

    The signed-energy time-energy optimum of a move of length D, ignoring limits and bounds, is
    T = D/β*. ω = 1 gives β* = ∞ (minimum time), ω = 0 gives β* = 0 (the slowest move). Without
    viscous friction (a2 = 0) ψ is bounded (by a3/a4·∫1 du as β → ∞): when ω/(1 − ω) lies above
    ψ at a speed far beyond any the limits allow, J increases with T over every feasible duration and
    β* = ∞ as well (the answer is the smallest feasible duration). Φ' here by adaptive quadrature.
    """
    if omega >= 1.0:
        return math.inf
    if omega <= 0.0:
        return 0.0
    from scipy.integrate import quad  # scipy loads on first use: a command that only parses loads none
    from scipy.optimize import brentq

    lm = law_model(law, params)
    target = omega / (1.0 - omega)

    def phi_prime_precise(k: float) -> float:
        def f(u: float) -> float:
            s = float(law.shape(u, 1))
            return s * s / (1.0 + (k * s) ** 2)

        return quad(f, 0.0, 1.0, epsabs=1e-15, epsrel=1e-13, limit=200, points=[0.5])[0]

    def psi(b: float) -> float:
        return b * b * (lm.a2 * lm.I2 + lm.a3 * lm.a4 * phi_prime_precise(lm.a4 * b)) - target

    hi = 1.0
    beyond = _BEYOND_ANY_SPEED * params.v_max
    while psi(hi) < 0.0:  # at most log2(beyond) + 1 doublings
        if hi > beyond:
            return math.inf
        hi *= 2.0
    try:
        return brentq(psi, 0.0, hi, xtol=1e-16, rtol=1e-15, maxiter=_BRENT_STEPS)
    except RuntimeError:  # pragma: no cover - Brent converges in ~20 steps on this smooth, monotone ψ
        what = f"the optimal speed ratio of {law.name} at omega = {omega}"
        raise iteration_cap(what, _BRENT_STEPS) from None
