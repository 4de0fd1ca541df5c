"""The friction law of the axis, written once: eq. (1)'s terms and the terms beside them.

    F_c(ẋ) = f0 + a1·sign(ẋ) + da1·|sign(ẋ)| + a2·ẋ + da2·|ẋ| + a3·atan(a4·ẋ)

with sign(0) = 0, so that at rest F_c(0) = f0. The terms (:mod:`.terms`, each off when its values are
zero):

* ``coulomb`` a1 [N] and ``viscous`` a2 [N·s/m], the paper's;
* ``offset`` f0 [N]: a constant force **along +x that the motor must supply**, moving or at rest (an
  amplifier's current offset, a cable chain's pull, gravity). Gravity on an axis whose +x points up
  a fixed incline at θ above the horizontal is f0 = m_g·g·sin θ, m_g the mass that rises with the
  carriage (the carriage and its payload, not the rotating parts); an axis whose +x points downhill
  has f0 = −m_g·g·sin θ;
* ``asymmetry`` da1 [N], da2 [N·s/m]: Coulomb a1 + da1 and viscous a2 + da2 while ẋ > 0, a1 − da1
  and a2 − da2 while ẋ < 0 (each ≥ 0);
* ``atan`` a3 [N], a4 [s/m]: the paper's low-speed term.

While the axis moves, f0 and da1 both add a constant per direction: +(f0 + da1) moving towards +x and
(f0 + da1) as well moving towards −x, against −a1 for Coulomb. Motion data alone therefore tell only
their sum apart from a1; **f0 and da1 cannot both be fitted**: one must be given (gravity known from
the incline, say) for the other to mean anything (identification refuses to fit both).

**The forward law per direction.** A move in direction s = ±1 sees, along its motion (v = |ẋ| ≥ 0),

    φ_s(v) = c_s + b_s·v + a3·atan(a4·v),   c_s = a1 + s·da1 + s·f0,   b_s = a2 + s·da2,

the force the motor spends on friction and load while the carriage moves forward in the move's own
frame (:meth:`FrictionLaw.forward`, a :class:`ForwardLaw`). c_s < 0 is a load that helps the move
(gravity on a downhill move): the planner then checks braking as well as driving (docs/planner.md).

Every place of axisflow that needs friction calls this module: :class:`FrictionLaw` and
:func:`friction_law` (the law of any parameter record), :func:`friction_force` (F_c at velocities),
:func:`forward_friction` and :class:`ForwardLaw` (the planner's form, with slope and curvature for
Newton steps), :func:`friction_regressors` (the parameter Jacobian), :func:`friction_expression`
(the law over any algebra: CasADi symbols for IPOPT and the SQP fit). Hot scalar loops (the simulated
plant's integrator, the exact solver's Horner evaluations) keep an inlined copy for speed; each says
so where it does, and a test checks that copy against this module.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .terms import LAW_PARAMETERS

ArrayLike = float | np.ndarray

FRICTION_PARAMETERS: tuple[str, ...] = ("a1", "a2", "a3", "a4", "f0", "da1", "da2")
"""the friction law's parameters, in the order of :func:`friction_regressors`' columns (the paper's
four first)"""
assert set(FRICTION_PARAMETERS) == set(LAW_PARAMETERS)


@dataclass(frozen=True)
class ForwardLaw:
    """φ(v) = c + b·v + a3·atan(a4·v) for v ≥ 0: the friction along a move in one direction (module
    docstring). ``c`` may be negative (a load that helps the move); b, a3, a4 are ≥ 0."""

    c: float
    """φ(0⁺) [N]: Coulomb friction of the direction plus the load along it"""
    b: float
    """viscous friction of the direction [N·s/m]"""
    a3: float
    """low-speed amplitude [N]"""
    a4: float
    """low-speed shape [s/m]"""

    def value(self, velocity_m_s: ArrayLike) -> np.ndarray:
        """φ(v) [N]."""
        v = np.asarray(velocity_m_s, dtype=float)
        return self.c + self.b * v + self.a3 * np.arctan(self.a4 * v)

    def slope(self, velocity_m_s: ArrayLike) -> np.ndarray:
        """φ'(v) [N·s/m] = b + a3·a4/(1 + (a4·v)²)."""
        z = self.a4 * np.asarray(velocity_m_s, dtype=float)
        return self.b + self.a3 * self.a4 / (1.0 + z * z)

    def curvature(self, velocity_m_s: ArrayLike) -> np.ndarray:
        """φ''(v) [N·s²/m²] = −2·a3·a4³·v/(1 + (a4·v)²)²."""
        z = self.a4 * np.asarray(velocity_m_s, dtype=float)
        q = 1.0 / (1.0 + z * z)
        return -2.0 * self.a3 * self.a4 * self.a4 * z * q * q

    @property
    def saturated_n(self) -> float:
        """c + a3·π/2 [N]: the dry part of φ at high speed (the viscous part aside)."""
        return self.c + (self.a3 * math.pi / 2.0 if self.a4 > 0.0 else 0.0)

    def negated(self) -> ForwardLaw:
        """−φ as a record of the same shape (b and a3 negative): the braking side's friction."""
        return ForwardLaw(-self.c, -self.b, -self.a3, self.a4)


@dataclass(frozen=True)
class FrictionLaw:
    """The friction law's values (module docstring); a term that is off has zero values."""

    a1: float = 0.0
    """Coulomb friction [N] (the mean of the two directions')"""
    a2: float = 0.0
    """viscous friction [N·s/m] (the mean of the two directions')"""
    a3: float = 0.0
    """low-speed friction amplitude [N]"""
    a4: float = 0.0
    """low-speed friction shape [s/m]"""
    f0: float = 0.0
    """constant force along +x the motor supplies [N]"""
    da1: float = 0.0
    """Coulomb asymmetry [N]: a1 + da1 towards +x, a1 − da1 towards −x"""
    da2: float = 0.0
    """viscous asymmetry [N·s/m]: a2 + da2 towards +x, a2 − da2 towards −x"""

    def forward(self, direction: float) -> ForwardLaw:
        """φ_s of a move in ``direction`` s (its sign: +1 towards +x, −1 towards −x)."""
        s = 1.0 if direction >= 0.0 else -1.0
        return ForwardLaw(self.a1 + s * (self.da1 + self.f0), self.a2 + s * self.da2, self.a3, self.a4)

    def force(self, velocity_m_s: ArrayLike) -> np.ndarray:
        """F_c(ẋ) [N] (sign(0) = 0: f0 at rest)."""
        return friction_force(velocity_m_s, self)

    @property
    def is_symmetric(self) -> bool:
        """Whether both directions see the same forward law (no offset, no asymmetry)."""
        return self.f0 == 0.0 and self.da1 == 0.0 and self.da2 == 0.0


def friction_law(params: Any) -> FrictionLaw:
    """The :class:`FrictionLaw` of any record with the law's parameters as attributes (an
    :class:`~axisflow.model.params.AxisParams`, a fit's values); a record of the paper's shape, a1…a4
    only, has the other terms off."""
    if isinstance(params, FrictionLaw):
        return params
    return FrictionLaw(
        params.a1,
        params.a2,
        params.a3,
        params.a4,
        getattr(params, "f0", 0.0),
        getattr(params, "da1", 0.0),
        getattr(params, "da2", 0.0),
    )


def friction_expression(
    velocity: Any,
    sign: Any,
    a1: Any,
    a2: Any,
    a3: Any,
    a4: Any,
    atan: Callable[[Any], Any],
    f0: Any = 0.0,
    da1: Any = 0.0,
    da2: Any = 0.0,
) -> Any:
    """f0 + (a1 + da1·sign)·sign + (a2 + da2·sign)·v + a3·atan(a4·v) over any algebra (floats, numpy
    arrays, CasADi symbols): the law of the module docstring, since sign² = |sign| and sign·v = |v|.

    ``sign`` is the Coulomb sign the caller has decided on (sign(ẋ), or ±1 for a move's direction);
    ``atan`` the arctangent of the algebra (``math.atan``, ``numpy.arctan``, ``casadi.atan``).
    """
    return f0 + (a1 + da1 * sign) * sign + (a2 + da2 * sign) * velocity + a3 * atan(a4 * velocity)


def friction_force(velocity_m_s: ArrayLike, params: Any) -> np.ndarray:
    """Friction force F_c [N] at cart velocity ẋ (module docstring; sign(0) = 0, so f0 at rest)."""
    law = friction_law(params)
    v = np.asarray(velocity_m_s, dtype=float)
    return friction_expression(
        v, np.sign(v), law.a1, law.a2, law.a3, law.a4, np.arctan, law.f0, law.da1, law.da2
    )


def forward_friction(velocity_m_s: ArrayLike, params: Any, direction: float = 1.0) -> np.ndarray:
    """φ_s(v) [N]: friction in the forward frame of a move in ``direction`` (v ≥ 0; the Coulomb
    term has the sign of the motion just after rest, which is what a planner needs at the ends of a
    rest-to-rest move and what IPOPT's nodes use)."""
    return friction_law(params).forward(direction).value(velocity_m_s)


def friction_slope(velocity_m_s: ArrayLike, params: Any) -> np.ndarray:
    """dF_c/dẋ [N·s/m] = a2 + da2·sign(ẋ) + a3·a4/(1 + (a4·ẋ)²) for ẋ ≠ 0 (the Coulomb step adds
    nothing there)."""
    law = friction_law(params)
    v = np.asarray(velocity_m_s, dtype=float)
    z = law.a4 * v
    return law.a2 + law.da2 * np.sign(v) + law.a3 * law.a4 / (1.0 + z * z)


def friction_curvature(velocity_m_s: ArrayLike, params: Any) -> np.ndarray:
    """d²F_c/dẋ² [N·s²/m²] = −2·a3·a4³·ẋ/(1 + (a4·ẋ)²)² for ẋ ≠ 0."""
    law = friction_law(params)
    z = law.a4 * np.asarray(velocity_m_s, dtype=float)
    q = 1.0 / (1.0 + z * z)
    return -2.0 * law.a3 * law.a4 * law.a4 * z * q * q


def friction_regressors(velocity_m_s: ArrayLike, params: Any) -> np.ndarray:
    """∂F_c/∂(a1, a2, a3, a4, f0, da1, da2) at each velocity: an (n, 7) array (columns in
    :data:`FRICTION_PARAMETERS` order): sign(ẋ), ẋ, atan(a4·ẋ), a3·ẋ/(1 + (a4·ẋ)²), 1, |sign ẋ|, |ẋ|.

    F_c is linear in all but a4, so this is also the Gauss–Newton Jacobian of a torque fit (times the
    transmission's k and with a minus sign for residuals measured − model). The columns of f0 and da1
    are equal wherever ẋ ≠ 0 (module docstring).
    """
    law = friction_law(params)
    v = np.atleast_1d(np.asarray(velocity_m_s, dtype=float))
    z = law.a4 * v
    s = np.sign(v)
    return np.column_stack(
        [s, v, np.arctan(z), law.a3 * v / (1.0 + z * z), np.ones_like(v), np.abs(s), np.abs(v)]
    )
