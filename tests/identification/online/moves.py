"""Live samples made in closed form for the adaptation tests: an axis running rest-to-rest poly5 moves
between random way points, its motor torque eq. (1) of known parameters (plus white noise), sampled
at 1 kHz as a drive reports it (motor angle [rad], motor torque [N·m], stamps [ns])."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from axisflow.identification.fit import FrictionValues
from axisflow.model import AxisParams, Move, default_params, polynomial_law

NOMINAL = default_params()
T0_NS = 1_767_225_600_000_000_000
RATE_HZ = 1000.0


@dataclass(frozen=True)
class Samples:
    stamp_ns: np.ndarray
    angle_rad: np.ndarray
    torque_nm: np.ndarray

    def part(self, start_s: float, end_s: float) -> Samples:
        t = (self.stamp_ns - self.stamp_ns[0]) * 1e-9
        keep = (t >= start_s) & (t < end_s)
        return Samples(self.stamp_ns[keep], self.angle_rad[keep], self.torque_nm[keep])

    def then(self, other: Samples) -> Samples:
        """These samples, then ``other``'s (whose stamps must follow)."""
        return Samples(
            np.concatenate([self.stamp_ns, other.stamp_ns]),
            np.concatenate([self.angle_rad, other.angle_rad]),
            np.concatenate([self.torque_nm, other.torque_nm]),
        )


def truth(
    params: AxisParams = NOMINAL, coulomb: float = 1.0, viscous: float = 1.0, mass: float = 1.0
) -> FrictionValues:
    """``params``'s eq. (1) with a1 and a3 scaled by ``coulomb``, a2 by ``viscous``, M_eq by ``mass``."""
    return FrictionValues(
        params.M_eq * mass, params.a1 * coulomb, params.a2 * viscous, params.a3 * coulomb, params.a4
    )


def moves(
    values: FrictionValues,
    seconds: float,
    seed: int = 0,
    noise_nm: float = 0.004,
    speed_m_s: float = 0.6,
    start_ns: int = T0_NS,
    low_m: float = 0.05,
    high_m: float = 0.75,
) -> Samples:
    """``seconds`` of back-to-back poly5 moves between way points uniform in [low, high] (each at an
    average speed of ``speed_m_s``, so peak 1.875×), the torque of ``values`` plus white noise."""
    rng = np.random.default_rng(seed)
    t_all, x_all, v_all, a_all = [], [], [], []
    x0, t0 = 0.4, 0.0
    law = polynomial_law("poly5")
    while t0 < seconds:
        x1 = float(rng.uniform(low_m, high_m))
        if abs(x1 - x0) < 0.05:
            continue
        duration = abs(x1 - x0) / speed_m_s
        t = np.arange(0.0, duration, 1.0 / RATE_HZ)
        s = Move(x0, x1, duration, law).sample(t)
        t_all.append(t0 + t)
        x_all.append(s.position_m)
        v_all.append(s.velocity_m_s)
        a_all.append(s.acceleration_m_s2)
        x0, t0 = x1, t0 + t.size / RATE_HZ
    t, x, v, a = (np.concatenate(c) for c in (t_all, x_all, v_all, a_all))
    keep = t < seconds
    t, x, v, a = t[keep], x[keep], v[keep], a[keep]
    k = NOMINAL.r / NOMINAL.i_r
    torque = values.force_n(v, a) * k + rng.normal(0.0, noise_nm, t.size)
    stamps = start_ns + np.rint(t * 1e9).astype(np.int64)
    return Samples(stamps, x / k, torque)


def at_rest(seconds: float, start_ns: int = T0_NS, x_m: float = 0.4) -> Samples:
    """An axis holding still (zero torque but noise)."""
    n = round(seconds * RATE_HZ)
    stamps = start_ns + np.arange(n, dtype=np.int64) * 1_000_000
    k = NOMINAL.r / NOMINAL.i_r
    return Samples(stamps, np.full(n, x_m / k), np.random.default_rng(1).normal(0.0, 0.004, n))
