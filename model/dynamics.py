"""Inverse dynamics of the belt axis, eq. (1) of the paper.

    F = M_eq·ẍ + a1·sign(ẋ) + a2·ẋ + a3·atan(a4·ẋ),   M_eq = m + ((J_m + J_g)·i_r² + 2·J_p)/r²
    τ_m = F·r/i_r,    ω_m = ẋ·i_r/r,    P = F·ẋ = τ_m·ω_m

F is the belt (traction) force on the cart [N]; belt elasticity is neglected; the friction term is
:mod:`axisflow.model.friction`. All functions take scalars or numpy arrays.
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
    """Motor torque [N·m] that produces cart force F: τ_m = F·r/i_r."""
    return np.asarray(force_n, dtype=float) * params.r / params.i_r


def cart_force_from_torque(torque_nm: ArrayLike, params: AxisParams) -> np.ndarray:
    """Cart force [N] from motor torque: F = τ_m·i_r/r."""
    return np.asarray(torque_nm, dtype=float) * params.i_r / params.r


def motor_angle(position_m: ArrayLike, params: AxisParams) -> np.ndarray:
    """Motor shaft angle [rad] for cart position x: x·i_r/r."""
    return np.asarray(position_m, dtype=float) * params.i_r / params.r


def motor_speed(velocity_m_s: ArrayLike, params: AxisParams) -> np.ndarray:
    """Motor shaft speed [rad/s] for cart velocity ẋ: ẋ·i_r/r."""
    return np.asarray(velocity_m_s, dtype=float) * params.i_r / params.r


def mechanical_power(velocity_m_s: ArrayLike, acceleration_m_s2: ArrayLike, params: AxisParams) -> np.ndarray:
    """Mechanical power delivered to the cart [W]: P = F·ẋ."""
    v = np.asarray(velocity_m_s, dtype=float)
    return cart_force(v, acceleration_m_s2, params) * v
