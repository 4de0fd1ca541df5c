"""The simulated axis's mechanics: what moves when the motor pushes, integrated a few kHz.

Two models, both advanced one 1 ms tick at a time with ``substeps`` semi-implicit Euler steps and a
constant motor force F [N] (the motor torque seen at the cart through the transmission, τ/k) over
the tick:

* :class:`RigidAxis` — eq. (1) of the paper: M_eq·ẍ = F − F_c(ẋ), F_c the friction law of
  :mod:`axisflow.model.friction` with its terms (f0, da1, da2). Friction is Karnopp-style at rest:
  the cart sticks while −(a1 − da1) ≤ F − f0 ≤ a1 + da1, and the velocity is clamped to 0 when it
  would change sign within a step.
* :class:`BeltAxis` — the same axis with an elastic belt between the drive pulley and the cart: the
  rotating parts (rotor, gearbox, pulleys: M_r = M_eq − m, referred to the belt) and the cart (m) are
  two masses joined by a spring-damper,

      M_r·ẍ_m = F − F_b,    m·ẍ_c = F_b − F_c(ẋ_c),    F_b = k(x_c)·(x_m − x_c) + c·(ẋ_m − ẋ_c),

  k from :meth:`~axisflow.acquisition.drives.plant.BeltConfig.stiffness_n_m` (evaluated once per
  tick), friction acting on the cart (Karnopp as above, with the belt force in place of F). The motor
  encoder sees x_m; the cart lags it by the belt's stretch. At low frequencies the two masses move
  together and eq. (1) holds with M_eq = M_r + m.

The stroke ends at 0 and L are hard stops for the cart (position clamped, velocity zeroed).

Both loops step the cart with :func:`cart_velocity`, which inlines the friction law for speed (the
integrator runs ~4000 steps per second of drive time in pure Python, where numpy on scalars costs
several times more); tests/acquisition/drives/test_mechanics.py holds it, through both loops, to the
model's law.
"""

from __future__ import annotations

import math

from ...model import EXECUTION_PERIOD_S, AxisParams
from .plant import BeltConfig


def cart_velocity(
    v: float,
    force_n: float,
    mass_kg: float,
    dt_s: float,
    f0: float,
    up: float,
    down: float,
    viscous_up: float,
    viscous_down: float,
    a3: float,
    a4: float,
) -> float:
    """The cart's velocity [m/s] after one step of ``dt_s`` from ``v`` under the force ``force_n`` [N]
    (the motor's, or the belt's pull), with friction: the law of :mod:`axisflow.model.friction` inlined
    (module docstring), its parameters per direction (``up`` = a1 + da1 and ``viscous_up`` = a2 + da2
    towards +x, ``down`` = a1 − da1 and ``viscous_down`` = a2 − da2 towards −x). Karnopp at rest: the
    cart stays at 0 while −down ≤ F − f0 ≤ up; a step that would reverse the motion ends at 0."""
    if v == 0.0:
        net = force_n - f0
        if -down <= net <= up:
            return 0.0  # static friction holds the cart
        return ((net - up) if net > 0.0 else (net + down)) / mass_kg * dt_s
    if v > 0.0:
        friction = f0 + up + viscous_up * v + a3 * math.atan(a4 * v)
    else:
        friction = f0 - down + viscous_down * v + a3 * math.atan(a4 * v)
    v_next = v + (force_n - friction) / mass_kg * dt_s
    return 0.0 if v_next * v < 0.0 else v_next


class RigidAxis:
    """eq. (1), rigid (see the module docstring); ``x``, ``v``: the cart's position [m] and velocity [m/s]."""

    def __init__(self, axis: AxisParams, substeps: int, position_m: float) -> None:
        self.axis = axis
        self.x = position_m
        self.v = 0.0
        self._M = axis.M_eq
        self._substeps = substeps
        self._dt = EXECUTION_PERIOD_S / substeps

    @property
    def motor_x(self) -> float:
        """The pulley's position in cart metres: the cart's (the belt does not stretch)."""
        return self.x

    @property
    def motor_v(self) -> float:
        return self.v

    def set_state(self, position_m: float, velocity_m_s: float) -> None:
        self.x, self.v = position_m, velocity_m_s

    def advance(
        self,
        force_n: float,
        a1: float,
        a2: float,
        a3: float,
        a4: float,
        f0: float = 0.0,
        da1: float = 0.0,
        da2: float = 0.0,
    ) -> None:
        """One tick under the motor force ``force_n`` [N] with the friction of this tick (the law's
        parameters, :mod:`axisflow.model.friction`)."""
        x, v, dt, M, L = self.x, self.v, self._dt, self._M, self.axis.L
        up, down = a1 + da1, a1 - da1  # Coulomb friction towards +x and towards -x
        viscous_up, viscous_down = a2 + da2, a2 - da2
        for _ in range(self._substeps):
            v = cart_velocity(v, force_n, M, dt, f0, up, down, viscous_up, viscous_down, a3, a4)
            if v == 0.0:
                continue  # at rest: static friction holds the cart, or the motion just stopped
            x += v * dt
            if x < 0.0:
                x, v = 0.0, 0.0
            elif x > L:
                x, v = L, 0.0
        self.x, self.v = x, v


class BeltAxis:
    """The two-mass axis with an elastic belt (see the module docstring). ``x``, ``v``: the cart;
    ``motor_x``, ``motor_v``: the drive pulley's rim (motor side, in cart metres)."""

    def __init__(self, axis: AxisParams, belt: BeltConfig, substeps: int, position_m: float) -> None:
        self.axis = axis
        self.belt = belt
        self.x = self.motor_x = position_m
        self.v = self.motor_v = 0.0
        self.m = axis.m
        self.m_rotating = axis.M_eq - axis.m
        m_reduced = self.m * self.m_rotating / (self.m + self.m_rotating)
        k_mid = belt.stiffness_n_m(0.5 * axis.L, axis.L)
        self.damping_n_s_m = 2.0 * belt.damping_ratio * math.sqrt(k_mid * m_reduced)
        self._near = belt.end_span_m
        self._far = 2.0 * axis.L + 3.0 * belt.end_span_m
        self._substeps = substeps
        self._dt = EXECUTION_PERIOD_S / substeps

    def set_state(self, position_m: float, velocity_m_s: float) -> None:
        """Both masses at ``position_m`` moving at ``velocity_m_s``, the belt unstretched."""
        self.x = self.motor_x = position_m
        self.v = self.motor_v = velocity_m_s

    def stretch_m(self) -> float:
        """x_m − x_c: how far the motor side leads the cart [m]."""
        return self.motor_x - self.x

    def advance(
        self,
        force_n: float,
        a1: float,
        a2: float,
        a3: float,
        a4: float,
        f0: float = 0.0,
        da1: float = 0.0,
        da2: float = 0.0,
    ) -> None:
        """One tick under the motor force ``force_n`` [N] with the cart's friction of this tick."""
        x, v, xm, vm = self.x, self.v, self.motor_x, self.motor_v
        dt, m, m_r, c, L = self._dt, self.m, self.m_rotating, self.damping_n_s_m, self.axis.L
        k = self.belt.spring_rate_n * (1.0 / (x + self._near) + 1.0 / (self._far - x))
        up, down = a1 + da1, a1 - da1  # Coulomb friction towards +x and towards -x
        viscous_up, viscous_down = a2 + da2, a2 - da2
        for _ in range(self._substeps):
            belt = k * (xm - x) + c * (vm - v)
            vm += (force_n - belt) / m_r * dt
            xm += vm * dt
            v = cart_velocity(v, belt, m, dt, f0, up, down, viscous_up, viscous_down, a3, a4)
            if v == 0.0:
                continue  # at rest: static friction holds the cart, or the motion just stopped
            x += v * dt
            if x < 0.0:
                x, v = 0.0, 0.0
            elif x > L:
                x, v = L, 0.0
        self.x, self.v, self.motor_x, self.motor_v = x, v, xm, vm
