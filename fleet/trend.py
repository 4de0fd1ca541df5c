"""Trends and the change detector: each axis's parameters over its windows, and wear found in them.

A :class:`Series` is one axis's parameter over its identified windows (status ``ok``), in time order,
with each window's σ. The trended parameters (:data:`TRENDED`) are the Coulomb friction at speed, the
viscous friction a2, M_eq and the energy per metre; the detector watches the friction ones
(:data:`WATCHED`).

The detector (:func:`detect`) is a two-sided CUSUM in units of σ against the axis's own first
windows:

* **baseline**: the first B windows (:attr:`DetectorSettings.baseline_windows`): level μ₀ = their
  median;
* **scale**: a fit's σ counts the noise of its samples, not what changes from day to day; that
  scatter, τ² = max(0, (1.4826·MAD(Δy)/√2)² − median σ²) from the successive differences Δy of the
  whole series (a step moves one of them), is added to every window's: s_i² = σ_i² + τ²;
* **statistic**: z_i = (y_i − μ₀)/s_i for each later window; S⁺_i = max(0, S⁺_(i−1) + z_i − k),
  S⁻_i likewise with −z_i; an alarm where S⁺ or S⁻ exceeds h, its onset the first window of the run
  that crossed (the window after S was last 0), the standard CUSUM change-point estimate;
* **k**, the reference value, is half the smallest shift worth an alarm, in σ units — the larger of
  :attr:`~DetectorSettings.min_shift_sigma` and :attr:`~DetectorSettings.min_change_pct` of μ₀ over
  the baseline's typical s (a change far inside the fits' noise but below the practical threshold,
  a fraction of a per cent, is real, and no engineer would stop a line for it) — plus three σ of the
  baseline's own error (1.2533/√B for a median of B): the run-length formula below assumes a known
  level, and an estimated one is shared by every later window;
* **h**, the decision interval, holds the false alarm rate over the **whole period and fleet**: with
  Siegmund's approximation of a one-sided CUSUM's in-control run length for standard normal z,
  ARL₀(k, h) = (e^(2k·b) − 2k·b − 1)/(2k²), b = h + 1.166, h is the smallest value with
  ARL₀ ≥ 2·N/α: N the windows watched in all (every axis, both parameters, after their baselines),
  α :attr:`~DetectorSettings.false_alarm` (the two sides halve the run length), so that the expected
  number of false alarms over everything is at most α.

The alarm says how large the change is (:attr:`Detection.change_pct`: the median of the last three
windows against μ₀) and how well that is known (:attr:`Detection.sigma_pct`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .errors import FleetValueError
from .fits import FitRow

TRENDED: dict[str, tuple[str, str]] = {
    "coulomb_n": ("Coulomb friction at 0.2 m/s", "N"),
    "a2": ("viscous friction a2", "N·s/m"),
    "M_eq": ("equivalent mass M_eq", "kg"),
    "energy_per_m_j": ("energy per metre travelled", "J/m"),
}
"""parameter → (title, unit) of the trends"""
WATCHED = ("coulomb_n", "a2")
"""the parameters the change detector watches (wear shows in friction)"""
SIEGMUND_OFFSET = 1.166
BASELINE_BOUND = 3.0
SCALE_BOUND = 2.0
MAD_RELATIVE_STD = 1.167
"""a MAD-based standard deviation of n normal values is off by about 1.167/√n (relative): the scatter
is taken at 2 of those above its estimate, so that a series whose scatter happened to look small
does not look like a change"""
MEDIAN_EFFICIENCY = 1.2533
"""the baseline's median is off by about 1.2533·s/√B (σ units): k is raised by 3 of those, so that a
baseline that happened to land low does not look like a change"""
LAST_WINDOWS = 3
"""the change of an alarm: the median of this many last windows against the baseline"""


@dataclass(frozen=True)
class DetectorSettings:
    baseline_windows: int = 5
    min_change_pct: float = 3.0
    """the smallest change worth an alarm [% of the baseline]"""
    min_shift_sigma: float = 3.0
    """the smallest shift worth an alarm in σ units (when the per cent threshold is smaller)"""
    false_alarm: float = 0.01
    """the expected number of false alarms over the whole period and fleet"""

    def __post_init__(self) -> None:
        if not 2 <= self.baseline_windows <= 1000:
            raise FleetValueError(
                f"--baseline {self.baseline_windows} windows must be within [2, 1000] windows"
            )
        if not (math.isfinite(self.min_change_pct) and 0.0 <= self.min_change_pct <= 100.0):
            raise FleetValueError(f"--min-change {self.min_change_pct} % must be within [0, 100] %")
        if not (math.isfinite(self.false_alarm) and 1e-9 <= self.false_alarm <= 1.0):
            raise FleetValueError(f"--false-alarm {self.false_alarm} must be within [1e-09, 1] false alarms")
        if not (math.isfinite(self.min_shift_sigma) and 0.5 <= self.min_shift_sigma <= 100.0):
            raise FleetValueError(f"min shift {self.min_shift_sigma} σ must be within [0.5, 100] σ")


@dataclass(frozen=True, eq=False)
class Series:
    """One axis's parameter over its ok windows, in time order (NaN σ: the parameter has none)."""

    axis: str
    parameter: str
    start_ns: np.ndarray
    end_ns: np.ndarray
    value: np.ndarray
    std: np.ndarray

    def __len__(self) -> int:
        return int(self.value.size)


def series_of(rows: Sequence[FitRow], parameter: str) -> list[Series]:
    """Per axis (sorted), the ok windows' ``parameter`` (see :meth:`FitRow.value`)."""
    by_axis: dict[str, list[FitRow]] = {}
    for r in rows:
        if r.ok:
            by_axis.setdefault(r.axis, []).append(r)
    out = []
    for axis in sorted(by_axis):
        ordered = sorted(by_axis[axis], key=lambda r: r.window_start_ns)
        pairs = [r.value(parameter) for r in ordered]
        out.append(
            Series(
                axis=axis,
                parameter=parameter,
                start_ns=np.array([r.window_start_ns for r in ordered], dtype=np.int64),
                end_ns=np.array([r.window_end_ns for r in ordered], dtype=np.int64),
                value=np.array([p[0] for p in pairs], dtype=float),
                std=np.array([p[1] for p in pairs], dtype=float),
            )
        )
    return out


def decision_interval(k: float, watched_windows: int, false_alarm: float) -> float:
    """The smallest h with Siegmund's ARL₀(k, h) ≥ 2·N/α (see the module docstring), by bisection."""
    target = 2.0 * max(watched_windows, 1) / false_alarm

    def arl(h: float) -> float:
        a = 2.0 * k * (h + SIEGMUND_OFFSET)
        if a > 700.0:
            return math.inf
        return (math.exp(a) - a - 1.0) / (2.0 * k * k)

    lo, hi = 0.0, 1.0
    while arl(hi) < target:
        hi *= 2.0
    if arl(lo) >= target:
        return lo
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if arl(mid) >= target else (mid, hi)
    return hi


@dataclass(frozen=True, eq=False)
class Detection:
    """The detector on one series (see the module docstring); ``alarm`` is None without one."""

    series: Series
    baseline: float
    """μ₀ (the parameter's unit)"""
    extra_scatter: float
    """τ (the parameter's unit)"""
    scale: np.ndarray
    """s_i per window (NaN in the baseline)"""
    z: np.ndarray
    cusum_up: np.ndarray
    cusum_down: np.ndarray
    k: float
    h: float
    alarm: int | None
    """index of the window where the CUSUM crossed h"""
    onset: int | None
    """index of the first window of the change"""
    direction: int
    """+1 up, −1 down, 0 no alarm"""
    change_pct: float
    sigma_pct: float
    baseline_windows: int


def extra_scatter(y: np.ndarray, sigma: np.ndarray) -> float:
    """τ: the scatter from window to window beyond the fits' σ, from the successive differences of the
    whole series (robust: a step moves one difference, a slow ramp all of them a little)."""
    diffs = np.diff(y)
    if diffs.size < 2:
        return 0.0
    spread = 1.4826 * float(np.median(np.abs(diffs - np.median(diffs)))) / math.sqrt(2.0)
    spread *= 1.0 + SCALE_BOUND * MAD_RELATIVE_STD / math.sqrt(diffs.size)
    return math.sqrt(max(spread * spread - float(np.median(sigma**2)), 0.0))


def watched_windows(series: Sequence[Series], settings: DetectorSettings) -> int:
    """N of the false alarm budget: the windows after the baselines of all the watched series."""
    return sum(max(len(s) - settings.baseline_windows, 0) for s in series)


def detect(series: Series, settings: DetectorSettings, watched: int) -> Detection | None:
    """The CUSUM on ``series`` (None: too few windows for a baseline and one more, or no σ)."""
    b = settings.baseline_windows
    y, sigma = series.value, series.std
    if len(series) <= b or not np.all(np.isfinite(sigma[:b])):
        return None
    mu0 = float(np.median(y[:b]))
    tau = extra_scatter(y, sigma)
    s = np.sqrt(sigma**2 + tau**2)
    s_typ = float(np.median(s[:b]))
    if not s_typ > 0:
        return None
    shift = max(settings.min_shift_sigma, settings.min_change_pct / 100.0 * abs(mu0) / s_typ)
    k = 0.5 * shift + BASELINE_BOUND * MEDIAN_EFFICIENCY / math.sqrt(b)
    h = decision_interval(k, watched, settings.false_alarm)
    n = len(series)
    z = np.full(n, np.nan)
    up, down = np.zeros(n), np.zeros(n)
    alarm = onset = None
    direction = 0
    start_up = start_down = b
    for i in range(b, n):
        z[i] = (y[i] - mu0) / s[i] if s[i] > 0 else 0.0
        up[i] = max(0.0, up[i - 1] + z[i] - k)
        down[i] = max(0.0, down[i - 1] - z[i] - k)
        if up[i] == 0.0:
            start_up = i + 1
        if down[i] == 0.0:
            start_down = i + 1
        if alarm is None and (up[i] > h or down[i] > h):
            alarm = i
            direction = 1 if up[i] > h else -1
            onset = start_up if direction > 0 else start_down
    change_pct = sigma_pct = math.nan
    if onset is not None:
        last = y[max(onset, n - LAST_WINDOWS) :]
        change_pct = 100.0 * (float(np.median(last)) - mu0) / mu0
        s_last = float(np.sqrt(np.mean(s[n - last.size :] ** 2) / last.size))
        sigma_pct = 100.0 * math.hypot(s_last, s_typ / math.sqrt(b)) / abs(mu0)
    scale = s.copy()
    scale[:b] = np.nan
    return Detection(
        series, mu0, tau, scale, z, up, down, k, h, alarm, onset, direction, change_pct, sigma_pct, b
    )
