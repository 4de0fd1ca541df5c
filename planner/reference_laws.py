"""Reference laws: what the axis can do at its limits, with the full friction model of eq. (1).

In the frame where the move runs forward (v ≥ 0) the cart obeys M·v̇ = F − φ(v), with
φ(v) = a1 + a2·v + a3·atan(a4·v) and the motor force bounded by |F| ≤ F_max = tau_max·i_r/r.

**Time-optimal law (bang–cruise–bang).** Full driving force, then (if the top speed is reached) a
cruise at it with F = φ(v), then full braking force F = −F_max, during which friction helps. The top
speed is v_max, or, on an axis whose friction at v_max exceeds F_max, the friction-limited speed
v_f (φ(v_f) = F_max, approached but never reached at full force) less 1e-9 of it:

    accelerating to V:  t_a(V) = ∫₀ⱽ M/(F_max − φ(w)) dw,   x_a(V) = ∫₀ⱽ M·w/(F_max − φ(w)) dw
    braking from V:     t_b(V) = ∫₀ⱽ M/(F_max + φ(w)) dw,   x_b(V) = ∫₀ⱽ M·w/(F_max + φ(w)) dw

The peak velocity V solves x_a(V) + x_b(V) = D (if that V is below the top speed; otherwise V is the
top speed and the rest is cruise). Near v_f the acceleration integrals have a pole; their panels
are graded geometrically towards it. Because friction opposes acceleration and helps braking,
x_a > x_b: the switch is past mid-stroke. Pontryagin's principle gives this bang–bang structure
for min T s.t. the limits.

**Least-energy profile at a given duration T.** Among profiles that accelerate at full force to a
cruise speed V_c, cruise, coast (F = 0, friction decelerates: M·v̇ = −φ(v)) down to V_b and brake at
full force, the one with the least energy under the accounting g:

* signed: E = friction work ∫φ(v)·dx; with no coasting (V_b = V_c) this is the profile of the paper
  notes (full-force ramps, flat cruise): the cruise speed V_c is the smallest that still makes T;
* positive/absolute: braking energy is not refunded, coasting is free, so the coast–brake split is
  optimised (one variable, bounded Brent search; V_c follows from the duration).

Energies in closed form per phase: accelerating F_max·x_a, cruise φ(V_c)·x_c, coast 0, braking
g(−F_max·x_b) (signed −F_max·x_b, positive 0, absolute +F_max·x_b).

The least-energy profile is optimal within that family (which contains the signed-energy optimum
when ψ(v) = φ(v) + λ/v is convex on the speeds used; docs/planner.md). It is a reference, not a
planner back-end: all quadratures are 16-point Gauss–Legendre on graded panels (≈1e-12 relative).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..model import AxisParams, EnergyAccounting, MoveError, forward_friction
from ..model.deadline import Deadline, iteration_cap
from ..model.encoder import axis_resolution_m
from ..model.params import forward_axis
from .errors import InfeasibleMoveError
from .problem import DEFAULT_OMEGA, DEFAULT_TIME_BOUNDS_S, DEFAULT_W0, REFERENCE_LAWS, Case

_DOUBLINGS = 64
"""the cap of the searches that double (or halve) a speed to bracket a root: 2^64 spans any speed"""
_BRENT_STEPS = 200
"""the cap of Brent's method on the phase equations (smooth and monotone: ~20 steps)"""
_RTOL_FLOOR = 4.0 * float(np.finfo(float).eps)
"""the smallest relative tolerance Brent's method takes (its default)"""
_SEARCH_DEADLINE_S = 30.0
"""the default deadline of :func:`plan_reference`'s Brent search over the duration [s] (a search of a
short move's time-energy optimum takes seconds: docs/planner.md)"""

_X, _W = np.polynomial.legendre.leggauss(16)
_EDGES = np.array([0.0, 1e-3, 1e-2, 0.05, 0.2, 0.5, 1.0])


class ReferenceLawError(MoveError):
    """The axis cannot follow the reference law (e.g. friction at v_max exceeds the force limit)."""


def _integral(f, lo: float, hi: float, pole: float = math.inf) -> float:  # noqa: ANN001 - ndarray -> ndarray
    """∫_lo^hi f(w) dw on panels graded towards lo (where atan(a4·w) turns) and, when f has a pole
    just above hi (the friction-limited speed), geometrically towards hi as well."""
    if hi <= lo:
        return 0.0
    edges = lo + (hi - lo) * _EDGES
    gap = pole - hi
    if gap < hi - lo:  # panel k spans distances gap·10^k … gap·10^(k+1) to the pole
        k = np.arange(0, int(math.log10((hi - lo) / gap)) + 1)
        near = pole - gap * 10.0**k
        edges = np.unique(np.concatenate([edges, near[near > lo]]))  # graded at both ends
    a, b = edges[:-1, None], edges[1:, None]
    x = 0.5 * (a + b) + 0.5 * (b - a) * _X
    return float(np.sum(0.5 * (b - a) * _W * f(x)))


@dataclass(frozen=True)
class _Phases:
    params: AxisParams

    def accel(self, v: float) -> tuple[float, float]:
        """(t_a, x_a): time and distance to accelerate from rest to v at full force."""
        p = self.params
        f = p.f_max
        pole = friction_limited_speed(p)
        t = _integral(lambda w: p.M_eq / (f - forward_friction(w, p)), 0.0, v, pole)
        x = _integral(lambda w: p.M_eq * w / (f - forward_friction(w, p)), 0.0, v, pole)
        return t, x

    def brake(self, v_hi: float, v_lo: float = 0.0) -> tuple[float, float]:
        """(t_b, x_b): time and distance to brake from v_hi to v_lo at full braking force."""
        p = self.params
        f = p.f_max
        t = _integral(lambda w: p.M_eq / (f + forward_friction(w, p)), v_lo, v_hi)
        x = _integral(lambda w: p.M_eq * w / (f + forward_friction(w, p)), v_lo, v_hi)
        return t, x

    def coast(self, v_hi: float, v_lo: float) -> tuple[float, float]:
        """(t_c, x_c): time and distance to coast (F = 0) from v_hi down to v_lo."""
        p = self.params
        t = _integral(lambda w: p.M_eq / forward_friction(w, p), v_lo, v_hi)
        x = _integral(lambda w: p.M_eq * w / forward_friction(w, p), v_lo, v_hi)
        return t, x


@dataclass(frozen=True)
class ReferenceProfile:
    """A rest-to-rest profile made of phases: full force, cruise, coast, full braking."""

    law: str
    distance_m: float
    cruise_velocity_m_s: float
    """the top speed V_c [m/s]"""
    brake_velocity_m_s: float
    """the speed V_b [m/s] at which coasting ends and full braking starts (V_b = V_c: no coast)"""
    accel_time_s: float
    cruise_time_s: float
    coast_time_s: float
    brake_time_s: float
    accel_distance_m: float
    cruise_distance_m: float
    coast_distance_m: float
    brake_distance_m: float
    energy_j: dict[str, float]
    """energy [J] under each accounting (signed, positive, absolute)"""

    @property
    def duration_s(self) -> float:
        return self.accel_time_s + self.cruise_time_s + self.coast_time_s + self.brake_time_s

    @property
    def switch_fraction(self) -> float:
        """Where the braking starts, as a fraction of the stroke (0.5 = mid-stroke)."""
        if self.distance_m == 0.0:
            return 0.5
        return (self.distance_m - self.brake_distance_m) / self.distance_m

    def energy(self, accounting: EnergyAccounting | str) -> float:
        return self.energy_j[EnergyAccounting(accounting).value]


def _profile(
    law: str, params: AxisParams, D: float, v_c: float, v_b: float, phases: _Phases
) -> ReferenceProfile | None:
    """The phase profile with top speed v_c and brake speed v_b ≤ v_c, or None if it overshoots D."""
    t_a, x_a = phases.accel(v_c)
    t_k, x_k = phases.coast(v_c, v_b) if v_b < v_c else (0.0, 0.0)
    t_b, x_b = phases.brake(v_b)
    x_c = D - x_a - x_k - x_b
    if x_c < -1e-12 * max(D, 1e-300):
        return None
    x_c = max(x_c, 0.0)
    f = params.f_max
    cruise = float(forward_friction(v_c, params)) * x_c  # < 0 where a load drives the cart on (c < 0)
    work = f * x_a + cruise
    driving = f * x_a + max(cruise, 0.0)
    return ReferenceProfile(
        law=law,
        distance_m=D,
        cruise_velocity_m_s=v_c,
        brake_velocity_m_s=v_b,
        accel_time_s=t_a,
        cruise_time_s=x_c / v_c if v_c > 0 else 0.0,
        coast_time_s=t_k,
        brake_time_s=t_b,
        accel_distance_m=x_a,
        cruise_distance_m=x_c,
        coast_distance_m=x_k,
        brake_distance_m=x_b,
        energy_j={
            "signed": work - f * x_b,
            "positive": driving,
            "absolute": driving + max(-cruise, 0.0) + f * x_b,
        },
    )


@lru_cache(maxsize=64)
def friction_limited_speed(params: AxisParams) -> float:
    """The speed [m/s] at which friction takes the whole force limit, φ(v) = F_max (∞ if never):
    full force accelerates the cart towards it, but never to it."""
    f = params.f_max
    law = params.forward(1.0)  # φ of forward_friction, as a record
    if float(law.value(0.0)) >= f:
        return 0.0
    if law.b == 0.0 and law.saturated_n <= f:
        return math.inf  # friction saturates below the force limit
    hi = 1.0
    for _ in range(_DOUBLINGS):
        if float(law.value(hi)) >= f:
            return _brent(lambda v: float(law.value(v)) - f, 0.0, hi, "the friction-limited v")
        hi *= 2.0
    return math.inf  # φ stays below F_max beyond 2^64 m/s: no speed the axis reaches


def _brent(f, a: float, b: float, what: str, xtol: float = 1e-15, rtol: float = 1e-15) -> float:  # noqa: ANN001
    """Brent's root of f on [a, b], capped at :data:`_BRENT_STEPS` steps."""
    try:
        from scipy.optimize import brentq  # scipy loads on first use, not with the planner package

        return brentq(f, a, b, xtol=xtol, rtol=rtol, maxiter=_BRENT_STEPS)
    except RuntimeError:  # pragma: no cover - bracketed, smooth and monotone
        raise iteration_cap(what, _BRENT_STEPS) from None


_BELOW_FRICTION_LIMIT = 1e-9
"""the top speed stays this fraction below the friction-limited speed (reached only asymptotically)"""


def top_speed(params: AxisParams) -> float:
    """The highest speed [m/s] a profile may cruise at: v_max, or just below the friction-limited
    speed when friction at v_max exceeds the force limit."""
    v_fric = friction_limited_speed(params)
    if v_fric == 0.0:
        raise ReferenceLawError(
            f"the Coulomb friction a1 = {params.a1} N is not below the force limit "
            f"F_max = {params.f_max:.6g} N (tau_max = {params.tau_max} N·m): the axis cannot move"
        )
    return min(params.v_max, v_fric * (1.0 - _BELOW_FRICTION_LIMIT))


def time_optimal(distance_m: float, params: AxisParams) -> ReferenceProfile:
    """The bang–cruise–bang minimum-time profile over |distance_m| (see the module docstring); a
    distance shorter than one encoder count is a zero move (the profile of distance 0)."""
    D = abs(float(distance_m))
    if not math.isfinite(D):
        raise MoveError(f"distance_m = {distance_m} m is not finite")
    if D > params.L * (1 + 1e-12):
        raise MoveError(f"distance_m = {distance_m} m is longer than the stroke L = {params.L} m")
    if axis_resolution_m(params) > D:  # a zero move
        D = 0.0
    return _time_optimal(D, forward_axis(params, float(distance_m)))


@lru_cache(maxsize=4096)
def _time_optimal(D: float, params: AxisParams) -> ReferenceProfile:
    v_top = top_speed(params)
    ph = _Phases(params)
    if D == 0.0:
        return _profile("bang", params, 0.0, 0.0, 0.0, ph)  # type: ignore[return-value]

    def overshoot(v: float) -> float:
        return ph.accel(v)[1] + ph.brake(v)[1] - D

    v = v_top
    if overshoot(v_top) > 0.0:
        v = _brent(overshoot, 0.0, v_top, "the bang law's peak speed", rtol=_RTOL_FLOOR)
    prof = _profile("bang", params, D, v, v, ph)
    assert prof is not None  # v was chosen so that the ramps fit
    return prof


def least_energy(
    distance_m: float, duration_s: float, params: AxisParams, accounting: EnergyAccounting | str | None = None
) -> ReferenceProfile:
    """The least-energy profile of the family above that covers |distance_m| in ``duration_s``."""
    acc = params.energy_accounting if accounting is None else EnergyAccounting(accounting)
    fastest = time_optimal(distance_m, params)
    params = forward_axis(params, float(distance_m))
    c = params.a1 + params.f0
    if c < 0.0 and fastest.distance_m > 0.0:
        raise ReferenceLawError(
            f"least-energy: a load of {-c:.6g} N drives the cart along this move (friction and f0 "
            "give c < 0): its coast phase would not slow the cart; the reference needs c >= 0"
        )
    D = fastest.distance_m
    T = float(duration_s)
    if not math.isfinite(T) or T < 0.0 or (T == 0.0 and D > 0.0):
        raise MoveError(f"duration_s = {duration_s} s must be a finite number > 0 s")
    if D == 0.0:  # a zero move (shorter than one encoder count): any duration, 0 included
        return fastest
    if fastest.duration_s * (1 - 1e-12) > T:
        raise InfeasibleMoveError(
            f"duration_s = {T:.6g} s is shorter than the time-optimal {fastest.duration_s:.6g} s for "
            f"{D:.6g} m under v_max = {params.v_max} m/s and tau_max = {params.tau_max} N·m"
        )
    if fastest.duration_s >= T:
        return fastest
    return _least_energy(D, T, params, acc)


@lru_cache(maxsize=8192)
def _least_energy(D: float, T: float, params: AxisParams, acc: EnergyAccounting) -> ReferenceProfile:
    ph = _Phases(params)
    v_top = _time_optimal(D, params).cruise_velocity_m_s

    def with_ratio(r: float) -> ReferenceProfile | None:
        """The profile with V_b = r·V_c whose duration is T (None if no V_c ≤ v_max gives T)."""

        def ramps(v_c: float) -> float:
            x_k = ph.coast(v_c, r * v_c)[1] if r < 1.0 else 0.0
            return ph.accel(v_c)[1] + x_k + ph.brake(r * v_c)[1] - D

        # the largest top speed whose ramps (and coast) still fit the distance
        v_fit = (
            v_top
            if ramps(v_top) <= 0.0
            else _brent(ramps, 0.0, v_top, "the least-energy law's top speed", rtol=_RTOL_FLOOR) * (1 - 1e-13)
        )

        def excess(v_c: float) -> float:
            prof = _profile("least-energy", params, D, v_c, r * v_c, ph)
            return -math.inf if prof is None else T - prof.duration_s

        if excess(v_fit) < 0.0:
            return None
        lo = v_fit
        for _ in range(_DOUBLINGS):
            if excess(lo) < 0.0:
                break
            lo *= 0.5
        else:
            raise iteration_cap("the least-energy law's cruise-speed bracket", _DOUBLINGS)
        v_c = _brent(excess, lo, v_fit, "the least-energy law's cruise speed", rtol=1e-14)
        return _profile("least-energy", params, D, v_c, r * v_c, ph)

    if acc is EnergyAccounting.SIGNED:
        prof = with_ratio(1.0)
        assert prof is not None
        return prof

    def cost(r: float) -> float:
        prof = with_ratio(r)
        return math.inf if prof is None else prof.energy(acc)

    best = with_ratio(1.0)
    assert best is not None
    from scipy.optimize import minimize_scalar

    res = minimize_scalar(cost, bounds=(0.0, 1.0), method="bounded", options={"xatol": 1e-7})
    for r in (float(res.x), 0.0):
        cand = with_ratio(r)
        if cand is not None and cand.energy(acc) < best.energy(acc):
            best = cand
    return best


@dataclass(frozen=True)
class ReferencePlan:
    """A reference law planned for one move: the chosen duration and its profile."""

    law: str
    duration_s: float
    objective: float
    energy_j: float
    profile: ReferenceProfile
    solve_time_s: float


def plan_reference(
    law: str,
    distance_m: float,
    params: AxisParams,
    *,
    minimise_time: bool = True,
    omega: float = DEFAULT_OMEGA,
    w0: float = DEFAULT_W0,
    t_min_s: float = DEFAULT_TIME_BOUNDS_S[Case.MIN_TIME][0],
    t_max_s: float = DEFAULT_TIME_BOUNDS_S[Case.MIN_TIME][1],
    deadline_s: float = _SEARCH_DEADLINE_S,
) -> ReferencePlan:
    """Plan a move with a reference law.

    ``bang`` (minimum time only): the bang–cruise–bang duration, raised to ``t_min_s`` if shorter (a
    longer move is then the least-energy profile at t_min_s). ``least-energy``: for minimum time the
    same duration; for min ω·T + (1 − ω)·E_least(T) a bounded Brent search over
    [max(t_min_s, T_bang), t_max_s] (E_least is decreasing and smooth in T in practice; a local
    optimum, not certified; every step checks a deadline of ``deadline_s``,
    :class:`~axisflow.model.deadline.DeadlineError`). A distance shorter than one encoder count is a
    zero move: duration 0 s, energy 0 J, as the polynomial laws' (:mod:`.evaluation`).
    """
    import time

    if law not in REFERENCE_LAWS:
        raise MoveError(f"unknown reference law {law!r}; choose one of {', '.join(REFERENCE_LAWS)}")
    if law == "bang" and not minimise_time:
        raise MoveError("the bang law is the minimum-time law: use it with --case min-time")
    t0 = time.perf_counter()
    deadline = Deadline(deadline_s, f"the {law} reference plan")
    acc = params.energy_accounting
    fastest = time_optimal(distance_m, params)
    if fastest.distance_m == 0.0:
        return ReferencePlan(law, 0.0, 0.0, 0.0, fastest, time.perf_counter() - t0)
    t_lo = max(t_min_s, fastest.duration_s)
    if t_lo > t_max_s:
        raise InfeasibleMoveError(
            f"no duration in [{t_min_s}, {t_max_s}] s: the time-optimal move over {abs(distance_m):.6g} m "
            f"takes {fastest.duration_s:.6g} s"
        )
    if minimise_time:
        prof = least_energy(distance_m, t_lo, params)
        t = t_lo
        obj = w0 * t if minimise_time else omega * t + (1 - omega) * prof.energy(acc)
    else:

        def cost(t: float) -> float:
            deadline.check("the Brent search over the duration")
            return omega * t + (1 - omega) * least_energy(distance_m, t, params).energy(acc)

        from scipy.optimize import minimize_scalar

        res = minimize_scalar(cost, bounds=(t_lo, t_max_s), method="bounded", options={"xatol": 1e-7})
        t = float(res.x)
        if cost(t_lo) < res.fun:
            t = t_lo
        prof = least_energy(distance_m, t, params)
        obj = cost(t)
    return ReferencePlan(law, t, obj, prof.energy(acc), prof, time.perf_counter() - t0)
