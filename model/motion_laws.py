"""Rest-to-rest polynomial motion laws poly3, poly5, poly7 (Sect. 2 of the paper).

A move from x0 to x1 in time T follows x(t) = x0 + d·s(u), u = t/T ∈ [0, 1], d = x1 − x0, where
the normalised shape s(u) is the unique polynomial of degree 3, 5 or 7 with s(0) = 0, s(1) = 1 and

* poly3: s'(0) = s'(1) = 0
* poly5: also s''(0) = s''(1) = 0
* poly7: also s'''(0) = s'''(1) = 0

Derivatives scale with T: ẋ = d/T·s'(u), ẍ = d/T²·s''(u), x⃛ = d/T³·s'''(u). So the peak velocity
is ``peak_velocity_factor``·|d|/T and the peak acceleration ``peak_acceleration_factor``·|d|/T².
Outside [0, T] the cart is at rest (at x0 before, at x1 after), which is what an executing drive does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np
from numpy.polynomial import polynomial as P

from .errors import MoveError

ArrayLike = float | np.ndarray


def _rest_to_rest_coefficients(degree: int) -> np.ndarray:
    """Coefficients (ascending powers) of s(u) with s(0)=0, s(1)=1 and the first (degree−1)/2
    derivatives zero at both ends; solved as a small linear system (exact for these sizes)."""
    k = (degree + 1) // 2  # conditions per end: value + (k − 1) derivatives
    rows, rhs = [], []
    for end, value in ((0.0, 0.0), (1.0, 1.0)):
        for order in range(k):
            row = np.zeros(degree + 1)
            for p in range(order, degree + 1):
                row[p] = math.perm(p, order) * end ** (p - order)
            rows.append(row)
            rhs.append(value if order == 0 else 0.0)
    coeffs = np.linalg.solve(np.array(rows), np.array(rhs))
    return np.round(coeffs, 9)  # the exact coefficients are integers


def _peak_abs(coeffs: np.ndarray) -> float:
    """max |p(u)| over u ∈ [0, 1] for a polynomial p, from its critical points and the ends."""
    crit = P.polyroots(P.polyder(coeffs)) if len(coeffs) > 2 else np.array([])
    crit = np.real(crit[np.abs(np.imag(crit)) < 1e-12])
    pts = np.concatenate([[0.0, 1.0], crit[(crit >= 0.0) & (crit <= 1.0)]])
    return float(np.max(np.abs(P.polyval(pts, coeffs))))


@dataclass(frozen=True, eq=False)
class PolynomialLaw:
    """A normalised rest-to-rest polynomial shape s(u) on u ∈ [0, 1]."""

    name: str
    degree: int
    coefficients: np.ndarray = field(repr=False)
    """s(u) coefficients, ascending powers of u"""
    derivatives: tuple[np.ndarray, ...] = field(repr=False)
    """coefficients of s', s'', s'''"""
    peak_velocity_factor: float
    """max |s'(u)|"""
    peak_acceleration_factor: float
    """max |s''(u)|"""
    peak_jerk_factor: float
    """max |s'''(u)|"""

    @classmethod
    def of_degree(cls, degree: int) -> PolynomialLaw:
        c = _rest_to_rest_coefficients(degree)
        d1 = P.polyder(c)
        d2 = P.polyder(d1)
        d3 = P.polyder(d2)
        return cls(
            name=f"poly{degree}",
            degree=degree,
            coefficients=c,
            derivatives=(d1, d2, d3),
            peak_velocity_factor=_peak_abs(d1),
            peak_acceleration_factor=_peak_abs(d2),
            peak_jerk_factor=_peak_abs(d3),
        )

    def shape(self, u: ArrayLike, order: int = 0) -> np.ndarray:
        """s^(order)(u) for u in [0, 1] (no clipping)."""
        c = self.coefficients if order == 0 else self.derivatives[order - 1]
        return P.polyval(np.asarray(u, dtype=float), c)

    def integral_of_squared_velocity(self) -> float:
        """∫₀¹ s'(u)² du (closed form from the coefficients); viscous energy = a2·d²/T times this."""
        sq = P.polymul(self.derivatives[0], self.derivatives[0])
        return float(P.polyval(1.0, P.polyint(sq)))


MAX_MOVE_DURATION_S = 3600.0
"""the longest move the model accepts [s]: one hour, 3.6 million samples at the 1 kHz execution rate
(the paper's bounds end at 20 s; anything longer than this is a unit mistake, not a move)"""

POLY3 = PolynomialLaw.of_degree(3)
POLY5 = PolynomialLaw.of_degree(5)
POLY7 = PolynomialLaw.of_degree(7)
POLYNOMIAL_LAWS: dict[str, PolynomialLaw] = {law.name: law for law in (POLY3, POLY5, POLY7)}


def polynomial_law(name: str) -> PolynomialLaw:
    """Look a law up by name ('poly3', 'poly5', 'poly7')."""
    try:
        return POLYNOMIAL_LAWS[name]
    except KeyError:
        raise MoveError(f"unknown motion law {name!r}; choose one of {', '.join(POLYNOMIAL_LAWS)}") from None


@dataclass(frozen=True)
class MoveSamples:
    """Kinematics of a move at given times (arrays of the same shape as the times)."""

    t_s: np.ndarray
    position_m: np.ndarray
    velocity_m_s: np.ndarray
    acceleration_m_s2: np.ndarray
    jerk_m_s3: np.ndarray


class Motion(Protocol):
    """What a drive can execute: a rest-to-rest motion from ``x0_m`` to ``x1_m`` over ``duration_s``
    (a polynomial :class:`Move`, a :class:`~axisflow.model.trajectory.SampledTrajectory`)."""

    @property
    def duration_s(self) -> float: ...

    @property
    def x0_m(self) -> float: ...

    @property
    def x1_m(self) -> float: ...

    def sample(self, t_s: ArrayLike) -> MoveSamples: ...


@dataclass(frozen=True)
class Move:
    """A rest-to-rest move x0 → x1 in ``duration_s`` seconds along a polynomial law."""

    x0_m: float
    x1_m: float
    duration_s: float
    law: PolynomialLaw

    def __post_init__(self) -> None:
        for name, unit in (("x0_m", "m"), ("x1_m", "m"), ("duration_s", "s")):
            value = getattr(self, name)
            if not math.isfinite(value):
                raise MoveError(f"move {name} = {value} {unit} is not finite")
        if self.duration_s <= 0:
            raise MoveError(f"move duration_s = {self.duration_s} s must be > 0 s")
        if self.duration_s > MAX_MOVE_DURATION_S:
            raise MoveError(
                f"move duration_s = {self.duration_s} s exceeds the longest move, {MAX_MOVE_DURATION_S:g} s"
            )

    @property
    def distance_m(self) -> float:
        """Signed travel d = x1 − x0 [m]."""
        return self.x1_m - self.x0_m

    @property
    def peak_velocity_m_s(self) -> float:
        return self.law.peak_velocity_factor * abs(self.distance_m) / self.duration_s

    @property
    def peak_acceleration_m_s2(self) -> float:
        return self.law.peak_acceleration_factor * abs(self.distance_m) / self.duration_s**2

    def sample(self, t_s: ArrayLike) -> MoveSamples:
        """Position, velocity, acceleration and jerk at times ``t_s`` [s] after the move's start.

        Times before 0 or after the duration give the rest states at x0 or x1.
        """
        t = np.asarray(t_s, dtype=float)
        T = self.duration_s
        d = self.distance_m
        u = np.clip(t / T, 0.0, 1.0)
        inside = (t >= 0.0) & (t <= T)
        pos = self.x0_m + d * self.law.shape(u)
        vel = np.where(inside, d / T * self.law.shape(u, 1), 0.0)
        acc = np.where(inside, d / T**2 * self.law.shape(u, 2), 0.0)
        jerk = np.where(inside, d / T**3 * self.law.shape(u, 3), 0.0)
        return MoveSamples(t, pos, vel, acc, jerk)
