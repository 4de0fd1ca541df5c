"""A symmetric polynomial law and an axis, prepared once for the exact solver.

A move of length D = |x1 − x0| > 0 along a law s(u), u = t/T ∈ [0, 1], in time T has, in the frame
where it runs forward, velocity v = β·s'(u) with β = D/T and acceleration (D/T²)·s''(u). The laws are
rest-to-rest and symmetric, s'(1 − u) = s'(u) and s''(1 − u) = −s''(u), so every integral over the
move is twice an integral over [0, 1/2] and the accelerating half mirrors the braking half.

:class:`LawModel` holds what the solver's scalar loops and quadratures read: the coefficients of
s', s'', s''', s'''' (highest power first, for Horner's rule), the axis scalars of eq. (1)
(M = M_eq, the forward law φ(v) = a1 + a2·v + a3·atan(a4·v) of the move's direction, F_max,
v_max), the argmax of s'' on [0, 1/2], I2 = ∫₀¹ s'² du, and two fixed
quadratures. It is immutable, and cached per (law, axis) by :func:`law_model` (the parameters are
frozen and hashable; a law is one shared object per name).
"""

from __future__ import annotations

import dataclasses
import itertools
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ...model import AxisParams, ForwardLaw, PolynomialLaw
from ..errors import InfeasibleMoveError

NEWTON_MAX_STEPS = 60
"""the step cap of every safeguarded Newton, secant or bisection loop of the exact solver"""


def horner(coefficients: tuple[float, ...], u: float) -> float:
    """The polynomial with ``coefficients`` (highest power first) at u, by Horner's rule."""
    r = 0.0
    for a in coefficients:
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


def _coefficient_columns(*polys: np.ndarray) -> np.ndarray:
    """Polynomials (lowest power first) as the columns of one zero-padded matrix."""
    out = np.zeros((max(p.size for p in polys), len(polys)))
    for k, p in enumerate(polys):
        out[: p.size, k] = p
    return out


@dataclass(frozen=True, eq=False)
class LawModel:
    """A symmetric polynomial law and an axis, prepared for the exact solver (scalars and nodes)."""

    law: PolynomialLaw
    M: float
    """M_eq [kg]"""
    a1: float
    a2: float
    a3: float
    a4: float
    """the forward law of the move's direction (c_s, b_s, a3, a4 of :class:`~axisflow.model.ForwardLaw`,
    from :func:`~axisflow.model.params.forward_axis`): a1 < 0 where a load helps the move; all four
    signs of φ flipped in the braking side's model (:meth:`LawModel.negated`)"""
    f_max_n: float
    """the cart force limit F_max = tau_max·i_r/r [N]"""
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
    """graded Gauss–Legendre on [0, 1/2] and s' at its nodes (weights doubled for the symmetric half)"""
    s12: np.ndarray
    """(n, 2): s' and s'' coefficients, lowest power first (columns), for vectorised evaluation"""
    forward: ForwardLaw
    """φ as the model's record (a1…a4 above as c, b, a3, a4), for the vectorised quadratures"""
    rest_load: float = 0.0
    """the force along the motion at rest, the Coulomb sign 0 (s·f0 [N]): what the axis needs at a
    law's ends where they accelerate (poly3), and the braking side's friction at rest"""

    @classmethod
    def build(cls, law: PolynomialLaw, params: AxisParams) -> LawModel:
        """Prepare ``law`` for the axis ``params``; refuses an axis that cannot move and a law that
        is not symmetric."""
        c = params.a1 + params.f0  # the forward axis's φ(0⁺) (forward_axis)
        if params.f_max <= c:
            # F(u, T) → a1 as T → ∞: no duration makes the torque peak meet the limit
            raise InfeasibleMoveError(
                f"the motor torque limit tau_max = {params.tau_max} N·m gives a cart force of at most "
                f"F_max = {params.f_max:.6g} N, not above the friction at the start of the move "
                f"a1 + f0 = {c:.6g} N: the axis cannot move"
            )
        if params.f_max <= abs(params.f0):
            raise InfeasibleMoveError(
                f"the cart force limit F_max = {params.f_max:.6g} N is not above the constant load "
                f"|f0| = {abs(params.f0):.6g} N: the axis cannot hold itself"
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
            a1=c,
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
            s12=_coefficient_columns(d[0], d[1]),
            forward=ForwardLaw(c, params.a2, params.a3, params.a4),
            rest_load=params.f0,
        )

    def braking_side(self) -> LawModel:
        """The braking half's model, read from the move's end: F(u) of it is A·s'' − φ_b(β·s') with
        φ_b = rest_load + a2·v + a3·atan(a4·v), φ without the Coulomb friction's help (which the
        samples at rest, the end of a poly3 move, do not have): never below the true braking force
        (:mod:`.torque_limit`)."""
        brake = ForwardLaw(-self.rest_load, -self.a2, -self.a3, self.a4)
        return dataclasses.replace(
            self, a1=brake.c, a2=brake.b, a3=brake.a3, forward=brake, rest_load=-self.rest_load
        )

    @property
    def braking_can_bind(self) -> bool:
        """Whether the braking half can need more force than the driving half: the braking side's φ_b
        exceeds −φ only by c + rest_load, so only where that is < 0 (a load helps the move)."""
        return self.a1 + self.rest_load < 0.0


@lru_cache(maxsize=256)
def law_model(law: PolynomialLaw, params: AxisParams) -> LawModel:
    """The prepared law for an axis (cached: parameters are frozen and hashable)."""
    return LawModel.build(law, params)
