"""Baseline laws: the rest-to-rest profiles drives run today, computed by Ruckig.

* ``trapezoid`` — a trapezoidal velocity profile: accelerate at a, cruise at v (if the move is long
  enough to reach it), decelerate at a; the profile of CiA 402 profile position mode. The acceleration
  jumps (infinite jerk). Closed form: a move of length D ≥ v²/a takes T = D/v + v/a, a shorter one
  2·√(D/a) (a triangle).
* ``scurve`` — the time-optimal profile under velocity, acceleration and jerk limits (up to seven phases
  of constant jerk ±j or 0): what Ruckig, most motion controllers and PLC motion libraries generate.
  A move that reaches both a and v takes T = D/v + v/a + a/j.

Both come from **Ruckig** (the field's reference library; the trapezoid is its second-order profile,
jerk = ∞), one degree of freedom from rest to rest. Ruckig returns each profile as phases of constant
jerk j_k with the position, velocity and acceleration at each phase start, so within phase k, τ after
its start,

    x = p_k + v_k·τ + a_k·τ²/2 + j_k·τ³/6,   ẋ = v_k + a_k·τ + j_k·τ²/2,   ẍ = a_k + j_k·τ

exactly (:class:`BaselineMove`). **Stretched** to a longer duration T (an equal-time comparison), each
keeps its acceleration and jerk limits and cruises slower: Ruckig's ``minimum_duration`` (for the
trapezoid the closed form v' = (a·T − √(a²T² − 4aD))/2, which the tests hold it to).

A baseline move is a :class:`~axisflow.model.Motion` like any other: its energy is eq. (3) under the
axis's accounting (:func:`~axisflow.model.motion_energy`, phase by phase: the trapezoid's jumps in
acceleration are phase edges), its peak torque and power are taken over each phase in continuous time,
and the 1 kHz limit check is the model's (:func:`~axisflow.model.check_limits`).

**How it reaches the bridge.** The wire contract already carries paths no polynomial describes: a move
of law ``sampled`` with knots (t, x, ẋ, ẍ) joined by quintic Hermite pieces, validated by the bridge at
every 1 kHz sample and knot like any move (:meth:`BaselineMove.trajectory`); no new law kind is needed.
An S-curve's phases are cubic with continuous acceleration, so knots at its phase edges reproduce it
exactly (8 knots at most). A trapezoid's acceleration jumps, which no C² path can do: knots at the 1 kHz
ticks would make the Hermite pieces that straddle a jump overshoot the acceleration by up to ~30 %
between the ticks (the bridge, checking between ticks, then rejects a trapezoid at the torque limit),
so each jump is sent as a ramp of 1 µs instead (:data:`JUMP_RAMP_S`): an S-curve with jerk a/1 µs,
whose setpoints differ from the trapezoid's by less than a·1 µs in velocity.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..model import (
    AxisParams,
    EnergyAccounting,
    MoveError,
    MoveSamples,
    SampledTrajectory,
    cart_force,
    check_limits,
    motion_energy,
    motor_speed,
    motor_torque,
)
from ..model.encoder import encoder_resolution_m
from ..model.motion_laws import ArrayLike
from .baseline_limits import BaselineLimits, check_law
from .errors import InfeasibleMoveError

_PHASE_POINTS = 257
"""points per phase at which the peaks are taken (both ends included, each with its own phase's
acceleration, so a jump counts on both sides)"""
JUMP_RAMP_S = 1e-6
"""on the wire, a jump in acceleration becomes a ramp this long [s] (a C² path cannot jump)"""
_STRETCH_RTOL = 1e-9
"""a requested duration this close (relative) below the minimum counts as the minimum itself"""


@dataclass(frozen=True, eq=False)
class BaselineMove:
    """A rest-to-rest baseline profile (see the module docstring); arrays per phase."""

    law: str
    x0_m: float
    x1_m: float
    limits: BaselineLimits
    """the limits the profile was computed with (the S-curve's jerk filled in)"""
    start_s: np.ndarray
    """(n + 1,) phase edges [s] from the move's start: 0, …, the duration"""
    position_m: np.ndarray
    """(n,) position at each phase's start [m]"""
    velocity_m_s: np.ndarray
    acceleration_m_s2: np.ndarray
    jerk_m_s3: np.ndarray
    """(n,) each phase's constant jerk [m/s³] (0 throughout for the trapezoid)"""
    min_duration_s: float
    """the time-optimal duration under the limits [s] (the duration unless stretched)"""
    _span: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_span", np.diff(self.start_s))

    @property
    def duration_s(self) -> float:
        return float(self.start_s[-1])

    @property
    def distance_m(self) -> float:
        return self.x1_m - self.x0_m

    @property
    def breaks_s(self) -> np.ndarray:
        """The phase edges [s]: where the kinematics may stop being smooth."""
        return self.start_s

    @property
    def stretched(self) -> bool:
        return self.duration_s > self.min_duration_s

    def phase_states(self, k: int, tau_s: np.ndarray) -> MoveSamples:
        """Kinematics within phase k at ``tau_s`` [s] after its start (not clipped to the phase)."""
        tau = np.asarray(tau_s, dtype=float)
        p, v, a, j = self.position_m[k], self.velocity_m_s[k], self.acceleration_m_s2[k], self.jerk_m_s3[k]
        return MoveSamples(
            self.start_s[k] + tau,
            p + tau * (v + tau * (a / 2 + tau * j / 6)),
            v + tau * (a + tau * j / 2),
            a + j * tau,
            np.full_like(tau, j),
        )

    def sample(self, t_s: ArrayLike) -> MoveSamples:
        """Position, velocity, acceleration and jerk at times ``t_s`` [s] after the start; rest at x0
        before it and at x1 from the duration on. At a phase edge the later phase's values."""
        t = np.asarray(t_s, dtype=float)
        k = np.clip(np.searchsorted(self.start_s, t, side="right") - 1, 0, self._span.size - 1)
        tau = np.clip(t - self.start_s[k], 0.0, self._span[k])
        p, v, a, j = self.position_m[k], self.velocity_m_s[k], self.acceleration_m_s2[k], self.jerk_m_s3[k]
        pos = p + tau * (v + tau * (a / 2 + tau * j / 6))
        vel = v + tau * (a + tau * j / 2)
        acc = a + j * tau
        before, after = t < 0.0, t >= self.duration_s
        return MoveSamples(
            t,
            np.where(before, self.x0_m, np.where(after, self.x1_m, pos)),
            np.where(before | after, 0.0, vel),
            np.where(before | after, 0.0, acc),
            np.where(before | after, 0.0, np.broadcast_to(j, np.shape(t))),
        )

    @property
    def continuous_acceleration(self) -> bool:
        """Whether the acceleration is continuous (no jump at any phase edge, nor at the ends)."""
        ends = self.phase_states(self._span.size - 1, np.array([self._span[-1]])).acceleration_m_s2
        jumps = [self.acceleration_m_s2[0], float(ends[0])]
        for k in range(1, self._span.size):
            before = self.phase_states(k - 1, np.array([self._span[k - 1]])).acceleration_m_s2[0]
            jumps.append(float(before) - self.acceleration_m_s2[k])
        scale = max(self.limits.acceleration_m_s2, 1e-300)
        return bool(np.max(np.abs(jumps)) <= 1e-9 * scale)

    def trajectory(self) -> SampledTrajectory:
        """The move as the wire's sampled path: knots at the phase edges, which the quintic Hermite
        pieces reproduce exactly where the acceleration is continuous. Where it jumps (the trapezoid),
        each jump becomes a ramp of :data:`JUMP_RAMP_S` (the same law under the jerk a/1 µs, computed
        by Ruckig at the same duration): the path differs from the trapezoid by < a·1 µs in velocity
        and its duration by at most 1 µs (see the module docstring)."""
        if not self.continuous_acceleration:
            lim = self.limits
            ramped = BaselineLimits(
                lim.velocity_m_s, lim.acceleration_m_s2, lim.acceleration_m_s2 / JUMP_RAMP_S
            )
            wire = baseline_move("scurve", self.x0_m, self.x1_m, ramped)  # the trapezoid's T + ≤ 1 µs
            if wire.duration_s < self.duration_s:  # stretched as the trapezoid is
                wire = baseline_move("scurve", self.x0_m, self.x1_m, ramped, self.duration_s)
            return wire.trajectory()
        t = self.start_s.copy()
        s = self.sample(t)
        x, v, a = s.position_m.copy(), s.velocity_m_s.copy(), s.acceleration_m_s2.copy()
        x[0], x[-1] = self.x0_m, self.x1_m
        v[0] = v[-1] = a[0] = a[-1] = 0.0
        return SampledTrajectory(t, x, v, a)


@dataclass(frozen=True)
class BaselinePlan:
    """One baseline move planned and scored on the axis model (the result object of
    :func:`plan_baseline`); a zero move (shorter than one encoder count) has no move and zeros."""

    law: str
    x0_m: float
    x1_m: float
    limits: BaselineLimits
    move: BaselineMove | None
    duration_s: float
    min_duration_s: float
    energy_j: float
    """eq. (3) under ``accounting`` [J]"""
    accounting: EnergyAccounting
    peak_velocity_m_s: float
    peak_acceleration_m_s2: float
    peak_torque_nm: float
    """the largest |τ_m| over the move [N·m], each phase in continuous time"""
    peak_power_w: float
    """the largest mechanical power F·ẋ drawn from the drive over the move [W]"""
    max_violation: float
    """the worst relative excess over v_max or tau_max at the 1 kHz samples (0: none)"""
    solve_time_s: float
    """Ruckig's calculation [s]"""
    message: str = ""

    @property
    def zero_move(self) -> bool:
        return self.move is None

    def to_dict(self) -> dict[str, object]:
        """What ``axisflow plan --law trapezoid|scurve --json`` prints besides the move's end points."""
        return {
            "solver": "ruckig",
            "status": "converged",
            "duration_s": self.duration_s,
            "min_duration_s": self.min_duration_s,
            "energy_j": self.energy_j,
            "energy_accounting": self.accounting.value,
            "peak_velocity_m_s": self.peak_velocity_m_s,
            "peak_acceleration_m_s2": self.peak_acceleration_m_s2,
            "peak_torque_nm": self.peak_torque_nm,
            "peak_power_w": self.peak_power_w,
            "max_violation": self.max_violation,
            "solve_time_ms": self.solve_time_s * 1e3,
            "limits": self.limits.to_dict(),
            "message": self.message,
        }


def baseline_move(
    law: str, x0_m: float, x1_m: float, limits: BaselineLimits, duration_s: float | None = None
) -> BaselineMove:
    """The ``law`` profile from rest at ``x0_m`` to rest at ``x1_m`` under ``limits`` (Ruckig), time
    optimal, or stretched to ``duration_s`` [s] (not shorter than the time-optimal duration:
    :class:`InfeasibleMoveError`). The distance must be > 0."""
    from ruckig import InputParameter, Result, Ruckig, Trajectory  # loads with the first baseline

    check_law(law)
    limits = limits.for_law(law)
    if x1_m == x0_m:
        raise MoveError(f"a baseline move needs a distance: x0 = x1 = {x0_m} m")
    inp = InputParameter(1)
    inp.current_position, inp.target_position = [float(x0_m)], [float(x1_m)]
    inp.max_velocity = [limits.velocity_m_s]
    inp.max_acceleration = [limits.acceleration_m_s2]
    inp.max_jerk = [limits.jerk_for(law)]
    otg, traj = Ruckig(1), Trajectory(1)
    result = otg.calculate(inp, traj)
    if result != Result.Working:
        raise MoveError(f"Ruckig cannot compute the {law} move {x0_m:.6g} → {x1_m:.6g} m: {result.name}")
    t_min = float(traj.duration)
    if duration_s is not None and duration_s > t_min:
        inp.minimum_duration = float(duration_s)
        result = otg.calculate(inp, traj)
        if result != Result.Working:
            raise MoveError(
                f"Ruckig cannot stretch the {law} move {x0_m:.6g} → {x1_m:.6g} m to {duration_s} s: "
                f"{result.name}"
            )
    elif duration_s is not None and duration_s < t_min * (1.0 - _STRETCH_RTOL):
        raise InfeasibleMoveError(
            f"duration {duration_s:.6g} s is shorter than the {law}'s time-optimal {t_min:.6g} s for "
            f"{abs(x1_m - x0_m):.6g} m under {limits.describe()}"
        )
    return _move_of(law, float(x0_m), float(x1_m), limits, traj, t_min)


def _move_of(
    law: str, x0: float, x1: float, limits: BaselineLimits, traj: object, t_min: float
) -> BaselineMove:
    """Ruckig's profile as phases, those of zero length left out."""
    prof = traj.profiles[0][0]  # type: ignore[attr-defined]  # one section, one degree of freedom
    t = np.asarray(prof.t, dtype=float)
    keep = t > 0.0
    edges = np.concatenate([[0.0], np.cumsum(t[keep])])
    return BaselineMove(
        law=law,
        x0_m=x0,
        x1_m=x1,
        limits=limits,
        start_s=edges,
        position_m=np.asarray(prof.p, dtype=float)[:-1][keep],
        velocity_m_s=np.asarray(prof.v, dtype=float)[:-1][keep],
        acceleration_m_s2=np.asarray(prof.a, dtype=float)[:-1][keep],
        jerk_m_s3=np.asarray(prof.j, dtype=float)[keep],
        min_duration_s=t_min,
    )


def _peaks(move: BaselineMove, params: AxisParams) -> tuple[float, float, float, float]:
    """(|ẋ|, |ẍ|, |τ_m|, F·ẋ) peaks over every phase, its two ends included with its own values."""
    v_pk = a_pk = tau_pk = p_pk = 0.0
    u = np.linspace(0.0, 1.0, _PHASE_POINTS)
    for k, span in enumerate(np.diff(move.start_s)):
        s = move.phase_states(k, u * span)
        force = cart_force(s.velocity_m_s, s.acceleration_m_s2, params)
        v_pk = max(v_pk, float(np.max(np.abs(s.velocity_m_s))))
        a_pk = max(a_pk, float(np.max(np.abs(s.acceleration_m_s2))))
        tau_pk = max(tau_pk, float(np.max(np.abs(motor_torque(force, params)))))
        power = motor_torque(force, params) * motor_speed(s.velocity_m_s, params)
        p_pk = max(p_pk, float(np.max(power)))
    return v_pk, a_pk, tau_pk, p_pk


def plan_baseline(
    law: str,
    x0_m: float,
    x1_m: float,
    limits: BaselineLimits,
    params: AxisParams,
    duration_s: float | None = None,
) -> BaselinePlan:
    """The ``law`` move x0 → x1 under ``limits`` (time optimal, or stretched to ``duration_s``), scored
    on the axis model: energy, peaks, the 1 kHz limit check. A move shorter than one encoder count is
    a zero move (duration 0, energy 0), as for the other laws."""
    check_law(law)
    limits = limits.for_law(law)
    for name, x in (("x0_m", x0_m), ("x1_m", x1_m)):
        if not math.isfinite(x) or not 0.0 <= x <= params.L:
            raise MoveError(f"{name} = {x} m is outside the stroke [0, {params.L}] m")
    acc = params.energy_accounting
    if abs(x1_m - x0_m) < encoder_resolution_m(params.r):
        return BaselinePlan(
            law, x0_m, x1_m, limits, None, 0.0, 0.0, 0.0, acc, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
            f"zero move: |x1 - x0| = {abs(x1_m - x0_m):.3g} m is shorter than one encoder count",
        )  # fmt: skip
    t0 = time.perf_counter()
    move = baseline_move(law, x0_m, x1_m, limits, duration_s)
    solve = time.perf_counter() - t0
    v_pk, a_pk, tau_pk, p_pk = _peaks(move, params)
    what = "stretched from" if move.stretched else "time-optimal"
    return BaselinePlan(
        law=law,
        x0_m=x0_m,
        x1_m=x1_m,
        limits=limits,
        move=move,
        duration_s=move.duration_s,
        min_duration_s=move.min_duration_s,
        energy_j=motion_energy(move, params, move.breaks_s, acc),
        accounting=acc,
        peak_velocity_m_s=v_pk,
        peak_acceleration_m_s2=a_pk,
        peak_torque_nm=tau_pk,
        peak_power_w=p_pk,
        max_violation=check_limits(move, params).max_violation,
        solve_time_s=solve,
        message=f"{law} by Ruckig, {what} {move.min_duration_s:.6g} s under {limits.describe()}",
    )
