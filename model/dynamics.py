"""Inverse dynamics of the axis, eq. (1) of the paper with the terms beside it.

    F = M_eq·ẍ + F_c(ẋ),   F_c = f0 + a1·sign(ẋ) + da1·|sign ẋ| + a2·ẋ + da2·|ẋ| + a3·atan(a4·ẋ)
    τ_m = k·F,    ω_m = ẋ/k,    P = F·ẋ = τ_m·ω_m

F is the traction force on the cart [N] (belt elasticity neglected); the friction law is
:mod:`axisflow.model.friction`; k [m/rad] and M_eq come from the transmission
(:mod:`axisflow.model.transmission`; a belt: k = r/i_r, M_eq = m + ((J_m + J_g)·i_r² + 2·J_p)/r²).
All functions take scalars or numpy arrays.
"""

from __future__ import annotations

import numpy as np

from .friction import friction_force
from .params import AxisParams

ArrayLike = float | np.ndarray


def cart_force(velocity_m_s: ArrayLike, acceleration_m_s2: ArrayLike, params: AxisParams) -> np.ndarray:
    """Belt force on the cart [N] by eq. (1)."""
    a = np.asarray(acceleration_m_s2, dtype=float)
    return params.M_eq * a + friction_force(velocity_m_s, params)


def motor_torque(force_n: ArrayLike, params: AxisParams) -> np.ndarray:
    """Motor torque [N·m] that produces cart force F: τ_m = k·F (a belt: F·r/i_r)."""
    return params.transmission.motor_torque(force_n)


def cart_force_from_torque(torque_nm: ArrayLike, params: AxisParams) -> np.ndarray:
    """Cart force [N] from motor torque: F = τ_m/k (a belt: τ_m·i_r/r)."""
    return params.transmission.carriage_force(torque_nm)


def motor_angle(position_m: ArrayLike, params: AxisParams) -> np.ndarray:
    """Motor shaft angle [rad] for cart position x: x/k (a belt: x·i_r/r)."""
    return params.transmission.motor_angle(position_m)


def motor_speed(velocity_m_s: ArrayLike, params: AxisParams) -> np.ndarray:
    """Motor shaft speed [rad/s] for cart velocity ẋ: ẋ/k (a belt: ẋ·i_r/r)."""
    return params.transmission.motor_speed(velocity_m_s)


def mechanical_power(velocity_m_s: ArrayLike, acceleration_m_s2: ArrayLike, params: AxisParams) -> np.ndarray:
    """Mechanical power delivered to the cart [W]: P = F·ẋ."""
    v = np.asarray(velocity_m_s, dtype=float)
    return cart_force(v, acceleration_m_s2, params) * v
