"""The torque limit: the shortest duration T_τ whose peak cart force meets F_max.

A move of length D along the law s(u), with y = 1/T and β = D·y, needs the cart force (eq. 1 in the
frame where it runs forward; the friction sign closed at the end points, as IPOPT's nodes do)

    F(u, y) = M·D·y²·s''(u) + φ(D·y·s'(u)),      φ(v) = a1 + a2·v + a3·atan(a4·v),  u ∈ [0, 1].

φ is the forward law of the move's direction (:func:`~axisflow.model.params.forward_axis`). With
a1…a4 ≥ 0, max_u F and max_u (−F) are both non-increasing in T (each braking term −F shrinks with T
wherever it is positive, because atan(z) ≥ z/(1 + z²)), so feasibility is monotone in T. The laws
are symmetric, so the braking peak −F(1 − u) = F(u) − 2φ is the driving peak minus twice the
friction and never binds: only max_u F(u, y) = F_max needs solving.

**A load that helps the move** (f_s = s·f0 < 0: gravity on a downhill move) lowers φ, and the braking
half can need more force than the driving half: where c + f_s < 0 (c = φ(0⁺); c < 0 itself where the
load outweighs friction). The braking force, read from the move's end, is bounded by
g(u, y) = M·D·y²·s''(u) − φ_b(D·y·s'(u)) with φ_b = f_s + b·v + a3·atan(a4·v), φ without the Coulomb
friction's help (the samples at rest, the end of a poly3 move, have none): the same function with
−φ_b (:meth:`LawModel.braking_side`), solved by the same Newton machinery
(:attr:`TorqueLimit.braking`). Feasibility stays monotone: where g ≥ −f_s, A·s'' ≥ φ_b − f_s, so
T·∂g/∂T = −2A·s'' + φ_b'·v ≤ −b·v − a3·(2·atan z − z/(1 + z²)) ≤ 0 (the constant cancels), and
g(0, y) ≥ −f_s with |f0| < F_max: a duration that meets the limit stays within it when lengthened.
T_τ is then the larger of the two roots. T_τ = 1/y solves the pair


    ∂F/∂u (u, y) = 0,    F(u, y) = F_max

by Newton's method in (u, y) (a 2×2 system, all derivatives analytic), or F(0, y) = F_max in y alone
when the peak sits on the boundary u = 0 (poly3 with a strong inertia term). The start comes from a
table of (y, u) over log D, built once per (law, axis) before the :class:`TorqueLimit` that holds it
(it only chooses the start; 2–4 Newton steps). A safeguarded scalar iteration (Newton on y, with the
peak found by a bracketed Newton in u) takes over if a step misbehaves.

The peak force is reported as F at the last Newton iterate plus the quadratic bound F_u²/(2|F_uu|)
on what the remaining step could add, so it never under-reports: the duration returned meets the
limit, and F > F_max at t_upper_s·(1 − 1e-11) with the same u proves that duration infeasible.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ...model import AxisParams, PolynomialLaw
from ...model.deadline import Deadline, iteration_cap
from .law_model import NEWTON_MAX_STEPS, LawModel, horner, law_model

BRACKET_REL = 1e-11
"""relative width of the proved case-1 bracket: t_lower_s = t_upper_s·(1 − BRACKET_REL)"""
_TABLE_NODES = 160
_PAIR_STEPS = 12
"""the cap of the Newton steps on the pair (u, y) (2–4 from the table's start)"""
_ROUNDING_STEPS = 48
"""the cap of the steps that move y to the feasible side of the limit after the Newton solve (one or
two ulps normally; each step doubles the last)"""


@dataclass(frozen=True)
class TorqueRootTable:
    """The torque root at log-spaced D ∈ [1e-7·L, 1.001·L]: log D, log y = −log T_τ and the peak's u."""

    log_d: tuple[float, ...]
    log_y: tuple[float, ...]
    u: tuple[float, ...]


@dataclass(frozen=True, eq=False)
class TorqueLimit:
    """The torque limit of a law on an axis: F(u, y) along the law, its peak and T_τ."""

    model: LawModel
    table: TorqueRootTable | None
    """start points of the Newton solve; None gives the analytic start (used to build the table)"""
    braking: TorqueLimit | None = None
    """the braking half's limit (−φ), where a load helps the move (c < 0); None where braking
    never binds (module docstring)"""

    @classmethod
    def build(cls, model: LawModel, stroke_m: float) -> TorqueLimit:
        """The torque limit with its start table over the stroke (solved from the analytic start),
        and the braking half's where c < 0."""
        braking = None
        if model.braking_can_bind:
            brake = model.braking_side()
            braking = cls(brake, cls(brake, None).root_table(stroke_m))
        return cls(model, cls(model, None).root_table(stroke_m), braking)

    def within(self, y: float, D: float) -> bool:
        """Whether the move of length D with y = 1/T meets the force limit on both halves (the
        peaks never under-report: :meth:`peak_force`)."""
        fmax = self.model.f_max_n
        if self.peak_force(y, D, self.model.u_acc_peak)[0] > fmax:
            return False
        return self.braking is None or self.braking.peak_force(y, D, self.model.u_acc_peak)[0] <= fmax

    def force_derivatives(self, u: float, y: float, D: float) -> tuple[float, float, float, float, float]:
        """F, ∂F/∂u, ∂²F/∂u², ∂F/∂y, ∂²F/∂u∂y at (u, y) for a move of length D (forward frame).

        With v = D·y·s', φ' = dφ/dv and φ'' = d²φ/dv²:
        F_u = M·D·y²·s''' + φ'·D·y·s'', F_uu = M·D·y²·s'''' + φ''·(D·y·s'')² + φ'·D·y·s''',
        F_y = 2·M·D·y·s'' + φ'·D·s', F_uy = 2·M·D·y·s''' + D·s''·(φ' + φ''·v).
        """
        m = self.model
        s1 = horner(m.c1, u)
        s2 = horner(m.c2, u)
        s3 = horner(m.c3, u)
        s4 = horner(m.c4, u)
        a3, a4 = m.a3, m.a4
        Dy = D * y
        v = Dy * s1
        # φ(v), φ'(v), φ''(v) of model/friction.py (ForwardLaw.value, .slope,
        # .curvature), inlined: this runs 10–30 times per solve, where numpy calls on scalars
        # would cost several times the whole evaluation (tests/planner/test_inlined_friction.py)
        z = a4 * v
        q = 1.0 / (1.0 + z * z)
        fp = m.a2 + a3 * a4 * q
        fpp = -2.0 * a3 * a4 * a4 * z * q * q
        MDy2 = m.M * D * y * y
        F = MDy2 * s2 + m.a1 + m.a2 * v + a3 * math.atan(z)
        Fu = MDy2 * s3 + fp * Dy * s2
        Fuu = MDy2 * s4 + fpp * (Dy * s2) ** 2 + fp * Dy * s3
        Fy = 2.0 * m.M * D * y * s2 + fp * D * s1
        Fuy = 2.0 * m.M * D * y * s3 + D * s2 * (fp + fpp * v)
        return F, Fu, Fuu, Fy, Fuy

    def peak_force(self, y: float, D: float, u0: float) -> tuple[float, float, float]:
        """max over u ∈ [0, 1/2] of F(u, y): (F_peak [N], ∂F/∂y there [N·s], u_peak).

        Safeguarded Newton on ∂F/∂u = 0 inside a sign bracket (∂F/∂u > 0 left, < 0 right; at
        u = 1/2, s'' = 0 and s''' < 0). When ∂F/∂u(0) < 0 the peak is the boundary u = 0. The value
        returned is F at the last iterate plus the bound F_u²/(2|F_uu|) on what the remaining step
        could add, so it never under-reports.
        """
        fd = self.force_derivatives
        F, Fu, Fuu, Fy, _ = fd(0.0, y, D)
        if Fu < 0.0:
            return F, Fy, 0.0
        lo, hi = 0.0, 0.5
        u = min(max(u0, 0.0), 0.5)
        for _ in range(NEWTON_MAX_STEPS):
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

    def duration(self, D: float, deadline: Deadline | None = None) -> tuple[float, float, float]:
        """T_τ [s]: the smallest T with max_u F(u, T) ≤ F_max (and the braking half's, where it can
        bind), as (t_upper_s, t_lower_s, u_peak).

        Newton's method on the pair ∂F/∂u = 0, F = F_max in (u, y) from the table. The peak meets the
        limit at t_upper_s and exceeds it at t_lower_s (a proof that t_lower_s is infeasible). Every
        loop is capped; ``deadline`` is checked between them (:class:`SolveLimitError` at either).
        """
        driving = self._duration(D, deadline)
        if self.braking is None:
            return driving
        braking = self.braking._duration(D, deadline)
        return braking if braking[0] > driving[0] else driving

    def _duration(self, D: float, deadline: Deadline | None) -> tuple[float, float, float]:
        """:meth:`duration` of this side alone."""
        fmax = self.model.f_max_n
        y, u = self._start(D)
        fd = self.force_derivatives
        for _ in range(_PAIR_STEPS):
            F, Fu, Fuu, Fy, Fuy = fd(u, y, D)
            G = F - fmax
            if u <= 0.0 and Fu <= 0.0:  # boundary peak (poly3): solve F(0, y) = F_max in y only
                du, dy = 0.0, -G / Fy
            elif Fuu < 0.0:
                det = Fuu * Fy - Fuy * Fu
                du = (Fuy * G - Fy * Fu) / det
                dy = (Fu * Fu - Fuu * G) / det
            else:
                y, u = self._scalar_root(D, y, u)
                break
            u = u + du
            if u < 0.0:
                u = 0.0
            elif u > 0.5:
                y, u = self._scalar_root(D, y, 0.25)
                break
            y += dy
            if abs(dy) <= 1e-15 * y and abs(du) <= 1e-9:
                break
        else:
            y, u = self._scalar_root(D, y, u)
        if deadline is not None:
            deadline.check("the torque limit's Newton solve")
        F, _, u = self.peak_force(y, D, u)
        for k in range(_ROUNDING_STEPS):  # rounding: step to the feasible side
            if fmax >= F:
                break
            y *= 1.0 - 4e-16 * 2.0**k
            F, _, u = self.peak_force(y, D, u)
        else:
            raise iteration_cap(f"the torque limit's rounding step (D = {D:.6g} m)", _ROUNDING_STEPS)
        if not (y > 0.0 and math.isfinite(y)):
            raise iteration_cap(f"the torque limit's Newton solve (D = {D:.6g} m, y = {y})", _PAIR_STEPS)
        t_up = 1.0 / y
        t_low = t_up * (1.0 - BRACKET_REL)
        if fd(u, 1.0 / t_low, D)[0] <= fmax:  # pragma: no cover - numerical guard
            t_low = t_up * (1.0 - 1e-8)
        return t_up, t_low, u

    def _scalar_root(self, D: float, y: float, u: float) -> tuple[float, float]:
        """(y, u_peak) with y = 1/T_τ by a safeguarded Newton on G(y) = max_u F(u, y) − F_max
        (G increasing in y), from the start (y, u)."""
        m = self.model
        fmax = m.f_max_n
        y_hi = math.sqrt(fmax / (m.M * D * horner(m.c2, m.u_acc_peak)))  # F(u_a, y_hi) ≥ F_max + a1
        for _ in range(_ROUNDING_STEPS):  # φ < 0 somewhere (a helping load, a braking side): widen
            if self.force_derivatives(m.u_acc_peak, y_hi, D)[0] > fmax:
                break
            y_hi *= 2.0
        y_lo = 0.0  # F(u, 0) = a1 < F_max

        y = min(y, y_hi)
        for _ in range(NEWTON_MAX_STEPS):
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

    def _start(self, D: float) -> tuple[float, float]:
        """(y, u) of the torque root interpolated from the table over log D (outside it, or without
        a table: the inertia-only estimate with the friction at v_max taken from F_max)."""
        table = self.table
        x = math.log(D)
        if table is None or not table.log_d[0] < x < table.log_d[-1]:
            m = self.model
            free = m.f_max_n - m.a1 - m.a3 * math.pi / 2.0 - m.a2 * m.v_max_m_s
            if free <= 0.0:
                free = 0.5 * (m.f_max_n - m.a1)
            return math.sqrt(free / (m.M * D * horner(m.c2, m.u_acc_peak))), m.u_acc_peak
        log_d, log_y, us = table.log_d, table.log_y, table.u
        k = bisect.bisect_right(log_d, x) - 1
        w = (x - log_d[k]) / (log_d[k + 1] - log_d[k])
        return math.exp(log_y[k] + w * (log_y[k + 1] - log_y[k])), us[k] + w * (us[k + 1] - us[k])

    def root_table(self, stroke_m: float, nodes: int = _TABLE_NODES) -> TorqueRootTable:
        """The torque root y(D) at ``nodes`` log-spaced D ∈ [1e-7·L, 1.001·L], each solved by
        :meth:`_scalar_root` from this limit's start."""
        ds = np.geomspace(1e-7 * stroke_m, 1.001 * stroke_m, nodes)
        log_y, us = [], []
        for D in ds:
            y, u = self._scalar_root(float(D), *self._start(float(D)))
            log_y.append(math.log(y))
            us.append(u)
        return TorqueRootTable(tuple(math.log(float(D)) for D in ds), tuple(log_y), tuple(us))


@lru_cache(maxsize=256)
def torque_limit(law: PolynomialLaw, params: AxisParams) -> TorqueLimit:
    """The torque limit of ``law`` on the axis, with its start table (cached; ~10 ms to build)."""
    return TorqueLimit.build(law_model(law, params), params.L)
