"""The excitation run for identification: bursts of sinusoids that make every parameter of eq. (1)
visible in the measured torque.

What the fit needs (eq. (1): τ_m = (r/i_r)·(M_eq·ẍ + a1·sign ẋ + a2·ẋ + a3·atan(a4·ẋ))):

* speeds from near zero, where a1·sign and a3·atan(a4·ẋ) differ (above |ẋ| ≈ 3/a4 the atan term is
  almost a constant and the two are collinear), up to most of what the axis can sustain, where a2·ẋ
  dominates; both directions;
* accelerations that vary independently of the speed, so that M_eq·ẍ is not confounded with the
  friction terms (in a sinusoid ẍ peaks where ẋ = 0 and vice versa, and the same speed is reached at
  two frequencies, i.e. with two accelerations);
* several periods at each setting, so that the fit averages noise and start-up transients.

So the excitation is a sequence of **bursts**, each a rest-to-rest move around the centre c:

    x(t) = c + A(t)·sin(ω·t),  A(t) = A·S(t/τ) on the ramp up, A on the hold, A·S((T − t)/τ) down,

with S(u) = 10u³ − 15u⁴ + 6u⁵ (zero slope and curvature at both ends) and τ one period, so a burst
starts and ends at rest at c with zero acceleration, and bursts follow each other with no jump. Each
burst is set by its velocity amplitude V = A·ω: a geometric ladder of V from :data:`SLOW_SPEED_M_S` up
to the fastest the limits allow, each at a *slow* frequency (:data:`MIN_FREQUENCY_HZ`, or higher when
the stroke does not allow the amplitude) and at a *fast* one (the largest acceleration the torque
margin allows, at most :data:`MAX_FREQUENCY_HZ`), when the two differ. The peak nominal torque of
every burst is checked at its 1 kHz samples against ``torque_margin``·tau_max (the plant's friction
may be higher than nominal: the margin leaves the controller room), and its path against the
stroke; the bridge validates it again.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..model import (
    EXECUTION_PERIOD_S,
    AxisParams,
    MoveError,
    SampledTrajectory,
    check_limits,
    forward_friction,
)

SLOW_SPEED_M_S = 0.01
"""the lowest velocity amplitude of a burst [m/s]"""
MIN_FREQUENCY_HZ = 0.25
MAX_FREQUENCY_HZ = 0.5
"""the frequency band of the bursts [Hz]. Low on purpose: around each reversal of the motion the cart
sticks and the drive's position loop kicks it free, a transient of a few hundred milliseconds that
eq. (1) does not describe and the fit leaves out (see :mod:`.preparation`); a half period of 1–2 s
keeps most of each swing usable"""
SPEED_LEVELS = 8
"""velocity amplitudes in the geometric ladder"""
DEFAULT_DURATION_S = 120.0
"""the default length of a run [s] (with the defaults, the shortest run is about 110 s)"""
MIN_HOLD_PERIODS = 1
DEFAULT_TORQUE_MARGIN = 0.8
DEFAULT_SPEED_MARGIN = 0.8
_STROKE_MARGIN_M = 0.02


@dataclass(frozen=True)
class Burst:
    """One setting: velocity amplitude V = A·ω, frequency and the periods held at full amplitude."""

    amplitude_m: float
    frequency_hz: float
    hold_periods: int

    @property
    def omega_rad_s(self) -> float:
        return 2.0 * math.pi * self.frequency_hz

    @property
    def speed_m_s(self) -> float:
        """velocity amplitude V = A·ω [m/s]"""
        return self.amplitude_m * self.omega_rad_s

    @property
    def duration_s(self) -> float:
        """hold periods plus one period of ramp at each end [s], rounded up to whole ticks"""
        raw = (self.hold_periods + 2) / self.frequency_hz
        return math.ceil(raw / EXECUTION_PERIOD_S - 1e-9) * EXECUTION_PERIOD_S

    def trajectory(self, center_m: float, step_s: float = EXECUTION_PERIOD_S) -> SampledTrajectory:
        """The burst as knots ``step_s`` apart (1 ms: executed exactly at the drive's ticks)."""
        T = self.duration_s
        n = round(T / step_s)
        t = np.arange(n + 1) * (T / n)
        w = self.omega_rad_s
        tau = 1.0 / self.frequency_hz
        a, da, dda = _envelope(t, T, tau)
        a, da, dda = self.amplitude_m * a, self.amplitude_m * da, self.amplitude_m * dda
        s, c = np.sin(w * t), np.cos(w * t)
        x = center_m + a * s
        v = da * s + a * w * c
        acc = dda * s + 2.0 * da * w * c - a * w * w * s
        x[0] = x[-1] = center_m  # exactly at rest at the centre (rounding of sin at the ends)
        v[0] = v[-1] = 0.0
        acc[0] = acc[-1] = 0.0
        return SampledTrajectory(t, x, v, acc)


def _envelope(t: np.ndarray, T: float, tau: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """S ramps of length τ at both ends of [0, T], 1 between: value, first and second derivative."""
    up = np.clip(t / tau, 0.0, 1.0)
    down = np.clip((T - t) / tau, 0.0, 1.0)
    s_up, d_up, dd_up = _smoothstep(up)
    s_dn, d_dn, dd_dn = _smoothstep(down)
    rising = t < tau
    falling = t > T - tau
    value = np.where(rising, s_up, np.where(falling, s_dn, 1.0))
    slope = np.where(rising, d_up / tau, np.where(falling, -d_dn / tau, 0.0))
    curve = np.where(rising, dd_up / tau**2, np.where(falling, dd_dn / tau**2, 0.0))
    return value, slope, curve


def _smoothstep(u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """S(u) = 10u³ − 15u⁴ + 6u⁵ and its two derivatives."""
    return (
        u**3 * (10.0 - 15.0 * u + 6.0 * u * u),
        30.0 * u * u * (1.0 - u) ** 2,
        60.0 * u * (1.0 - u) * (1.0 - 2.0 * u),
    )


@dataclass(frozen=True)
class ExcitationPlan:
    """The bursts of one excitation run around ``center_m``."""

    center_m: float
    bursts: tuple[Burst, ...]
    torque_margin: float

    @property
    def duration_s(self) -> float:
        return math.fsum(b.duration_s for b in self.bursts)

    def trajectories(self) -> list[SampledTrajectory]:
        return [b.trajectory(self.center_m) for b in self.bursts]

    def to_json(self) -> dict[str, object]:
        return {
            "center_m": self.center_m,
            "duration_s": self.duration_s,
            "torque_margin": self.torque_margin,
            "bursts": [
                {
                    "speed_m_s": b.speed_m_s,
                    "amplitude_m": b.amplitude_m,
                    "frequency_hz": b.frequency_hz,
                    "hold_periods": b.hold_periods,
                    "duration_s": b.duration_s,
                }
                for b in self.bursts
            ],
        }


def design_excitation(
    params: AxisParams,
    duration_s: float = DEFAULT_DURATION_S,
    center_m: float | None = None,
    torque_margin: float = DEFAULT_TORQUE_MARGIN,
    speed_margin: float = DEFAULT_SPEED_MARGIN,
) -> ExcitationPlan:
    """The bursts (see the module docstring) for an axis, lasting about ``duration_s`` in all (at
    least :data:`MIN_HOLD_PERIODS` held periods per burst: a shorter request gives the shortest run).

    ``torque_margin`` and ``speed_margin`` (fractions of tau_max and v_max) bound every burst with the
    nominal parameters. Raises :class:`MoveError` for impossible settings.
    """
    c = params.L / 2.0 if center_m is None else float(center_m)
    for name, value, lo, hi, unit in (
        ("duration", duration_s, 5.0, 3600.0, "s"),
        ("torque margin", torque_margin, 0.1, 1.0, "of tau_max"),
        ("speed margin", speed_margin, 0.1, 1.0, "of v_max"),
    ):
        if not math.isfinite(value) or not lo <= value <= hi:
            raise MoveError(f"excitation {name} = {value} {unit} is outside [{lo}, {hi}] {unit}")
    a_max = min(c, params.L - c) - _STROKE_MARGIN_M
    if not a_max > 0.0:
        raise MoveError(
            f"excitation centre = {c} m leaves no room in the stroke [0, {params.L}] m "
            f"(it needs more than {_STROKE_MARGIN_M} m on each side)"
        )
    settings = _settings(params, a_max, torque_margin, speed_margin)
    bursts = _periods_for(settings, duration_s)
    plan = ExcitationPlan(c, tuple(bursts), torque_margin)
    return plan


_SHRINK = 0.95
"""the factor of each step of the searches for the largest speed and frequency that fit the limits"""
_SHRINK_STEPS = 400
"""their cap: 0.95^400 ≈ 1e-9 spans every v_max of the parameter ranges down to SLOW_SPEED_M_S, and
MAX_FREQUENCY_HZ down to any slow frequency"""


def _settings(params: AxisParams, a_max: float, torque_margin: float, speed_margin: float) -> list[Burst]:
    """(amplitude, frequency) pairs: per velocity level a slow and a fast frequency, slowest first."""
    tau_budget = torque_margin * params.tau_max
    c = params.L / 2.0

    def fits(v: float, f: float) -> bool:
        return _peak_torque(params, Burst(v / (2.0 * math.pi * f), f, MIN_HOLD_PERIODS), c) <= tau_budget

    # the highest level: at the slowest frequency the stroke allows, the burst fits the torque margin
    v_top = speed_margin * params.v_max
    for _ in range(_SHRINK_STEPS):
        if v_top <= SLOW_SPEED_M_S or fits(v_top, _slow_frequency(v_top, a_max)):
            break
        v_top *= _SHRINK
    if v_top <= SLOW_SPEED_M_S or not fits(v_top, _slow_frequency(v_top, a_max)):
        raise MoveError(
            f"no excitation fits the limits: friction at {SLOW_SPEED_M_S} m/s already needs "
            f"{forward_friction(SLOW_SPEED_M_S, params):.4g} N of the {torque_margin * params.f_max:.4g} N "
            "torque margin"
        )
    bursts = []
    for v in np.geomspace(SLOW_SPEED_M_S, v_top, SPEED_LEVELS):
        v = float(v)
        slow = _slow_frequency(v, a_max)
        fast = MAX_FREQUENCY_HZ
        for _ in range(_SHRINK_STEPS):
            if fast <= slow or fits(v, fast):
                break
            fast *= _SHRINK
        bursts.append(Burst(v / (2.0 * math.pi * slow), slow, MIN_HOLD_PERIODS))
        if fast > 1.2 * slow:
            bursts.append(Burst(v / (2.0 * math.pi * fast), fast, MIN_HOLD_PERIODS))
    return bursts


def _slow_frequency(v: float, a_max: float) -> float:
    """the lowest frequency [Hz] at which velocity amplitude v fits the stroke (amplitude ≤ a_max)"""
    return max(MIN_FREQUENCY_HZ, v / (2.0 * math.pi * a_max))


def _peak_torque(params: AxisParams, burst: Burst, center_m: float) -> float:
    """Largest nominal motor torque [N·m] of a burst, ramps included, at its 1 kHz samples."""
    traj = burst.trajectory(center_m)
    return check_limits(traj, params, extra_times_s=traj.t_s).peak_torque_nm


def _periods_for(settings: list[Burst], duration_s: float) -> list[Burst]:
    """Hold periods so that the bursts fill ``duration_s``: the same hold time for every burst (at
    least MIN_HOLD_PERIODS periods each)."""
    ramps = math.fsum(2.0 / b.frequency_hz for b in settings)
    hold_time = max((duration_s - ramps) / len(settings), 0.0)
    out = []
    for b in settings:
        periods = max(MIN_HOLD_PERIODS, round(hold_time * b.frequency_hz))
        out.append(Burst(b.amplitude_m, b.frequency_hz, periods))
    return out
