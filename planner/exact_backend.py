"""Exact back-end: the paper's one-variable problem solved by its structure, with a certificate.

Notation (docs/planner.md has the derivations). A move of length D = |x1 − x0| > 0 along a law s(u)
in time T has, in the frame where it runs forward, velocity v = β·s'(u) with β = D/T, and needs the
cart force (eq. 1, the friction sign closed at the end points, as IPOPT's nodes do)

    F(u, T) = M·D·s''(u)/T² + φ(β·s'(u)),      φ(v) = a1 + a2·v + a3·atan(a4·v),  u ∈ [0, 1].

Case 1 (minimum time). The velocity limit gives T ≥ T_v = c_v·D/v_max (c_v = max s'). For the torque
limit, with a_i ≥ 0 both max_u F and max_u (−F) are non-increasing in T (each braking term −F shrinks
with T wherever it is positive, because atan(z) ≥ z/(1+z²)), so feasibility is monotone and the
answer is T* = max(T_min, T_v, T_τ), where T_τ solves max_u F(u, T) = F_max. The laws are symmetric
(s'(1−u) = s'(u), s''(1−u) = −s''(u)), so the braking peak is the driving peak minus twice the
friction and never binds; T_τ is found by Newton's method on the pair (u, y = 1/T) of equations
∂F/∂u = 0, F = F_max (the analytic extremum; at u = 0 for poly3 when the peak sits on the boundary).
The certificate is a bracket (t_lower_s, t_upper_s]: F(u*, t_lower_s) > F_max (or the velocity
limit) proves t_lower_s infeasible; t_upper_s meets every limit at the analytic extremum. When the
bound T_min decides, t_lower_s = t_upper_s = T_min (nothing shorter is allowed) and gap_s = 0.

Case 2 (minimum ω·T + (1 − ω)·E). Signed energy is friction work (the kinetic energy is returned):

    E_s(T) = a1·D + a2·D²·I2/T + a3·D·Φ(a4·β),   I2 = ∫s'²,  Φ(k) = ∫ s'·atan(k·s') du,

which is convex in T, and dJ/dT = 0 ⇔ ψ(β) := β²·(a2·I2 + a3·a4·Φ'(a4·β)) = ω/(1 − ω), with ψ
increasing: the unconstrained optimum is T = D/β*(law, ω), one cached scalar per ω. The constrained
optimum is the projection of D/β* on [T_feas, T_max]. Certificate: at an interior optimum a bracket
[t_lower_s, t_upper_s] with dJ/dT ≤ 0 ≤ dJ/dT at its ends and ``gap_j``, J(T) minus the crossing of
the tangents there (a lower bound on min J, by convexity); at a bound or a limit, dJ/dT there has the
sign that makes it the minimiser (gap 0), and a limit adds ``t_infeasible_s``, a duration proved to
break it.

The ``positive`` and ``absolute`` accountings add c·R(T) (c = 1, 2), R = D·∫ h⁺(u)·s'(u) du the
braking (regenerable) energy, h = A·|s''| − φ(β·s') on the braking half, A = M·β²/D. As a function
of β, h is convex (M·β²·|s''|/D convex, −a3·atan(a4·β·s') convex for β ≥ 0) and increasing where
positive, so h⁺ and R are convex and non-decreasing in β; β = D/T is convex in T, hence R and
J = J_s + (1 − ω)·c·R are convex in T. J is non-increasing on [T_feas, T_s] (T_s the signed
optimum), so the minimiser is T_s when dJ/dT(T_s) ≥ 0, and otherwise the root of dJ/dT in a bracket
[a, b] found by safeguarded secant steps, dR/dT by differentiating under the integral. The steps start
from a per-(law, axis, ω, accounting) table of the unconstrained optimum over log D (a Newton step
with its tabulated slope, then probes aimed just past the root), typically 3 exact evaluations; the
table is built by :meth:`ExactBackend.prepare` (20–60 ms), never inside a solve, so a solve has no
hidden set-up cost (without it the secant starts at T_s: 5–9 evaluations).
Certificate: by convexity min J ≥ the crossing of the tangents at a and b (exact evaluations only,
never the table); ``gap_j`` is J(best) minus that bound.
"""

from __future__ import annotations

import bisect
import itertools
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq

from ..model import AxisParams, EnergyAccounting, PolynomialLaw
from .errors import InfeasibleMoveError
from .evaluation import finish, objective
from .problem import Case, MoveProblem
from .result import PlanResult, SolveStatus

_NEWTON_MAX = 60
_GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0
_BEYOND_ANY_SPEED = 1e6
"""β above this many v_max is no feasible speed ratio (the peak velocity c_v·β ≥ β exceeds v_max)"""
_BRACKET_REL = 1e-11
"""relative width of the proved case-1 bracket"""


def _horner(c: tuple[float, ...], u: float) -> float:
    r = 0.0
    for a in c:
        r = r * u + a
    return r


def _graded_half_nodes(per_panel: int = 12) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights on [0, 1/2], panels graded towards u = 0 where s' → 0."""
    edges = [0.0, 1e-4, 1e-3, 5e-3, 0.02, 0.06, 0.13, 0.22, 0.33, 0.5]
    x, w = np.polynomial.legendre.leggauss(per_panel)
    us, ws = [], []
    for lo, hi in itertools.pairwise(edges):
        half = 0.5 * (hi - lo)
        us.append(lo + half * (x + 1.0))
        ws.append(half * w)
    return np.concatenate(us), np.concatenate(ws)


_GL16_X, _GL16_W = np.polynomial.legendre.leggauss(16)
_GL16_X1 = _GL16_X + 1.0
_POWERS = np.arange(16, dtype=float)
_GRADED_EDGES = (0.0, 1e-5, 1e-4, 1e-3, 1e-2, 0.05, 0.2, 0.5, 1.0)
_GRADED_X = np.concatenate([lo + 0.5 * (hi - lo) * _GL16_X1 for lo, hi in itertools.pairwise(_GRADED_EDGES)])
_GRADED_W = np.concatenate([0.5 * (hi - lo) * _GL16_W for lo, hi in itertools.pairwise(_GRADED_EDGES)])
"""16-point Gauss–Legendre on [0, 1], panels graded towards 0"""


def _coefficient_columns(*polys: np.ndarray) -> np.ndarray:
    """Polynomials (lowest power first) as the columns of one zero-padded matrix."""
    out = np.zeros((max(p.size for p in polys), len(polys)))
    for k, p in enumerate(polys):
        out[: p.size, k] = p
    return out


@dataclass(frozen=True, eq=False)
class LawModel:
    """A symmetric polynomial law and an axis, prepared for the exact solver (scalars and tables)."""

    law: PolynomialLaw
    M: float
    a1: float
    a2: float
    a3: float
    a4: float
    f_max_n: float
    v_max_m_s: float
    c1: tuple[float, ...]
    c2: tuple[float, ...]
    c3: tuple[float, ...]
    c4: tuple[float, ...]
    """s', s'', s''', s'''' coefficients, highest power first (Horner)"""
    u_acc_peak: float
    """argmax of s'' on [0, 1/2]"""
    I2: float
    """∫₀¹ s'² du"""
    half_u: np.ndarray
    half_w: np.ndarray
    half_s1: np.ndarray
    """graded quadrature on [0, 1/2] and s' at its nodes (weights doubled for the symmetric half)"""
    table: tuple[list[float], list[float], list[float]] | None
    """(log D, log y, u) of the torque root at table nodes; None until :meth:`with_table`"""
    s12: np.ndarray
    """(n, 2): s' and s'' coefficients, lowest power first (columns), for vectorised evaluation"""
    guess_tables: dict = field(default_factory=dict)
    """(ω, c) → :func:`_braking_guess_table` (or None), built by :meth:`ExactBackend.prepare`"""

    @classmethod
    def build(cls, law: PolynomialLaw, params: AxisParams) -> LawModel:
        if params.f_max <= params.a1:
            # F(u, T) → a1 as T → ∞: no duration makes the torque peak meet the limit
            raise InfeasibleMoveError(
                f"the motor torque limit tau_max = {params.tau_max} N·m gives a cart force of at most "
                f"F_max = {params.f_max:.6g} N, not above the Coulomb friction a1 = {params.a1} N: "
                "the axis cannot move"
            )
        d = [np.asarray(c, dtype=float) for c in law.derivatives]
        d4 = np.polynomial.polynomial.polyder(d[2])
        u = np.linspace(0.0, 1.0, 2001)
        s1, s2 = law.shape(u, 1), law.shape(u, 2)
        if not (np.allclose(s1, s1[::-1], atol=1e-12) and np.allclose(s2, -s2[::-1], atol=1e-12)):
            raise ValueError(f"law {law.name} is not symmetric; the exact back-end needs s'(1−u) = s'(u)")
        half = u <= 0.5
        hu, hw = _graded_half_nodes()
        return cls(
            law=law,
            M=params.M_eq,
            a1=params.a1,
            a2=params.a2,
            a3=params.a3,
            a4=params.a4,
            f_max_n=params.f_max,
            v_max_m_s=params.v_max,
            c1=tuple(float(c) for c in d[0][::-1]),
            c2=tuple(float(c) for c in d[1][::-1]),
            c3=tuple(float(c) for c in d[2][::-1]),
            c4=tuple(float(c) for c in d4[::-1]) if d4.size else (0.0,),
            u_acc_peak=float(u[half][np.argmax(s2[half])]),
            I2=law.integral_of_squared_velocity(),
            half_u=hu,
            half_w=2.0 * hw,
            half_s1=law.shape(hu, 1),
            table=None,
            s12=_coefficient_columns(d[0], d[1]),
        ).with_table(params.L)

    # ---- torque: F and its derivatives at (u, y = 1/T) -------------------------------------------
    def force_derivatives(self, u: float, y: float, D: float) -> tuple[float, float, float, float, float]:
        """F, ∂F/∂u, ∂²F/∂u², ∂F/∂y, ∂²F/∂u∂y at (u, y) for a move of length D (forward frame)."""
        s1 = _horner(self.c1, u)
        s2 = _horner(self.c2, u)
        s3 = _horner(self.c3, u)
        s4 = _horner(self.c4, u)
        a3, a4 = self.a3, self.a4
        Dy = D * y
        v = Dy * s1
        z = a4 * v
        q = 1.0 / (1.0 + z * z)
        fp = self.a2 + a3 * a4 * q
        fpp = -2.0 * a3 * a4 * a4 * z * q * q
        MDy2 = self.M * D * y * y
        F = MDy2 * s2 + self.a1 + self.a2 * v + a3 * math.atan(z)
        Fu = MDy2 * s3 + fp * Dy * s2
        Fuu = MDy2 * s4 + fpp * (Dy * s2) ** 2 + fp * Dy * s3
        Fy = 2.0 * self.M * D * y * s2 + fp * D * s1
        Fuy = 2.0 * self.M * D * y * s3 + D * s2 * (fp + fpp * v)
        return F, Fu, Fuu, Fy, Fuy

    def peak_force(self, y: float, D: float, u0: float) -> tuple[float, float, float]:
        """max over u ∈ [0, 1/2] of F(u, y): (F_peak [N], ∂F/∂y there [N·s], u_peak).

        Safeguarded Newton on ∂F/∂u = 0 inside a sign bracket (∂F/∂u > 0 left, < 0 right; at
        u = 1/2, s'' = 0 and s''' < 0). When ∂F/∂u(0) < 0 (poly3 with a strong inertia term) the
        peak is the boundary u = 0. The value returned is F at the last iterate plus the quadratic
        bound F_u²/(2|F_uu|) on what the remaining step could add, so it never under-reports.
        """
        fd = self.force_derivatives
        F, Fu, Fuu, Fy, _ = fd(0.0, y, D)
        if Fu < 0.0:
            return F, Fy, 0.0
        lo, hi = 0.0, 0.5
        u = min(max(u0, 0.0), 0.5)
        for _ in range(_NEWTON_MAX):
            F, Fu, Fuu, Fy, _ = fd(u, y, D)
            if Fu > 0.0:
                lo = u
            else:
                hi = u
            if Fuu < 0.0:
                new = u - Fu / Fuu
                if abs(new - u) <= 1e-9 and lo <= new <= hi:
                    return F + 0.5 * Fu * Fu / -Fuu, Fy, u
            else:
                new = -1.0
            if not lo < new < hi:
                new = 0.5 * (lo + hi)
            if hi - lo <= 1e-13:
                break
            u = new
        return F, Fy, u

    def _torque_root(self, D: float, y: float, u: float) -> tuple[float, float]:
        """y = 1/T_τ by Newton on G(y) = max_u F(u, y) − F_max (G increasing), from a guess."""
        M, fmax = self.M, self.f_max_n
        s2a = _horner(self.c2, self.u_acc_peak)
        y_hi = math.sqrt(fmax / (M * D * s2a))  # F(u_a, y_hi) ≥ F_max + a1: infeasible
        y_lo = 0.0  # F(u, 0) = a1 < F_max
        y = min(y, y_hi)
        for _ in range(_NEWTON_MAX):
            F, Fy, u = self.peak_force(y, D, u)
            G = F - fmax
            if G > 0.0:
                y_hi = y
            else:
                y_lo = y
            new = y - G / Fy
            if not y_lo < new < y_hi:
                new = 0.5 * (y_lo + y_hi)
            if abs(new - y) <= 2e-16 * y or y_hi - y_lo <= 2e-16 * y_hi:
                return (y if G <= 0.0 else min(new, y)), u
            y = new
        return y_lo, u

    def torque_limited_duration(self, D: float) -> tuple[float, float, float]:
        """T_τ [s]: smallest T with max_u F(u, T) ≤ F_max.

        Newton's method on the pair of equations ∂F/∂u = 0, F = F_max in (u, y = 1/T) from the
        law's table (2–4 steps); the safeguarded scalar iteration of :meth:`_torque_root` takes over
        if a step misbehaves. Returns (t_upper_s, t_lower_s, u_peak): the peak meets the limit at
        t_upper_s and exceeds it at t_lower_s (a proof that t_lower_s is infeasible).
        """
        fmax = self.f_max_n
        y, u = self._table_guess(D)
        fd = self.force_derivatives
        for _ in range(12):
            F, Fu, Fuu, Fy, Fuy = fd(u, y, D)
            G = F - fmax
            if u <= 0.0 and Fu <= 0.0:  # boundary peak (poly3): solve F(0, y) = F_max in y only
                du, dy = 0.0, -G / Fy
            elif Fuu < 0.0:
                det = Fuu * Fy - Fuy * Fu
                du = (Fuy * G - Fy * Fu) / det
                dy = (Fu * Fu - Fuu * G) / det
            else:
                y, u = self._torque_root(D, y, u)
                break
            u = u + du
            if u < 0.0:
                u = 0.0
            elif u > 0.5:
                y, u = self._torque_root(D, y, 0.25)
                break
            y += dy
            if abs(dy) <= 1e-15 * y and abs(du) <= 1e-9:
                break
        else:
            y, u = self._torque_root(D, y, u)
        F, _, u = self.peak_force(y, D, u)
        while fmax < F:  # rounding: step to the feasible side
            y *= 1.0 - 4e-16
            F, _, u = self.peak_force(y, D, u)
        t_up = 1.0 / y
        t_low = t_up * (1.0 - _BRACKET_REL)
        if fd(u, 1.0 / t_low, D)[0] <= fmax:  # pragma: no cover - numerical guard
            t_low = t_up * (1.0 - 1e-8)
        return t_up, t_low, u

    def _table_guess(self, D: float) -> tuple[float, float]:
        """(y, u) of the torque root interpolated from the table over log D (a start for Newton)."""
        table = self.table
        x = math.log(D)
        if table is None or not table[0][0] < x < table[0][-1]:
            fmax = self.f_max_n
            free = fmax - self.a1 - self.a3 * math.pi / 2.0 - self.a2 * self.v_max_m_s
            if free <= 0.0:
                free = 0.5 * (fmax - self.a1)
            return math.sqrt(free / (self.M * D * _horner(self.c2, self.u_acc_peak))), self.u_acc_peak
        log_d, log_y, us = table
        k = bisect.bisect_right(log_d, x) - 1
        w = (x - log_d[k]) / (log_d[k + 1] - log_d[k])
        return math.exp(log_y[k] + w * (log_y[k + 1] - log_y[k])), us[k] + w * (us[k + 1] - us[k])

    def with_table(self, stroke_m: float, nodes: int = 160) -> LawModel:
        """Fill the table of the torque root y(D) over D ∈ [1e-7·L, 1.001·L] (log spaced)."""
        ds = np.geomspace(1e-7 * stroke_m, 1.001 * stroke_m, nodes)
        log_y, us = [], []
        for D in ds:
            y, u = self._torque_root(float(D), *self._table_guess(float(D)))
            log_y.append(math.log(y))
            us.append(u)
        object.__setattr__(self, "table", ([math.log(float(D)) for D in ds], log_y, us))
        return self

    # ---- energy ----------------------------------------------------------------------------------
    def phi(self, k: float) -> float:
        """Φ(k) = ∫₀¹ s'·atan(k·s') du (graded Gauss–Legendre, symmetric halves)."""
        s = self.half_s1
        return float(np.dot(self.half_w, s * np.arctan(k * s)))

    def phi_prime(self, k: float) -> float:
        """Φ'(k) = ∫₀¹ s'²/(1 + k²s'²) du."""
        s = self.half_s1
        return float(np.dot(self.half_w, s * s / (1.0 + (k * s) ** 2)))

    def signed_energy(self, D: float, T: float) -> float:
        """E_s(T) [J] = a1·D + a2·D²·I2/T + a3·D·Φ(a4·D/T): the friction work of the move."""
        return self.a1 * D + self.a2 * D * D * self.I2 / T + self.a3 * D * self.phi(self.a4 * D / T)

    def signed_energy_slope(self, D: float, T: float) -> float:
        """dE_s/dT [J/s] = −(D/T)²·(a2·I2 + a3·a4·Φ'(a4·D/T))."""
        b = D / T
        return -b * b * (self.a2 * self.I2 + self.a3 * self.a4 * self.phi_prime(self.a4 * b))

    def energy(self, D: float, T: float, accounting: EnergyAccounting) -> float:
        """E [J] of the move under ``accounting``: E_s + c·R (c = 0, 1, 2 for signed, positive,
        absolute); the same quantity as :func:`axisflow.model.move_energy`, from this law's tables."""
        e = self.signed_energy(D, T)
        if accounting is EnergyAccounting.SIGNED:
            return e
        return e + (1.0 if accounting is EnergyAccounting.POSITIVE else 2.0) * self.braking_energy(D, T)

    def braking_energy(self, D: float, T: float) -> float:
        """R(T) [J]; see :meth:`braking_energy_and_slope`."""
        return self.braking_energy_and_slope(D, T)[0]

    def braking_energy_and_slope(
        self, D: float, T: float, hint: list[float] | None = None
    ) -> tuple[float, float]:
        """R(T) [J] and dR/dT [J/s]: R = D·∫ h⁺·s' du over the braking half, h = A·|s''| − φ(β·s').

        Mapped to u' = 1 − u ∈ [0, 1/2]: h = A·s''(u') − φ(β·s'(u')), A = M·β²/D, β = D/T. The
        interval where h > 0 is bracketed by the peak of h (Newton) and its roots (safeguarded
        Newton), then integrated by 16-point Gauss–Legendre, so the kink of h⁺ falls on the panel
        edges (on panels graded towards the interval's start, next to the move's end). Since
        h vanishes at the ends of the interval, dR/dT = D·∫ ∂h/∂T·s' du with
        ∂h/∂T = (−2A·s'' + φ'(β·s')·β·s')/T.
        ``hint`` (a list, updated in place) carries [lo, peak, hi] of the previous call with the same
        D, where the Newton iterations then start.
        """
        beta = D / T
        A = self.M * beta * beta / D
        a1, a2, a3, a4 = self.a1, self.a2, self.a3, self.a4
        c1, c2, c3, c4 = self.c1, self.c2, self.c3, self.c4

        def h_and_slope(u: float) -> tuple[float, float, float]:
            s1, s2, s3 = _horner(c1, u), _horner(c2, u), _horner(c3, u)
            v = beta * s1
            z = a4 * v
            fp = a2 + a3 * a4 / (1.0 + z * z)
            return A * s2 - a1 - a2 * v - a3 * math.atan(z), A * s3 - fp * beta * s2, s2

        # peak of h: start at the peak of s''; h' = A s''' − φ'(v)·β·s''
        u = hint[1] if hint else self.u_acc_peak
        lo_b, hi_b = 0.0, 0.5
        h0, hu0, _ = h_and_slope(0.0)
        if hu0 < 0.0:
            u = 0.0
        else:
            for _ in range(_NEWTON_MAX):
                s1, s2, s3, s4 = _horner(c1, u), _horner(c2, u), _horner(c3, u), _horner(c4, u)
                v = beta * s1
                z = a4 * v
                q = 1.0 / (1.0 + z * z)
                fp = a2 + a3 * a4 * q
                fpp = -2.0 * a3 * a4 * a4 * z * q * q
                hu = A * s3 - fp * beta * s2
                huu = A * s4 - fpp * (beta * s2) ** 2 - fp * beta * s3
                if hu > 0.0:
                    lo_b = u
                else:
                    hi_b = u
                new = u - hu / huu if huu < 0.0 else -1.0
                if not lo_b < new < hi_b:
                    new = 0.5 * (lo_b + hi_b)
                if abs(new - u) <= 1e-12 or hi_b - lo_b <= 1e-13:
                    u = new
                    break
                u = new
        h_peak = h_and_slope(u)[0]
        if h_peak <= 0.0:
            return 0.0, 0.0

        def root(a: float, b: float, x0: float) -> float:
            """the zero of h between a (h(a) ≤ 0 or > 0) and b, h changing sign (safeguarded Newton)."""
            fa = h_and_slope(a)[0]
            x = x0 if a < x0 < b else 0.5 * (a + b)
            for _ in range(_NEWTON_MAX):
                fx, dx, _ = h_and_slope(x)
                if (fx > 0.0) == (fa > 0.0):
                    a, fa = x, fx
                else:
                    b = x
                new = x - fx / dx if dx != 0.0 else -1.0
                if not min(a, b) < new < max(a, b):
                    new = 0.5 * (a + b)
                if abs(new - x) <= 1e-15 or abs(b - a) <= 1e-15:
                    return new
                x = new
            return x

        lo = 0.0 if h0 > 0.0 else root(0.0, u, hint[0] if hint else -1.0)
        hi = root(u, 0.5, hint[2] if hint else -1.0)
        if hint is not None:
            hint[:] = [lo, u, hi]
        # panels graded towards lo: the end of the move (u' = 0), where atan(a4·β·s') turns sharply, is
        # at or next to it
        x, wq = lo + (hi - lo) * _GRADED_X, (hi - lo) * _GRADED_W
        s = np.power.outer(x, _POWERS[: self.s12.shape[0]]) @ self.s12  # s', s'' at the nodes
        s1, s2 = s[:, 0], s[:, 1]
        v = beta * s1
        z = a4 * v
        hv = A * s2 - a1 - a2 * v - a3 * np.arctan(z)
        np.maximum(hv, 0.0, out=hv)
        dh = (a2 + a3 * a4 / (1.0 + z * z)) * v - 2.0 * A * s2
        w = D * wq * s1
        return float(w @ hv), float(w @ dh) / T


@lru_cache(maxsize=256)
def law_model(law: PolynomialLaw, params: AxisParams) -> LawModel:
    """The prepared law for an axis (cached: parameters are frozen and hashable)."""
    return LawModel.build(law, params)


@lru_cache(maxsize=1024)
def optimal_speed_ratio(law: PolynomialLaw, params: AxisParams, omega: float) -> float:
    """β* [m/s]: the root of ψ(β) = β²·(a2·I2 + a3·a4·Φ'(a4·β)) = ω/(1 − ω) (ψ is increasing).

    The signed-energy time-energy optimum of a move of length D, ignoring limits and bounds, is
    T = D/β*. ω = 1 gives β* = ∞ (minimum time), ω = 0 gives β* = 0 (the slowest move). Without
    viscous friction (a2 = 0) ψ is bounded (by a3/a4·∫1 du as β → ∞): when ω/(1 − ω) lies above
    ψ at a speed far beyond any the limits allow, J increases with T over every feasible duration and
    β* = ∞ as well (the answer is the smallest feasible duration).
    """
    if omega >= 1.0:
        return math.inf
    if omega <= 0.0:
        return 0.0
    lm = law_model(law, params)
    target = omega / (1.0 - omega)

    def phi_prime(k: float) -> float:
        def f(u: float) -> float:
            s = float(law.shape(u, 1))
            return s * s / (1.0 + (k * s) ** 2)

        return quad(f, 0.0, 1.0, epsabs=1e-15, epsrel=1e-13, limit=200, points=[0.5])[0]

    def psi(b: float) -> float:
        return b * b * (lm.a2 * lm.I2 + lm.a3 * lm.a4 * phi_prime(lm.a4 * b)) - target

    hi = 1.0
    beyond = _BEYOND_ANY_SPEED * params.v_max
    while psi(hi) < 0.0:
        if hi > beyond:
            return math.inf
        hi *= 2.0
    return brentq(psi, 0.0, hi, xtol=1e-16, rtol=1e-15)


@dataclass(frozen=True)
class ExactSolution:
    """The bare answer of the exact solver (no 1 kHz scoring): duration, objective and proof."""

    duration_s: float
    objective: float
    energy_j: float
    active: str
    """what decides the duration: t_min, velocity, torque, t_max, optimum, zero-length"""
    certificate: dict[str, float]


def min_feasible_duration(
    problem: MoveProblem, params: AxisParams, lm: LawModel | None = None
) -> tuple[float, float, str]:
    """(T_feas, T_below, active): the smallest feasible duration in the bounds and a proved-infeasible
    duration just below it (0 when T_feas is the lower bound); raises when none is feasible."""
    lm = lm or law_model(problem.law, params)
    D = abs(problem.x1_m - problem.x0_m)
    t_v = problem.law.peak_velocity_factor * D / params.v_max
    t_tau, t_tau_low, _ = lm.torque_limited_duration(D)
    t_min, t_max = problem.t_min_s, problem.t_max_s
    if t_min >= t_v and t_min >= t_tau:
        t, below, active = t_min, 0.0, "t_min"
    elif t_v >= t_tau:
        t, active = t_v, "velocity"
        c_v = problem.law.peak_velocity_factor
        while c_v * D / t > params.v_max:  # rounding: step up until the peak velocity meets the limit
            t = math.nextafter(t, math.inf)
        below = math.nextafter(t, 0.0)
        while c_v * D / below <= params.v_max:  # and down until it breaks it, as computed: the proof
            below = math.nextafter(below, 0.0)
    else:
        t, below, active = t_tau, t_tau_low, "torque"
    if t > t_max:
        raise InfeasibleMoveError(
            f"no duration in [{t_min}, {t_max}] s keeps the {problem.law.name} move {problem.x0_m:.6g} m → "
            f"{problem.x1_m:.6g} m within the limits: it needs T >= {t:.6g} s "
            f"(velocity: {t_v:.6g} s at v_max = {params.v_max} m/s; torque: {t_tau:.6g} s at "
            f"tau_max = {params.tau_max} N·m)"
        )
    return t, below, active


def solve_exact(problem: MoveProblem, params: AxisParams) -> ExactSolution:
    """Solve one move exactly (see the module docstring); the hot path of :class:`ExactBackend`."""
    problem.check_stroke(params)
    D = abs(problem.x1_m - problem.x0_m)
    if D == 0.0:
        t = problem.t_min_s
        return ExactSolution(t, objective(problem, t, 0.0), 0.0, "zero-length", {})
    lm = law_model(problem.law, params)
    if problem.case is Case.MIN_TIME:
        t_feas, t_below, active = min_feasible_duration(problem, params, lm)
        if active == "t_min":  # nothing shorter is allowed: the bound itself is the proof
            t_below = t_feas
        return ExactSolution(
            t_feas,
            problem.w0 * t_feas,
            math.nan,
            active,
            {"t_lower_s": t_below, "t_upper_s": t_feas, "gap_s": t_feas - t_below},
        )
    # case 2: the signed optimum D/β* projected on the bounds; if it meets the limits the smallest
    # feasible duration is not needed (feasibility is monotone), otherwise it is the answer
    beta = optimal_speed_ratio(problem.law, params, problem.omega)
    t_free = D / beta if beta > 0.0 else math.inf
    t_c = min(max(t_free, problem.t_min_s), problem.t_max_s)
    active = "optimum" if t_c == t_free else ("t_min" if t_c == problem.t_min_s else "t_max")
    proof: dict[str, float] = {}
    if (
        problem.law.peak_velocity_factor * D <= params.v_max * t_c
        and lm.peak_force(1.0 / t_c, D, lm.u_acc_peak)[0] <= lm.f_max_n
    ):
        t_s = t_c
    else:
        t_s, t_below, active = min_feasible_duration(problem, params, lm)
        if active in ("velocity", "torque"):
            proof = {"t_infeasible_s": t_below}  # a limit decides: shorter durations are proved out
    sol = _time_energy(problem, params, lm, D, t_s, active, beta)
    if proof and sol.duration_s == t_s:
        sol.certificate.update(proof)
    return sol


class _Slope:
    """dJ/dT of J = ω·T + (1 − ω)·(E_s + c·R) for one move, memoised per T (J itself on demand)."""

    __slots__ = ("D", "c", "hint", "lm", "memo", "omega")

    def __init__(self, lm: LawModel, D: float, omega: float, c: float) -> None:
        self.lm, self.D, self.omega, self.c = lm, D, omega, c
        self.hint: list[float] = []
        self.memo: dict[float, tuple[float, float]] = {}

    def __call__(self, t: float) -> tuple[float, float]:
        """(dJ/dT, R) at t: exact evaluations (analytic interval, Gauss–Legendre), memoised."""
        got = self.memo.get(t)
        if got is None:
            lm, D, omega = self.lm, self.D, self.omega
            r, dr = lm.braking_energy_and_slope(D, t, self.hint)
            got = self.memo[t] = (omega + (1.0 - omega) * (lm.signed_energy_slope(D, t) + self.c * dr), r)
        return got

    def objective(self, t: float) -> float:
        """J(t) [same units as the objective]; R from the memo when t was evaluated."""
        r = self(t)[1]
        return self.omega * t + (1.0 - self.omega) * (self.lm.signed_energy(self.D, t) + self.c * r)


def _slope_root(
    slope: _Slope, t_s: float, g_s: float, t_max: float, guess: tuple[float, float] | None = None
) -> tuple[float, float, float, bool]:
    """The root of dJ/dT (increasing: J is convex) right of T_s, where dJ/dT(T_s) = g_s < 0.

    Returns (a, b, g_last, open): dJ/dT(a) ≤ 0 ≤ dJ/dT(b) with b − a ≤ 1e-10·b, or ``open`` when
    dJ/dT < 0 up to t_max (then a = t_max). Secant steps, kept inside the bracket [a, b] once one is
    known; bisection when a step leaves it or stalls. ``guess`` = (T₀, dJ/dT'(T₀)) from the per-law
    table (:func:`_braking_guess_table`): the iteration then starts with an exact evaluation at T₀ and
    a Newton step with the tabulated slope, instead of a probe next to T_s. Close to the root
    (the secant's error estimate far below 1e-11·T) each probe is aimed 1e-11·T past the secant's
    root, away from the end just evaluated, so that the bracket closes in one or two more
    evaluations. Only exact evaluations of dJ/dT decide the bracket: the guess changes the path,
    never the proof.
    """
    a, b = t_s, math.inf
    x_prev, g_prev = t_s, g_s
    x = min(t_s * (1.0 + 1e-3), t_max)
    if guess is not None:
        t0, gp = guess
        if t_s <= t0 < t_max and gp > 0.0:
            g0 = slope(t0)[0]
            if g0 > 0.0:
                b = t0
            else:
                a = t0
            if g0 == 0.0:
                return t0, t0, 0.0, False
            x_prev, g_prev = t0, g0
            nx = t0 - g0 / gp  # (when it is already the left end, its value is memoised)
            x = nx if a <= nx < min(b, t_max) else (0.5 * (a + b) if b < math.inf else min(t0 * 1.01, t_max))
    gx = g_s
    for it in range(_NEWTON_MAX):
        gx = slope(x)[0]
        if gx > 0.0:
            b = min(b, x)
        else:
            a = max(a, x)
        if gx == 0.0 or (b < math.inf and b - a <= 1e-10 * b):
            break
        if gx < 0.0 and x >= t_max:  # J decreasing up to the bound
            break
        nx = x - gx * (x - x_prev) / (gx - g_prev) if gx != g_prev else math.nan
        # the secant's error is ~ |nx − x|·|nx − x_prev|/T: when that is far below 1e-11·T, a probe
        # 1e-11·T past nx lands on the other side of the root
        err = abs(nx - x) * abs(nx - x_prev) / x
        near = err <= 1e-13 * x
        x_prev, g_prev = x, gx
        if b == math.inf:
            if not nx > a:  # no sensible secant step yet: double the distance from T_s
                nx = t_s + 2.0 * (a - t_s)
            # aim a hair past the secant's root, so that a step from the left also brackets it
            x = min(nx + min(max(1e-11 * nx, 4.0 * err), 1e-10 * nx), t_max)
        elif a < nx < b and it < 12:
            if near:  # aim past the root, away from the end just evaluated
                hair = nx + (1e-11 * nx if gx < 0.0 else -1e-11 * nx)
                if a < hair < b:
                    nx = hair
            x = nx
        else:
            x = 0.5 * (a + b)
    if b == math.inf:
        return a, a, gx, True
    while b - a > 1e-10 * b and gx != 0.0:  # fallback: bisection (not reached in practice)
        x = 0.5 * (a + b)
        gx = slope(x)[0]
        if gx > 0.0:
            b = x
        else:
            a = x
    if gx == 0.0:
        a = b = x
    return a, b, gx, False


_GUESS_NODES = 48
"""base nodes of the start table over [1e-3·L, L] (16 more over [1e-7·L, 1e-3·L))"""
_GUESS_REFINE = 8
"""sub-intervals per base interval where the optimum has braking energy"""


@lru_cache(maxsize=512)
def _braking_guess_table(
    law: PolynomialLaw, params: AxisParams, omega: float, c: float
) -> tuple[list[float], list[float], list[float], float] | None:
    """Start points for :func:`_slope_root`: (log D, log(T_opt·β*/D), log(T·dJ/dT')) over log D,
    and the log D above which no node has braking energy at its optimum (no guess there).

    T_opt is the unconstrained optimum (no bounds, no limits) of a move of length D with the braking
    energy counted c times, solved by :func:`_slope_root` from T = D/β* (each node started from the
    previous one); dJ/dT' there by a central difference. Base nodes: 16 log-spaced D in
    [1e-7·L, 1e-3·L) and 48 in [1e-3·L, L]; every base interval with braking at either end is
    split in 8 (the braking optimum turns on over a narrow range of D, ~12 % wide for poly5).
    Interpolation (quadratic in log D) then gives T_opt to ~1e-5 and one Newton step with the
    tabulated slope ~1e-8, so two to four exact evaluations close the bracket. None when no move
    has braking energy at its optimum. Built once per (law, axis, ω, accounting), ~20–60 ms.
    """
    beta = optimal_speed_ratio(law, params, omega)
    if not 0.0 < beta < math.inf:
        return None
    lm = law_model(law, params)
    nodes: dict[float, tuple[float, float]] = {}
    last: list[tuple[float, float]] = []

    def node(D: float) -> None:
        t_s = D / beta
        slope = _Slope(lm, D, omega, c)
        g_s, r_s = slope(t_s)
        t_opt = t_s
        if r_s > 0.0 and g_s < 0.0:
            prev = (t_s * last[0][0], last[0][1] / t_s) if last else None
            a, b, _, is_open = _slope_root(slope, t_s, g_s, math.inf, prev)
            if is_open:  # pragma: no cover - J is bounded below by ω·T
                return
            t_opt = 0.5 * (a + b)
        h = 1e-5 * t_opt
        gp = (slope(t_opt + h)[0] - slope(t_opt - h)[0]) / (2.0 * h)
        if gp > 0.0:
            nodes[D] = (t_opt / t_s, t_opt * gp)
            last[:] = [(t_opt / t_s, t_opt * gp)]

    base = params.L * np.concatenate(
        [np.geomspace(1e-7, 1e-3, 16, endpoint=False), np.geomspace(1e-3, 1.0, _GUESS_NODES)]
    )
    for D in base:
        node(float(D))
    if not any(r > 1.0 for r, _ in nodes.values()):
        return None
    for lo, hi in itertools.pairwise(base):
        if nodes.get(float(lo), (1.0,))[0] > 1.0 or nodes.get(float(hi), (1.0,))[0] > 1.0:
            last[:] = [nodes[float(lo)]] if float(lo) in nodes else []
            for D in np.geomspace(lo, hi, _GUESS_REFINE + 1)[1:-1]:
                node(float(D))
    ds = sorted(nodes)
    if len(ds) < 3:
        return None
    k = max(i for i, D in enumerate(ds) if nodes[D][0] > 1.0)
    return (
        [math.log(D) for D in ds],
        [math.log(nodes[D][0]) for D in ds],
        [math.log(nodes[D][1]) for D in ds],
        math.log(ds[min(k + 1, len(ds) - 1)]),
    )


def _guess(
    table: tuple[list[float], list[float], list[float], float] | None, D: float, t_free: float
) -> tuple[float, float] | None:
    """(T₀, dJ/dT'(T₀)) interpolated from the table (None outside it); t_free = D/β*."""
    if table is None:
        return None
    log_d, log_r, log_s, x_braking = table
    x = math.log(D)
    if not log_d[0] <= x <= x_braking:
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
    return t0, math.exp(log_s[k] + w * (log_s[k + 1] - log_s[k])) / t0


def _tangent_lower_bound(a: float, b: float, ja: float, jb: float, ga: float, gb: float) -> float:
    """A lower bound on min J over [a, b] for a convex J with slopes ga ≤ 0 ≤ gb at the ends: the
    crossing of the tangents at a and b."""
    if a == b:
        return ja
    if gb > ga:
        t_x = (jb - ja + ga * a - gb * b) / (ga - gb)
        return ja + ga * (t_x - a)
    return min(ja, jb)


def _bracket_certificate(
    value_and_slope: Callable[[float], tuple[float, float]], t: float, j: float, slope: float
) -> dict[str, float]:
    """Certificate of an interior optimum T of a convex J (``value_and_slope(x)`` = (J, dJ/dT) at x):
    durations a < T < b with dJ/dT(a) ≤ 0 ≤ dJ/dT(b), and the gap of J(T) to the tangent bound."""
    for rel in (3e-11, 1e-9, 1e-7, 1e-5, 1e-4):
        a, b = t * (1.0 - rel), t * (1.0 + rel)
        (ja, ga), (jb, gb) = value_and_slope(a), value_and_slope(b)
        if ga <= 0.0 <= gb:
            lb = _tangent_lower_bound(a, b, ja, jb, ga, gb)
            return {"gap_j": max(j - lb, 0.0), "t_lower_s": a, "t_upper_s": b, "dJ_dT": slope}
    return {"gap_j": math.nan, "dJ_dT": slope}  # pragma: no cover - J flat to 1e-4·T: no proof


def _time_energy(
    problem: MoveProblem,
    params: AxisParams,
    lm: LawModel,
    D: float,
    t_s: float,
    active: str,
    beta: float,
) -> ExactSolution:
    """Case 2 from the signed optimum ``t_s`` (already feasible and inside the bounds); β* given."""
    omega = problem.omega
    t_max = problem.t_max_s
    acc = params.energy_accounting

    def signed(x: float) -> tuple[float, float]:
        """(J_s, dJ_s/dT) at x: the objective with signed energy"""
        return (
            omega * x + (1 - omega) * lm.signed_energy(D, x),
            omega + (1 - omega) * lm.signed_energy_slope(D, x),
        )

    if acc is EnergyAccounting.SIGNED:
        e = lm.signed_energy(D, t_s)
        j = omega * t_s + (1 - omega) * e
        slope = omega + (1.0 - omega) * lm.signed_energy_slope(D, t_s)
        certificate = {"gap_j": 0.0, "dJ_dT": slope}
        if active == "optimum":
            certificate = _bracket_certificate(signed, t_s, j, slope)
        # at a bound or a limit: dJ/dT has the sign that, by convexity, makes T_s the minimiser
        return ExactSolution(t_s, j, e, active, certificate)
    c = 1.0 if acc is EnergyAccounting.POSITIVE else 2.0
    slope = _Slope(lm, D, omega, c)
    guess = None
    if 0.0 < beta < math.inf and t_s < t_max:
        table = lm.guess_tables.get((omega, c))  # built by ExactBackend.prepare(), never in a solve
        if table:
            guess = _guess(table, D, D / beta)
            if guess is not None and not (t_s < guess[0] < t_max and guess[1] > 0.0):
                guess = None
    left = None
    if guess is not None:
        # dJ/dT < 0 at some T > T_s: J is convex, so its minimiser lies right of it and T_s needs
        # no evaluation; try T₀ and, when dJ/dT(T₀) > 0, the Newton step from it and a secant probe
        t0, gp = guess
        g0 = slope(t0)[0]
        if g0 < 0.0:
            left = t0, g0
        elif g0 > 0.0 and t_s < t0 - g0 / gp:
            x1 = t0 - g0 / gp
            g1 = slope(x1)[0]
            if g1 < 0.0:
                left = x1, g1
            elif g1 > 0.0 and g1 < g0:  # still right of the root: a secant probe aimed just left of it
                nx = x1 - g1 * (x1 - t0) / (g1 - g0)
                x2 = nx - max(1e-11 * nx, 4.0 * abs(nx - x1) * abs(nx - t0) / nx)
                if t_s < x2:
                    g2 = slope(x2)[0]
                    if g2 < 0.0:
                        left = x2, g2
    if left is not None:
        a, b, gx, is_open = _slope_root(slope, left[0], left[1], t_max, guess)
    else:
        g_s, r_s = slope(t_s)
        if r_s == 0.0 or t_s >= t_max or omega >= 1.0 or g_s >= 0.0:
            # J is convex (see the module docstring) and non-increasing on [T_feas, T_s]; dJ/dT ≥ 0
            # at T_s (or R = 0 there, so J = J_s from T_s on) makes T_s the global minimiser
            e = lm.signed_energy(D, t_s) + c * r_s
            j = slope.objective(t_s)
            certificate = {"gap_j": 0.0, "dJ_dT": g_s}
            if active == "optimum" and r_s == 0.0:
                # J = J_s + (1 − ω)·c·R ≥ J_s everywhere and J(T_s) = J_s(T_s): a bound on min J_s
                # bounds min J, so the signed bracket (no braking evaluations) certifies T_s
                certificate = _bracket_certificate(signed, t_s, j, g_s)
            elif active == "optimum":
                certificate = _bracket_certificate(lambda x: (slope.objective(x), slope(x)[0]), t_s, j, g_s)
            return ExactSolution(t_s, j, e, active, certificate)
        a, b, gx, is_open = _slope_root(slope, t_s, g_s, t_max, guess)
    if is_open:
        gb, rb = slope(t_max)
        if gb <= 0.0:  # dJ/dT ≤ 0 up to T_max
            e = lm.signed_energy(D, t_max) + c * rb
            return ExactSolution(t_max, slope.objective(t_max), e, "t_max", {"gap_j": 0.0, "dJ_dT": gb})
        a, b, gx, _ = _slope_root(slope, a, slope(a)[0], t_max)  # pragma: no cover - not reached
    ga, ra = slope(a)
    gb, rb = slope(b)
    ja, jb = slope.objective(a), slope.objective(b)
    # convexity: J ≥ max of the tangents at a and b; their crossing bounds min J from below
    lb = _tangent_lower_bound(a, b, ja, jb, ga, gb)
    t_opt, j_opt, r_opt = (a, ja, ra) if ja <= jb else (b, jb, rb)
    e = lm.signed_energy(D, t_opt) + c * r_opt
    return ExactSolution(
        t_opt,
        j_opt,
        e,
        "optimum",
        {"gap_j": max(j_opt - lb, 0.0), "t_lower_s": a, "t_upper_s": b, "dJ_dT": gx},
    )


class ExactBackend:
    """Exact back-end (structure + Newton + a certificate); ~10–100 µs per solve in CPython."""

    name = "exact"

    def prepare(self, problem: MoveProblem, params: AxisParams) -> None:
        """Build the law's tables and, for case 2, the optimal speed ratio for ω and the braking
        optimum's start table (all cached)."""
        law_model(problem.law, params)
        if problem.case is Case.MIN_TIME_ENERGY:
            optimal_speed_ratio(problem.law, params, problem.omega)
            acc = params.energy_accounting
            if acc is not EnergyAccounting.SIGNED:
                c = 1.0 if acc is EnergyAccounting.POSITIVE else 2.0
                lm = law_model(problem.law, params)
                lm.guess_tables[problem.omega, c] = _braking_guess_table(
                    problem.law, params, problem.omega, c
                )

    def solve(self, problem: MoveProblem, params: AxisParams) -> PlanResult:
        t0 = time.perf_counter()
        sol = solve_exact(problem, params)
        elapsed = time.perf_counter() - t0
        energy = sol.energy_j
        if math.isnan(energy):  # minimum time: the energy of the answer, from the same law model
            D = abs(problem.distance_m)
            energy = law_model(problem.law, params).energy(D, sol.duration_s, params.energy_accounting)
        return finish(
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
