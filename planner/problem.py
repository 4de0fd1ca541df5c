"""The point-to-point planning problem of the paper, eqs. (2)–(4), as validated data.

One decision variable, the duration T of a rest-to-rest move x0 → x1 along a motion law:

* case 1, minimum time:        min_T  w0·T
* case 2, minimum time-energy: min_T  ω·T + (1 − ω)·E(T),   E(T) = ∫₀ᵀ g(F·ẋ) dt

subject to (4), as adopted in docs/paper-notes: |ẋ(t)| ≤ v_max and |τ_m(t)| ≤ tau_max over the whole
move, 0 ≤ x ≤ L (the polynomial laws never overshoot, so the end points decide it) and
T_min ≤ T ≤ T_max (0.1–3 s for case 1, 0.3–20 s for case 2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum
from typing import TYPE_CHECKING

from ..model import MAX_MOVE_DURATION_S, MoveError, PolynomialLaw, polynomial_law

if TYPE_CHECKING:
    from ..model import AxisParams


class Case(StrEnum):
    """Which objective the duration minimises."""

    MIN_TIME = "min-time"
    MIN_TIME_ENERGY = "min-time-energy"


DEFAULT_TIME_BOUNDS_S: dict[Case, tuple[float, float]] = {
    Case.MIN_TIME: (0.1, 3.0),
    Case.MIN_TIME_ENERGY: (0.3, 20.0),
}
DEFAULT_OMEGA = 0.9
REFERENCE_LAWS: tuple[str, ...] = ("bang", "least-energy")
"""the reference laws by name (:mod:`.reference_laws`): the same move planned at the axis's limits
instead of along a polynomial law, as ``--law`` accepts them"""
DEFAULT_W0 = 100.0
"""the paper's w0 of eq. (2), "used to improve the convergence": with 100, IPOPT converges within its
10 iterations on the default axis (measured: ~9 iterations; with 1 most solves stop at the cap)"""


@dataclass(frozen=True, init=False)
class MoveProblem:
    """One move to plan: end points [m], law, case, weight ω and duration bounds [s] (given as None:
    the case's bounds, :data:`DEFAULT_TIME_BOUNDS_S`)."""

    x0_m: float
    x1_m: float
    law: PolynomialLaw
    case: Case
    omega: float
    t_min_s: float
    t_max_s: float
    w0: float

    def __init__(
        self,
        x0_m: float,
        x1_m: float,
        law: PolynomialLaw | str,
        case: Case | str = Case.MIN_TIME,
        omega: float = DEFAULT_OMEGA,
        t_min_s: float | None = None,
        t_max_s: float | None = None,
        w0: float = DEFAULT_W0,
    ) -> None:
        case = Case(case)
        lo, hi = DEFAULT_TIME_BOUNDS_S[case]
        given = {
            "x0_m": x0_m,
            "x1_m": x1_m,
            "law": polynomial_law(law) if isinstance(law, str) else law,
            "case": case,
            "omega": omega,
            "t_min_s": lo if t_min_s is None else t_min_s,
            "t_max_s": hi if t_max_s is None else t_max_s,
            "w0": w0,
        }
        for name, value in given.items():
            object.__setattr__(self, name, value)
        for name, unit in (
            ("x0_m", "m"),
            ("x1_m", "m"),
            ("omega", ""),
            ("t_min_s", "s"),
            ("t_max_s", "s"),
            ("w0", ""),
        ):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
                raise MoveError(f"{name} = {value!r} {unit} is not a finite number".replace("  ", " "))
            object.__setattr__(self, name, float(value))
        if not 0.0 <= self.omega <= 1.0:
            raise MoveError(f"omega = {self.omega} is outside [0, 1]")
        if self.w0 <= 0.0:
            raise MoveError(f"w0 = {self.w0} must be > 0")
        if self.t_min_s <= 0.0:
            raise MoveError(f"t_min_s = {self.t_min_s} s must be > 0 s")
        if self.t_max_s > MAX_MOVE_DURATION_S:
            raise MoveError(f"t_max_s = {self.t_max_s} s exceeds the longest move, {MAX_MOVE_DURATION_S:g} s")
        if self.t_min_s > self.t_max_s:
            raise MoveError(
                f"duration bounds are empty: t_min_s = {self.t_min_s} s > t_max_s = {self.t_max_s} s"
            )

    @property
    def distance_m(self) -> float:
        return self.x1_m - self.x0_m

    def check_stroke(self, params: AxisParams) -> None:
        """Raise :class:`MoveError` if an end point lies outside the stroke [0, L]."""
        for name in ("x0_m", "x1_m"):
            value = getattr(self, name)
            if not 0.0 <= value <= params.L:
                raise MoveError(f"{name} = {value} m is outside the stroke [0, {params.L}] m")
