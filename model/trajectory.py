"""A sampled rest-to-rest trajectory: knots (t_k, x_k, ẋ_k, ẍ_k) joined by quintic Hermite pieces.

A move that no polynomial law describes (an identification excitation, a path from another planner)
is given as knots at strictly increasing times t_0 = 0 < t_1 < … < t_n = T with position, velocity and
acceleration at each. Between two knots the motion is the unique quintic that matches all six values
(C² everywhere): with h = t_{k+1} − t_k, s = (t − t_k)/h ∈ [0, 1] and Δ = x_{k+1} − x_k,

    x(s) = Σ c_j·s^j,   c0 = x_k,  c1 = h·ẋ_k,  c2 = h²·ẍ_k/2,
    c3 = 10Δ − h(6ẋ_k + 4ẋ_{k+1}) − h²(1.5ẍ_k − 0.5ẍ_{k+1}),
    c4 = −15Δ + h(8ẋ_k + 7ẋ_{k+1}) + h²(1.5ẍ_k − ẍ_{k+1}),
    c5 = 6Δ − 3h(ẋ_k + ẋ_{k+1}) − h²(0.5ẍ_k − 0.5ẍ_{k+1}),

and ẋ = x'(s)/h, ẍ = x''(s)/h², x⃛ = x'''(s)/h³. Knots 1 ms apart at the execution ticks are executed
exactly. The trajectory must start and end at rest (ẋ_0 = ẋ_n = 0), so it queues after any move like a
polynomial law; outside [0, T] the cart rests at x_0 or x_n.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .errors import MoveError
from .motion_laws import MAX_MOVE_DURATION_S, ArrayLike, MoveSamples

MAX_KNOTS = 3_600_001
"""the most knots a trajectory may have: one hour at 1 kHz"""


@dataclass(frozen=True, eq=False)
class SampledTrajectory:
    """A rest-to-rest trajectory through knots (see the module docstring); arrays of equal length."""

    t_s: np.ndarray
    position_m: np.ndarray
    velocity_m_s: np.ndarray
    acceleration_m_s2: np.ndarray
    from_rest: bool = True
    """whether the trajectory must start at rest (every move does; a quick stop starts in motion)"""
    _coefficients: np.ndarray = field(init=False, repr=False)
    """(n − 1, 6) quintic coefficients per piece, ascending powers of s"""

    def __post_init__(self) -> None:
        arrays = {}
        for name in ("t_s", "position_m", "velocity_m_s", "acceleration_m_s2"):
            a = np.ascontiguousarray(getattr(self, name), dtype=float)
            if a.ndim != 1:
                raise MoveError(f"trajectory {name} must be one-dimensional, got shape {a.shape}")
            if not np.all(np.isfinite(a)):
                k = int(np.flatnonzero(~np.isfinite(a))[0])
                raise MoveError(f"trajectory {name}[{k}] = {a[k]} is not finite")
            arrays[name] = a
            object.__setattr__(self, name, a)
        n = arrays["t_s"].size
        if not 2 <= n <= MAX_KNOTS:
            raise MoveError(f"a trajectory needs 2 to {MAX_KNOTS} knots, got {n}")
        if any(a.size != n for a in arrays.values()):
            sizes = ", ".join(f"{k} {a.size}" for k, a in arrays.items())
            raise MoveError(f"trajectory arrays differ in length: {sizes}")
        t = arrays["t_s"]
        if t[0] != 0.0:
            raise MoveError(f"trajectory t_s[0] = {t[0]} s must be 0 s (times count from the move's start)")
        steps = np.diff(t)
        if np.any(steps <= 0.0):
            k = int(np.flatnonzero(steps <= 0.0)[0])
            raise MoveError(
                f"trajectory times must increase: t_s[{k + 1}] = {t[k + 1]} s <= t_s[{k}] = {t[k]} s"
            )
        if t[-1] > MAX_MOVE_DURATION_S:
            raise MoveError(
                f"trajectory duration {t[-1]} s exceeds the longest move, {MAX_MOVE_DURATION_S:g} s"
            )
        v = arrays["velocity_m_s"]
        if (self.from_rest and v[0] != 0.0) or v[-1] != 0.0:
            raise MoveError(
                f"a trajectory starts and ends at rest: velocity_m_s[0] = {v[0]} m/s, "
                f"velocity_m_s[-1] = {v[-1]} m/s (both must be 0 m/s)"
            )
        object.__setattr__(self, "_coefficients", _quintic_coefficients(steps, arrays))

    @property
    def duration_s(self) -> float:
        return float(self.t_s[-1])

    @property
    def x0_m(self) -> float:
        return float(self.position_m[0])

    @property
    def x1_m(self) -> float:
        return float(self.position_m[-1])

    @property
    def distance_m(self) -> float:
        return self.x1_m - self.x0_m

    def sample(self, t_s: ArrayLike) -> MoveSamples:
        """Position, velocity, acceleration and jerk at times ``t_s`` [s] after the start (rest
        outside [0, T])."""
        t = np.asarray(t_s, dtype=float)
        knots = self.t_s
        k = np.clip(np.searchsorted(knots, t, side="right") - 1, 0, knots.size - 2)
        h = knots[k + 1] - knots[k]
        s = np.clip((t - knots[k]) / h, 0.0, 1.0)
        c = self._coefficients[k]
        c0, c1, c2, c3, c4, c5 = np.moveaxis(c, -1, 0)
        pos = c0 + s * (c1 + s * (c2 + s * (c3 + s * (c4 + s * c5))))
        vel = (c1 + s * (2 * c2 + s * (3 * c3 + s * (4 * c4 + s * 5 * c5)))) / h
        acc = (2 * c2 + s * (6 * c3 + s * (12 * c4 + s * 20 * c5))) / h**2
        jerk = (6 * c3 + s * (24 * c4 + s * 60 * c5)) / h**3
        inside = (t >= 0.0) & (t <= self.duration_s)
        # from the end on, the last knot itself: the last piece's sum at s = 1 may miss it by an ulp,
        # and a path that ends on the stroke's end would then leave the stroke
        pos = np.where(t >= self.duration_s, self.position_m[-1], pos)
        return MoveSamples(
            t, pos, np.where(inside, vel, 0.0), np.where(inside, acc, 0.0), np.where(inside, jerk, 0.0)
        )


def _quintic_coefficients(h: np.ndarray, knots: dict[str, np.ndarray]) -> np.ndarray:
    x, v, a = knots["position_m"], knots["velocity_m_s"], knots["acceleration_m_s2"]
    d = x[1:] - x[:-1]
    v0, v1, a0, a1 = v[:-1] * h, v[1:] * h, a[:-1] * h * h, a[1:] * h * h
    return np.column_stack(
        [
            x[:-1],
            v0,
            0.5 * a0,
            10 * d - 6 * v0 - 4 * v1 - 1.5 * a0 + 0.5 * a1,
            -15 * d + 8 * v0 + 7 * v1 + 1.5 * a0 - a1,
            6 * d - 3 * v0 - 3 * v1 - 0.5 * a0 + 0.5 * a1,
        ]
    )
