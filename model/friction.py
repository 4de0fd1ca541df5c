"""The friction law of eq. (1), written once, with the derivatives its users need.

    F_c(ẋ) = a1·sign(ẋ) + a2·ẋ + a3·atan(a4·ẋ)

a1 is Coulomb friction [N], a2 viscous friction [N·s/m], a3 [N] and a4 [s/m] the low-speed term
(Sect. 2 of the paper). Every other place of axisflow that needs friction calls one of these:

* :func:`friction_force` — F_c at cart velocities (numpy), the model's eq. (1) term;
* :func:`forward_friction` — φ(v) = a1 + a2·v + a3·atan(a4·v), the law in the frame where a move runs
  forward (v ≥ 0, the Coulomb sign closed at rest as sign(0⁺) = 1): the planner's form;
* :func:`friction_slope`, :func:`friction_curvature` — dF_c/dẋ and d²F_c/dẋ² away from ẋ = 0 (the
  exact solver's Newton steps);
* :func:`friction_regressors` — ∂F_c/∂(a1, a2, a3, a4), the parameter Jacobian (identification);
* :func:`friction_expression` — the law over any algebra that has the four operations, ``atan`` and
  a sign given by the caller: CasADi symbols (IPOPT, the SQP fit) use it with ``casadi.atan``.

Hot scalar loops (the simulated plant's integrator, the exact solver's Horner evaluations) keep an
inlined copy for speed; each says so where it does, and a test checks that copy against this module.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

import numpy as np

ArrayLike = float | np.ndarray

FRICTION_PARAMETERS: tuple[str, ...] = ("a1", "a2", "a3", "a4")
"""the friction law's parameters, in the order of :func:`friction_regressors`' columns"""


class FrictionParams(Protocol):
    """Anything that carries a1…a4 (an :class:`~axisflow.model.params.AxisParams`, a fit's iterate),
    read-only."""

    @property
    def a1(self) -> Any: ...
    @property
    def a2(self) -> Any: ...
    @property
    def a3(self) -> Any: ...
    @property
    def a4(self) -> Any: ...


def friction_expression(
    velocity: Any, sign: Any, a1: Any, a2: Any, a3: Any, a4: Any, atan: Callable[[Any], Any]
) -> Any:
    """a1·sign + a2·v + a3·atan(a4·v) over any algebra (floats, numpy arrays, CasADi symbols).

    ``sign`` is the Coulomb sign the caller has decided on (sign(ẋ), or +1 in the forward frame of a
    move); ``atan`` the arctangent of the algebra (``math.atan``, ``numpy.arctan``, ``casadi.atan``).
    """
    return a1 * sign + a2 * velocity + a3 * atan(a4 * velocity)


def friction_force(velocity_m_s: ArrayLike, params: FrictionParams) -> np.ndarray:
    """Friction force [N] at cart velocity ẋ: a1·sign(ẋ) + a2·ẋ + a3·atan(a4·ẋ) (sign(0) = 0)."""
    v = np.asarray(velocity_m_s, dtype=float)
    return friction_expression(v, np.sign(v), params.a1, params.a2, params.a3, params.a4, np.arctan)


def forward_friction(velocity_m_s: ArrayLike, params: FrictionParams) -> np.ndarray:
    """φ(v) [N] = a1 + a2·v + a3·atan(a4·v): friction in a move's forward frame (v ≥ 0).

    The Coulomb term has the sign of the motion just after rest (+1), which is what a planner
    needs at the ends of a rest-to-rest move and what IPOPT's nodes use.
    """
    v = np.asarray(velocity_m_s, dtype=float)
    return friction_expression(v, 1.0, params.a1, params.a2, params.a3, params.a4, np.arctan)


def friction_slope(velocity_m_s: ArrayLike, params: FrictionParams) -> np.ndarray:
    """dF_c/dẋ [N·s/m] = a2 + a3·a4/(1 + (a4·ẋ)²) for ẋ ≠ 0 (the Coulomb step adds nothing there)."""
    z = params.a4 * np.asarray(velocity_m_s, dtype=float)
    return params.a2 + params.a3 * params.a4 / (1.0 + z * z)


def friction_curvature(velocity_m_s: ArrayLike, params: FrictionParams) -> np.ndarray:
    """d²F_c/dẋ² [N·s²/m²] = −2·a3·a4³·ẋ/(1 + (a4·ẋ)²)² for ẋ ≠ 0."""
    v = np.asarray(velocity_m_s, dtype=float)
    z = params.a4 * v
    q = 1.0 / (1.0 + z * z)
    return -2.0 * params.a3 * params.a4 * params.a4 * z * q * q


def friction_regressors(velocity_m_s: ArrayLike, params: FrictionParams) -> np.ndarray:
    """∂F_c/∂(a1, a2, a3, a4) at each velocity: an (n, 4) array (columns in
    :data:`FRICTION_PARAMETERS` order): sign(ẋ), ẋ, atan(a4·ẋ), a3·ẋ/(1 + (a4·ẋ)²).

    F_c is linear in a1…a3 and nonlinear in a4 only, so this is also the Gauss–Newton Jacobian of a
    torque fit (times r/i_r and with a minus sign for residuals measured − model).
    """
    v = np.atleast_1d(np.asarray(velocity_m_s, dtype=float))
    z = params.a4 * v
    return np.column_stack([np.sign(v), v, np.arctan(z), params.a3 * v / (1.0 + z * z)])
