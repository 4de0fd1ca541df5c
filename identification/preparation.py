"""From measured signals to the samples the fit uses: zero-phase filtering, derivatives, trimming,
stationary samples, decimation.

1. **One zero-phase filter on every signal the fit uses.** Position and force are filtered by the same
   Butterworth low-pass (order :attr:`PreparationSettings.order`, cut-off ``cutoff_hz``) run forwards
   and backwards (``sosfiltfilt``: no phase lag, squared magnitude response). Velocity and acceleration
   are the first and second derivatives of the filtered position (central differences), so all
   signals have passed the same filter and none leads or lags another. (The measured velocity of the
   log is not used: a drive's velocity is its own filtered estimate, with its own lag.)
2. **Edges trimmed**: ``trim_s`` at both ends of each log, where the forward-backward filter has
   transients.
3. **Stationary samples excluded**: where |ẋ| < ``stationary_speed_m_s`` the cart sticks or creeps
   (static friction, which eq. (1) does not model: its a1·sign(ẋ) jumps at ẋ = 0), and after a stick
   the drive's position loop kicks the cart free, a transient of a few hundred milliseconds (measured
   on the simulated drive: fits with a 0.05 s guard are biased by up to 0.5 %, with 0.3 s they are
   not); so those samples and ``guard_s`` around them are left out and counted. So are samples where
   the drive's effort is at its limit (``saturation_fraction`` of tau_max: a saturated drive does not
   track, and its torque steps are sharper than the filter), and samples that were not finite in the
   log.
   **Holes** (samples missing from the log, filled by interpolation on the grid, :mod:`.signals`): no
   filter output or derivative that a hole touches is fitted. The filter's reach is measured, not
   assumed: :func:`filter_reach_s` is the half-width of the window holding 99 % of the impulse
   response (by absolute area) of the acceleration's chain (zero-phase filter, two central
   differences) — 0.13 s at 15 Hz — and that much is left out on both sides of every hole (and of
   every non-finite sample), counted as ``near_holes``.
4. **Decimated** to ``fit_rate_hz`` for the fit (the filter has removed everything above the cut-off:
   the decimated samples carry the same information, and neighbouring residuals are less correlated).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from .errors import IdentificationError
from .signals import JointSignals

MIN_FIT_SAMPLES = 200


@dataclass(frozen=True)
class PreparationSettings:
    cutoff_hz: float = 15.0
    """cut-off of the zero-phase low-pass [Hz] (the excitation's content is below ~5 Hz)"""
    order: int = 4
    stationary_speed_m_s: float = 0.002
    """below this speed a sample counts as stationary [m/s]"""
    guard_s: float = 0.3
    """left out on both sides of a stationary or saturated stretch [s] (stick, release, filter tail)"""
    saturation_fraction: float = 0.97
    """an effort at or above this fraction of the drive's limit counts as saturated"""
    trim_s: float = 0.5
    """left out at both ends of each log [s] (filter transients)"""
    fit_rate_hz: float = 100.0
    """rate of the samples handed to the fit [Hz]"""

    def __post_init__(self) -> None:
        for name, value, lo, unit in (
            ("cutoff_hz", self.cutoff_hz, 0.1, "Hz"),
            ("stationary_speed_m_s", self.stationary_speed_m_s, 0.0, "m/s"),
            ("guard_s", self.guard_s, 0.0, "s"),
            ("trim_s", self.trim_s, 0.0, "s"),
            ("fit_rate_hz", self.fit_rate_hz, 1.0, "Hz"),
            ("saturation_fraction", self.saturation_fraction, 0.1, ""),
        ):
            if not math.isfinite(value) or value < lo:
                raise IdentificationError(f"{name} = {value} {unit} must be a finite number >= {lo} {unit}")


@dataclass(frozen=True, eq=False)
class PreparedLog:
    """One log after filtering: full-rate filtered signals and the mask of samples the fit may use."""

    signals: JointSignals
    position_m: np.ndarray
    velocity_m_s: np.ndarray
    acceleration_m_s2: np.ndarray
    force_n: np.ndarray
    """filtered force [N] (the raw one is ``signals.force_n``)"""
    usable: np.ndarray
    """True for samples inside the trimmed span, moving, unsaturated, finite"""
    moving: np.ndarray
    """True for samples inside the trimmed span, moving and unsaturated (holes not left out: the
    stretches a spectrum of the residual may use)"""
    trimmed: int
    stationary: int
    """samples left out as stationary (with their guard), inside the trimmed span"""
    saturated: int
    """samples left out as saturated (with their guard), inside the trimmed span and moving"""
    near_holes: int = 0
    """samples left out because a filter output or derivative there reaches a hole (or a non-finite
    sample), inside the trimmed span and not already left out as stationary or saturated"""
    left_out: np.ndarray | None = None
    """why each sample is left out (uint8, an index into :data:`LEFT_OUT`; 0: usable)"""

    def force_at(self, indices: np.ndarray, delay_s: float = 0.0) -> np.ndarray:
        """The filtered force at samples ``indices``, taken ``delay_s`` later (interpolated): a drive
        whose torque sample describes the tick before its position sample needs a positive delay."""
        if delay_s == 0.0:
            return self.force_n[indices]
        t = self.signals.t_s
        return np.interp(t[indices] + delay_s, t, self.force_n)

    def fit_indices(self, rate_hz: float, keep: np.ndarray | None = None) -> np.ndarray:
        """Indices of usable samples decimated to ``rate_hz`` (and inside ``keep``, if given)."""
        step = max(1, round(self.signals.rate_hz / rate_hz))
        mask = self.usable if keep is None else self.usable & keep
        picked = np.zeros_like(mask)
        picked[::step] = True
        return np.flatnonzero(mask & picked)


def prepare(signals: JointSignals, settings: PreparationSettings, effort_limit: float) -> PreparedLog:
    """Filter, differentiate and mark the samples of one log (see the module docstring);
    ``effort_limit`` is the drive's limit in the joint's effort units (tau_max [N·m], F_max [N])."""
    from scipy.signal import butter, sosfiltfilt  # scipy loads on first use, not with the package

    rate = signals.rate_hz
    if settings.cutoff_hz >= 0.5 * rate:
        raise IdentificationError(
            f"filter cut-off {settings.cutoff_hz:g} Hz must be below half the log's rate ({0.5 * rate:g} Hz)"
        )
    sos = butter(settings.order, settings.cutoff_hz, fs=rate, output="sos")
    pad = min(3 * round(rate / settings.cutoff_hz), len(signals.t_s) - 1)
    x = sosfiltfilt(sos, signals.position_m, padlen=pad)
    force = sosfiltfilt(sos, signals.force_n, padlen=pad)
    v = np.gradient(x, signals.t_s)
    a = np.gradient(v, signals.t_s)
    t = signals.t_s
    trim = round(settings.trim_s * rate)  # by index: the grid's fitted times differ in the last bits
    inside = np.zeros(t.size, dtype=bool)
    inside[trim : t.size - trim] = True
    guard = round(settings.guard_s * rate)
    still = _dilate(np.abs(v) < settings.stationary_speed_m_s, guard)
    effort = np.abs(signals.force_n * signals.effort_per_force)
    saturated = _dilate(effort >= settings.saturation_fraction * effort_limit, guard) & ~still
    reach = round(filter_reach_s(settings.cutoff_hz, rate, settings.order) * rate)
    holes = _dilate(~signals.finite | ~signals.observed, reach) & ~still & ~saturated
    moving = inside & ~still & ~saturated
    usable = moving & ~holes
    left_out = np.zeros(t.size, dtype=np.uint8)  # the first reason that applies, in LEFT_OUT's order
    for code, mask in reversed(
        list(enumerate((~signals.observed, ~signals.finite, ~inside, still, saturated, holes), start=1))
    ):
        left_out[mask] = code
    return PreparedLog(
        signals=signals,
        position_m=x,
        velocity_m_s=v,
        acceleration_m_s2=a,
        force_n=force,
        usable=usable,
        moving=moving,
        trimmed=int(np.count_nonzero(~inside)),
        stationary=int(np.count_nonzero(inside & still)),
        saturated=int(np.count_nonzero(inside & saturated)),
        near_holes=int(np.count_nonzero(inside & holes)),
        left_out=left_out,
    )


LEFT_OUT = ("", "missing", "not finite", "edge", "stationary", "saturated", "near a hole")
"""why a sample is left out of the fit (:attr:`PreparedLog.left_out`): a sample missing from the log
(filled by interpolation), not finite, within ``trim_s`` of a log's end, stationary (or within
``guard_s`` of it), saturated (or within ``guard_s``), within a filter's reach of a hole"""


@functools.lru_cache(maxsize=16)
def filter_reach_s(cutoff_hz: float, rate_hz: float, order: int = 4, share: float = 0.99) -> float:
    """Half-width [s] of the window around a sample that holds ``share`` of the absolute impulse
    response of the acceleration estimate (zero-phase Butterworth, then two central differences): how
    far a hole's filled values reach into the fitted signals."""
    from scipy.signal import butter, sosfiltfilt  # scipy loads on first use, not with the package

    n = 2 * round(8.0 * rate_hz / cutoff_hz) + 1
    impulse = np.zeros(n)
    impulse[n // 2] = 1.0
    sos = butter(order, cutoff_hz, fs=rate_hz, output="sos")
    response = np.abs(np.gradient(np.gradient(sosfiltfilt(sos, impulse, padlen=0))))
    total = float(response.sum())
    middle = n // 2
    for half in range(middle + 1):
        if response[middle - half : middle + half + 1].sum() >= share * total:
            return half / rate_hz
    return middle / rate_hz


MAX_VELOCITY_LAG_S = 0.02
LAG_SAMPLES = 100_000
"""at most this many samples (evenly chosen) decide the lag: it is a property of the whole log"""


def logged_velocity_lag_s(log: PreparedLog) -> float | None:
    """How far the log's own velocity lags the derivative of the filtered position [s] (a drive's
    low-passed estimate lags by about 1/(2π·f_c)); None for a log without velocities. The lag is the
    shift that brings the two closest (least mean square difference over the moving samples where both
    exist, ±:data:`MAX_VELOCITY_LAG_S`, refined by a parabola through the best three shifts)."""
    logged = log.signals.velocity_m_s
    valid = np.isfinite(logged)
    if not log.signals.velocity_logged:
        return None
    rate = log.signals.rate_hz
    reach = round(MAX_VELOCITY_LAG_S * rate)
    n = logged.size
    idx = np.flatnonzero(log.moving & valid)
    idx = idx[(idx >= reach) & (idx < n - reach)]
    if idx.size < 10 * reach:
        return None
    idx = idx[:: max(1, idx.size // LAG_SAMPLES)]
    reference = log.velocity_m_s[idx]
    costs = []
    for lag in range(-reach, reach + 1):
        both = valid[idx + lag]
        costs.append(float(np.mean((logged[idx + lag][both] - reference[both]) ** 2)))
    scores = np.array(costs)
    best = int(np.argmin(scores))
    shift = float(best - reach)
    if 0 < best < scores.size - 1:
        left, middle, right = scores[best - 1 : best + 2]
        curvature = left - 2.0 * middle + right
        if curvature > 0.0:
            shift += 0.5 * (left - right) / curvature
    return shift / rate


def _dilate(mask: np.ndarray, width: int) -> np.ndarray:
    """``mask`` widened by ``width`` samples on both sides."""
    if width <= 0 or not mask.any():
        return mask
    kernel = np.ones(2 * width + 1)
    return np.convolve(mask.astype(float), kernel, mode="same") > 0.5


@dataclass(frozen=True, eq=False)
class FitSamples:
    """The samples handed to the fit: filtered kinematics and force, decimated, from every log; and the
    columns of any extra linear terms (:mod:`.extra_terms`) at the same samples."""

    velocity_m_s: np.ndarray
    acceleration_m_s2: np.ndarray
    force_n: np.ndarray
    effort_per_force: float
    extra: np.ndarray | None = None
    """(n, p): cart force [N] per unit of each extra coefficient (None: no extra terms)"""

    def __len__(self) -> int:
        return int(self.velocity_m_s.size)


def fit_indices(
    logs: list[PreparedLog], rate_hz: float, keep: list[np.ndarray] | None = None
) -> list[np.ndarray]:
    """Per log, the decimated usable samples (restricted to ``keep[i]``); an error if too few."""
    parts = [log.fit_indices(rate_hz, None if keep is None else keep[i]) for i, log in enumerate(logs)]
    n = sum(p.size for p in parts)
    if n < MIN_FIT_SAMPLES:
        raise IdentificationError(
            f"only {n} samples are left to fit after trimming and leaving out stationary ones (at least "
            f"{MIN_FIT_SAMPLES} are needed at {rate_hz:g} Hz): the log has too little motion"
        )
    return parts


class Columns(Protocol):
    """The columns of extra linear terms of one log (:class:`~.extra_terms.TermColumns`)."""

    def at(self, idx: np.ndarray) -> np.ndarray: ...


def fit_samples(
    logs: list[PreparedLog],
    parts: list[np.ndarray],
    delay_s: float = 0.0,
    extra: Sequence[Columns] | None = None,
) -> FitSamples:
    """Concatenate the samples ``parts[i]`` of each log, the force taken ``delay_s`` later (and the
    extra terms' columns ``extra[i]`` at the same samples)."""
    scales = {log.signals.effort_per_force for log in logs}
    if len(scales) != 1:
        raise IdentificationError("the logs mix motor and carriage joints: fit one kind at a time")
    return FitSamples(
        velocity_m_s=np.concatenate([log.velocity_m_s[p] for log, p in zip(logs, parts, strict=True)]),
        acceleration_m_s2=np.concatenate(
            [log.acceleration_m_s2[p] for log, p in zip(logs, parts, strict=True)]
        ),
        force_n=np.concatenate([log.force_at(p, delay_s) for log, p in zip(logs, parts, strict=True)]),
        effort_per_force=scales.pop(),
        extra=None if extra is None else np.concatenate([c.at(p) for c, p in zip(extra, parts, strict=True)]),
    )
