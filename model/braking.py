"""Braking to rest as fast as the axis can: the quick-stop profile.

From a speed v0 the cart stops fastest with the motor pulling back at its full force F_max while
friction helps: in the frame where the cart moves forward (v ≥ 0), in direction s,

    M_eq·v̇ = −(f·F_max + φ_s(v)),   φ_s(v) = c_s + b_s·v + a3·atan(a4·v)   (:mod:`.friction`)

A load that helps the motion (c_s < 0: gravity on a downhill run) brakes against the motor: a stop is
refused (:class:`MoveError`) where f·F_max does not exceed −c_s, since the cart would never come to
rest.

with f ≤ 1 the fraction of the force used (a drive keeps a margin: its true friction and inertia are
not the nominal ones). Nothing brakes harder within the torque limit, so f = 1 gives the physical
minimum stopping time and distance. The profile is integrated with classical Runge–Kutta at 1 ms
steps (the drive's ticks; the last step is shortened to end exactly at rest) and returned as a
:class:`~.trajectory.SampledTrajectory` whose knots carry position, velocity and acceleration, so a
drive executes it like any move. The velocity limit only helps: the speed falls from v0 ≤ v_max.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .deadline import Deadline
from .errors import MoveError
from .friction import forward_friction
from .params import AxisParams
from .sampling import EXECUTION_PERIOD_S
from .trajectory import SampledTrajectory

QUICK_STOP_FORCE = 0.9
"""the fraction of the force limit a quick stop brakes with: the bridge's own, and what a CiA 402 drive's
default quick-stop deceleration assumes (the rest is the drive's margin: the true friction and inertia
differ from the nominal ones the profile is computed with)"""
_MAX_STEPS = 1_000_000
"""the cap of the integration: 1000 s of braking at 1 ms steps"""
_DEADLINE_S = 10.0
"""the integration's wall-clock deadline [s] (a stop from v_max on the default axis: ~0.2 ms of work)"""
_DEADLINE_EVERY = 1024
"""steps between two looks at the clock"""


@dataclass(frozen=True)
class StopProfile:
    """A stop from ``speed_m_s`` at ``x0_m``: its trajectory, distance [m] and time [s]."""

    trajectory: SampledTrajectory
    distance_m: float
    time_s: float


def braking_acceleration(
    speed_m_s: float, params: AxisParams, force_fraction: float, direction: float = 1.0
) -> float:
    """v̇ [m/s²] of a cart moving forward at ``speed_m_s`` ≥ 0 in ``direction`` braked with f·F_max."""
    friction = float(forward_friction(speed_m_s, params, direction))
    return -(force_fraction * params.f_max + friction) / params.M_eq


def stop_profile(
    x0_m: float,
    v0_m_s: float,
    params: AxisParams,
    force_fraction: float = 1.0,
    deadline_s: float = _DEADLINE_S,
) -> StopProfile:
    """The fastest stop from position ``x0_m`` and velocity ``v0_m_s`` (either sign) with a fraction
    ``force_fraction`` ∈ [0, 1] of the motor's force (see the module docstring); 0 is a coast to rest
    on friction alone (a drive whose power stage is off). The integration is capped at 10⁶ steps
    (:class:`MoveError`) and ``deadline_s`` of wall time (:class:`~.deadline.DeadlineError`)."""
    if not 0.0 <= force_fraction <= 1.0:
        raise MoveError(f"braking force fraction = {force_fraction} must be in [0, 1]")
    if not (math.isfinite(x0_m) and math.isfinite(v0_m_s)):
        raise MoveError(f"stop from x = {x0_m} m, v = {v0_m_s} m/s: not finite")
    direction = 1.0 if v0_m_s >= 0.0 else -1.0
    v = abs(v0_m_s)
    law = params.forward(direction)
    if v > 0.0 and force_fraction * params.f_max + law.c <= 0.0:
        raise MoveError(
            f"a stop from {v0_m_s} m/s cannot end: {force_fraction:g}·F_max = "
            f"{force_fraction * params.f_max:.6g} N does not exceed the load {-law.c:.6g} N that drives the "
            "cart on (f0 along the motion beyond the friction)"
        )
    dt = EXECUTION_PERIOD_S
    ts, xs, vs = [0.0], [0.0], [v]
    accs: list[float] = []
    """v̇ at each knot but the last (the first stage of the step from it)"""

    def acc(speed: float) -> float:
        return braking_acceleration(speed, params, force_fraction, direction)

    def rk4(v: float, k1: float, h: float) -> tuple[float, float]:
        """(Δv, Δx) of one classical Runge–Kutta step of length h from speed v, where v̇ = k1."""
        k2 = acc(max(v + 0.5 * h * k1, 0.0))
        k3 = acc(max(v + 0.5 * h * k2, 0.0))
        k4 = acc(max(v + h * k3, 0.0))
        dv = h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
        dx = h / 6.0 * (v + 2 * (v + 0.5 * h * k1) + 2 * (v + 0.5 * h * k2) + (v + h * k3))
        return dv, dx

    deadline = Deadline(deadline_s, f"the stop from {v0_m_s} m/s")
    while vs[-1] > 0.0:
        if len(ts) % _DEADLINE_EVERY == 0:
            deadline.check("the integration to rest")
        if len(ts) > _MAX_STEPS:  # pragma: no cover - a stop from v_max takes well under a second
            raise MoveError(f"a stop from {v0_m_s} m/s does not end within {_MAX_STEPS} ms")
        v, x = vs[-1], xs[-1]
        k1 = acc(v)
        accs.append(k1)
        dv, dx = rk4(v, k1, dt)
        h = dt
        if v + dv <= 0.0:  # the last, shorter step: the one that ends exactly at rest (bisection)
            lo, hi = 0.0, dt
            for _ in range(60):
                h = 0.5 * (lo + hi)
                dv, dx = rk4(v, k1, h)
                lo, hi = (h, hi) if v + dv > 0.0 else (lo, h)
            h = hi
            dv, dx = -v, rk4(v, k1, h)[1]
        vs.append(max(v + dv, 0.0))
        xs.append(x + dx)
        ts.append(ts[-1] + h)
    t_s = np.array(ts)
    x_m = x0_m + direction * np.array(xs)
    v_m_s = direction * np.array(vs)
    a_m_s2 = np.array([*(direction * k for k in accs), 0.0])  # at rest the drive holds: no braking force
    if len(t_s) == 1:  # at rest already: a single tick of rest
        t_s, x_m, v_m_s, a_m_s2 = np.array([0.0, dt]), np.array([x0_m, x0_m]), np.zeros(2), np.zeros(2)
    path = SampledTrajectory(t_s, x_m, v_m_s, a_m_s2, from_rest=False)
    return StopProfile(path, float(xs[-1]), float(t_s[-1]))
