"""The case-2 objective of one move with braking energy, and the root of its slope.

    J(T) = ω·T + (1 − ω)·(E_s(T) + c·R(T)),     dJ/dT = ω + (1 − ω)·(dE_s/dT + c·dR/dT),

convex in T (:mod:`.energy`), so dJ/dT is increasing and its root, when J falls at T_s and rises
later, is the global minimiser. :func:`slope_root` brackets that root by safeguarded secant steps;
only exact evaluations of dJ/dT (never a table) decide the bracket.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from ...model.deadline import Deadline, iteration_cap
from .energy import braking_energy_and_slope, signed_energy, signed_energy_slope
from .law_model import NEWTON_MAX_STEPS, LawModel

ROOT_REL = 1e-10
"""relative width at which the bracket of the root of dJ/dT is closed"""
_BISECTION_STEPS = 128
"""the cap of the closing bisection (each halves the bracket: 40 close any bracket of [T_min, T_max])"""
_AIM_PAST = 1e-11
"""near the root, probes are aimed this fraction of T past the secant's root"""


class StartGuess(NamedTuple):
    """A start for the root search: T₀ [s] near the root and d²J/dT² there (tabulated)."""

    t0_s: float
    curvature: float


class SlopeRoot(NamedTuple):
    """dJ/dT(t_lower_s) ≤ 0 ≤ dJ/dT(t_upper_s), with t_upper_s − t_lower_s ≤ 1e-10·t_upper_s;
    ``slope`` is the last dJ/dT evaluated. ``unbounded``: no positive slope was found up to T_max
    (both ends are then the last duration where dJ/dT ≤ 0)."""

    t_lower_s: float
    t_upper_s: float
    slope: float
    unbounded: bool


class ObjectiveSlope:
    """dJ/dT of J = ω·T + (1 − ω)·(E_s + c·R) for one move, memoised per T (J itself on demand)."""

    __slots__ = ("D", "c", "hint", "lm", "memo", "omega")

    def __init__(self, lm: LawModel, D: float, omega: float, c: float) -> None:
        self.lm, self.D, self.omega, self.c = lm, D, omega, c
        self.hint: list[float] = []
        self.memo: dict[float, tuple[float, float]] = {}

    def __call__(self, t: float) -> tuple[float, float]:
        """(dJ/dT, R) at t: exact evaluations (analytic interval, Gauss–Legendre), memoised."""
        got = self.memo.get(t)
        if got is None:
            lm, D, omega = self.lm, self.D, self.omega
            r, dr = braking_energy_and_slope(lm, D, t, self.hint)
            got = self.memo[t] = (omega + (1.0 - omega) * (signed_energy_slope(lm, D, t) + self.c * dr), r)
        return got

    def objective(self, t: float) -> float:
        """J(t); R from the memo when t was evaluated."""
        r = self(t)[1]
        return self.omega * t + (1.0 - self.omega) * (signed_energy(self.lm, self.D, t) + self.c * r)

    def value_and_slope(self, t: float) -> tuple[float, float]:
        """(J, dJ/dT) at t."""
        return self.objective(t), self(t)[0]


def slope_root(
    slope: ObjectiveSlope,
    t_s: float,
    g_s: float,
    t_max: float,
    guess: StartGuess | None = None,
    deadline: Deadline | None = None,
) -> SlopeRoot:
    """The root of dJ/dT right of t_s, where dJ/dT(t_s) = g_s < 0 (see :class:`_SecantSearch`);
    ``deadline`` is checked at every step (:class:`~axisflow.model.deadline.SolveLimitError`)."""
    return _SecantSearch(slope, t_s, g_s, t_max, deadline).run(guess)


class _SecantSearch:
    """Secant steps on dJ/dT (increasing), kept inside the bracket [a, b] once one is known;
    bisection when a step leaves it or stalls.

    Without a guess the first probe is next to T_s. With ``guess`` = (T₀, d²J/dT²(T₀)) from the start
    table (:mod:`.start_table`) the search starts with an exact evaluation at T₀ and a Newton step with
    the tabulated curvature. Close to the root (the secant's error estimate far below 1e-11·T) each
    probe is aimed 1e-11·T past the secant's root, away from the end just evaluated, so that the
    bracket closes in one or two more evaluations. The guess changes the path, never the proof.
    """

    def __init__(
        self, slope: ObjectiveSlope, t_s: float, g_s: float, t_max: float, deadline: Deadline | None = None
    ) -> None:
        self.slope, self.t_s, self.t_max, self.deadline = slope, t_s, t_max, deadline
        # the bracket: dJ/dT(a) ≤ 0 < dJ/dT(b), b = ∞ until a positive slope is seen
        self.a, self.b = t_s, math.inf
        # the previous probe and its slope, for the secant
        self.x_prev, self.g_prev = t_s, g_s

    def run(self, guess: StartGuess | None) -> SlopeRoot:
        x = min(self.t_s * (1.0 + 1e-3), self.t_max)
        if guess is not None and self.t_s <= guess.t0_s < self.t_max and guess.curvature > 0.0:
            step = self._newton_from(guess)
            if step is None:
                return SlopeRoot(guess.t0_s, guess.t0_s, 0.0, False)
            x = step
        gx = self.g_prev
        for it in range(NEWTON_MAX_STEPS):
            if self.deadline is not None:
                self.deadline.check("the secant search of the time-energy optimum")
            gx = self._probe(x)
            if gx == 0.0 or (self.b < math.inf and self.b - self.a <= ROOT_REL * self.b):
                break
            if gx < 0.0 and x >= self.t_max:  # J decreasing up to the bound
                break
            x = self._next(x, gx, it)
        if self.b == math.inf:
            return SlopeRoot(self.a, self.a, gx, True)
        return self._bisect(x, gx)

    def _probe(self, x: float) -> float:
        """dJ/dT at x, and the bracket narrowed by it."""
        gx = self.slope(x)[0]
        if gx > 0.0:
            self.b = min(self.b, x)
        else:
            self.a = max(self.a, x)
        return gx

    def _newton_from(self, guess: StartGuess) -> float | None:
        """Evaluate at T₀ and return the Newton step from it (None: dJ/dT(T₀) = 0, the root)."""
        t0 = guess.t0_s
        g0 = self.slope(t0)[0]
        if g0 > 0.0:
            self.b = t0
        else:
            self.a = t0
        if g0 == 0.0:
            return None
        self.x_prev, self.g_prev = t0, g0
        a, b = self.a, self.b
        nx = t0 - g0 / guess.curvature  # (when it is already the left end, its value is memoised)
        if a <= nx < min(b, self.t_max):
            return nx
        return 0.5 * (a + b) if b < math.inf else min(t0 * 1.01, self.t_max)

    def _next(self, x: float, gx: float, it: int) -> float:
        """The next probe after dJ/dT(x) = gx: the secant's root, safeguarded."""
        a, b = self.a, self.b
        nx = x - gx * (x - self.x_prev) / (gx - self.g_prev) if gx != self.g_prev else math.nan
        # the secant's error is ~ |nx − x|·|nx − x_prev|/T: when that is far below 1e-11·T, a probe
        # 1e-11·T past nx lands on the other side of the root
        err = abs(nx - x) * abs(nx - self.x_prev) / x
        near = err <= 1e-13 * x
        self.x_prev, self.g_prev = x, gx
        if b == math.inf:
            if not nx > a:  # no sensible secant step yet: double the distance from T_s
                nx = self.t_s + 2.0 * (a - self.t_s)
            # aim a hair past the secant's root, so that a step from the left also brackets it
            return min(nx + min(max(_AIM_PAST * nx, 4.0 * err), ROOT_REL * nx), self.t_max)
        if a < nx < b and it < 12:
            if near:  # aim past the root, away from the end just evaluated
                hair = nx + (_AIM_PAST * nx if gx < 0.0 else -_AIM_PAST * nx)
                if a < hair < b:
                    nx = hair
            return nx
        return 0.5 * (a + b)

    def _bisect(self, x: float, gx: float) -> SlopeRoot:
        """Close a bracket the secant left open (not reached in practice) and report it."""
        for _ in range(_BISECTION_STEPS):
            if not (self.b - self.a > ROOT_REL * self.b and gx != 0.0):
                break
            if self.deadline is not None:
                self.deadline.check("the bisection of the time-energy optimum")
            x = 0.5 * (self.a + self.b)
            gx = self.slope(x)[0]
            if gx > 0.0:
                self.b = x
            else:
                self.a = x
        else:
            raise iteration_cap("the bisection of the time-energy optimum", _BISECTION_STEPS)
        if gx == 0.0:
            self.a = self.b = x
        return SlopeRoot(self.a, self.b, gx, False)
