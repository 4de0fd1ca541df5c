"""What the model leaves unexplained: the noise floor, and the residual's spectrum in time and in angle.

The residual is the measured effort minus the model's, e(t) = k_e·(F(t + δ) − F_model(t)), F_model of
the fitted eq. (1) (and extra terms) on the filtered kinematics. It is analysed on the stretches the
fit may use (moving, unsaturated, inside the trimmed span; a missing sample inside a stretch counts
with its interpolated value: one sample in a thousand changes no spectrum), cut into segments of
:data:`SEGMENT_S` (Welch: Hann window, half overlap, periodograms averaged over every segment of every
log).

The spectra average at most :data:`MAX_ANALYSED_S` of the stretches.

* **Noise floor.** Where the model explains the motion, what is left of the measured effort is the
  drive's measurement noise. Its one-sided density N is the median of the unfiltered residual's
  spectrum over :data:`FLOOR_BAND` × the filter's cut-off (above the excitation's content, below the
  cut-off, where the model sees the accelerations; the median ignores lines of what the model misses),
  assumed flat down to 0 Hz. Through the fit's zero-phase filter (power gain |H(f)|⁴) it leaves
  ``noise_floor`` = √(N·∫|H|⁴ df): the filtered error a perfect model would show. A fit whose filtered
  error is near it has explained everything the log can tell.
* **Peaks in Hz.** The unfiltered residual's spectrum over the whole band: lines and humps standing
  out of a running median (±:data:`FLOOR_HALF_WIDTH_HZ`) by :data:`PEAK_RATIO` — an elastic belt's
  resonance, current-loop noise, anything periodic in time.
* **Peaks in cycles per motor revolution.** The same residual resampled at uniform steps of the motor
  angle θ = x·i_r/r (order analysis) on the slower stretches (where 1 kHz samples resolve orders up to
  :data:`MAX_ORDER`), in segments of :data:`ORDER_SEGMENT_REVOLUTIONS` revolutions: cogging and torque
  ripple at their orders (multiples of the motor's slot/pole count), whatever the speed.

Each peak: its frequency (or order), the RMS of the effort it holds above the local floor, and its
height over that floor.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

SEGMENT_S = 1.024
"""length of the time-domain Welch segments [s] (resolution ≈ 1 Hz); halved, down to
:data:`MIN_SEGMENT_S`, until at least :data:`MIN_SEGMENTS` fit into the log's stretches"""
MIN_SEGMENT_S = 0.256
MIN_SEGMENTS = 8
MAX_ANALYSED_S = 300.0
"""the spectra average at most this much of the stretches [s] (in log order): five minutes settle
any spectrum, and an hour-long log is not read a second time"""
FLOOR_BAND = (0.2, 0.6)
"""the band of the noise-floor estimate, as fractions of the filter's cut-off"""
FLOOR_HALF_WIDTH_HZ = 10.0
PEAK_RATIO = 4.0
"""a peak stands this many times above the local median of the spectrum"""
MAX_PEAKS = 5
MAX_ORDER = 64
"""highest order [cycles/rev] the angle-domain spectrum resolves"""
POINTS_PER_REVOLUTION = 4 * MAX_ORDER
ORDER_SEGMENT_REVOLUTIONS = 2
"""length of the angle-domain segments [revolutions] (resolution 0.5 cycles/rev)"""


@dataclass(frozen=True)
class SpectralPeak:
    frequency: float
    """Hz, or cycles per motor revolution"""
    rms: float
    """RMS effort of the peak above the local floor (effort units)"""
    ratio: float
    """the peak's height over the local floor"""


@dataclass(frozen=True, eq=False)
class ResidualAnalysis:
    """What the model leaves unexplained (see the module docstring); efforts in the joint's units."""

    noise_density: float
    """one-sided density of the measurement noise [effort²/Hz] (NaN: no segment long enough)"""
    noise_floor: float
    """the filtered RMS a perfect model would leave: √(noise_density·∫|H|⁴ df)"""
    floor_band_hz: tuple[float, float]
    peaks_hz: tuple[SpectralPeak, ...]
    peaks_order: tuple[SpectralPeak, ...]
    segments: int
    """time-domain segments the spectra averaged"""
    order_segments: int


def analysed_span(spectral: list[np.ndarray], rate_hz: float) -> list[int]:
    """Per log, how many of its first samples hold the stretches the spectra will use (at most
    :data:`MAX_ANALYSED_S` of them in all): the caller computes residuals only there."""
    out, left = [], round(MAX_ANALYSED_S * rate_hz)
    for mask in spectral:
        where = np.flatnonzero(mask)
        if left <= 0 or not where.size:
            out.append(0)
            continue
        out.append(int(where[min(left, where.size) - 1]) + 1)
        left -= min(where.size, left)
    return out


def analyse_residuals(
    residual: list[np.ndarray],
    spectral: list[np.ndarray],
    motor_angle_rad: list[np.ndarray],
    rate_hz: float,
    cutoff_hz: float,
    order: int,
) -> ResidualAnalysis:
    """The analysis of per-log unfiltered residuals (full-rate), ``spectral`` the stretches for the
    spectra, ``motor_angle_rad`` the raw motor angle of each sample (all arrays of a log the same
    length: the span :func:`analysed_span` gives)."""
    nperseg = 1 << round(math.log2(SEGMENT_S * rate_hz))
    while True:
        freqs, psd, segments = _welch_runs(residual, spectral, rate_hz, nperseg)
        if segments >= MIN_SEGMENTS or nperseg // 2 < MIN_SEGMENT_S * rate_hz:
            break
        nperseg //= 2
    band = (FLOOR_BAND[0] * cutoff_hz, FLOOR_BAND[1] * cutoff_hz)
    density, floor = math.nan, math.nan
    peaks: tuple[SpectralPeak, ...] = ()
    if segments:
        in_band = (freqs >= band[0]) & (freqs <= band[1])
        density = float(np.median(psd[in_band]))
        floor = math.sqrt(density * _filter_power_bandwidth(rate_hz, cutoff_hz, order))
        width = max(3, round(FLOOR_HALF_WIDTH_HZ / (freqs[1] - freqs[0])))
        peaks = _peaks(freqs, psd, width, exclude_below=band[0])
    orders, order_psd, order_segments = _order_spectrum(residual, spectral, motor_angle_rad)
    order_peaks: tuple[SpectralPeak, ...] = ()
    if order_segments:
        width = max(3, round(4.0 / (orders[1] - orders[0])))
        order_peaks = _peaks(orders, order_psd, width, exclude_below=1.5)
    return ResidualAnalysis(
        noise_density=density,
        noise_floor=floor,
        floor_band_hz=band,
        peaks_hz=peaks,
        peaks_order=order_peaks,
        segments=segments,
        order_segments=order_segments,
    )


def _runs(mask: np.ndarray, minimum: int) -> list[tuple[int, int]]:
    """(start, stop) of the runs of True in ``mask`` at least ``minimum`` long."""
    edges = np.flatnonzero(np.diff(np.r_[0, mask.astype(np.int8), 0]))
    return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2], strict=True) if b - a >= minimum]


def _welch_runs(
    series: list[np.ndarray], masks: list[np.ndarray], rate_hz: float, nperseg: int
) -> tuple[np.ndarray, np.ndarray, int]:
    """Welch's average over every segment inside every run; (frequencies, one-sided PSD, segments)."""
    from scipy.signal import welch  # scipy loads on first use, not with the package

    total, count = None, 0
    freqs = np.fft.rfftfreq(nperseg, 1.0 / rate_hz)
    for x, mask in zip(series, masks, strict=True):
        for a, b in _runs(mask, nperseg):
            n_seg = 1 + (b - a - nperseg) // (nperseg // 2)
            _f, p = welch(x[a:b], fs=rate_hz, nperseg=nperseg, noverlap=nperseg // 2, detrend="constant")
            total = p * n_seg if total is None else total + p * n_seg
            count += n_seg
    if total is None:
        return freqs, np.zeros_like(freqs), 0
    return freqs, total / count, count


def _filter_power_bandwidth(rate_hz: float, cutoff_hz: float, order: int) -> float:
    """∫|H(f)|⁴ df over [0, rate/2] [Hz]: the zero-phase filter's noise bandwidth."""
    from scipy.signal import butter, sosfreqz  # scipy loads on first use, not with the package

    sos = butter(order, cutoff_hz, fs=rate_hz, output="sos")
    f, h = sosfreqz(sos, worN=1 << 16, fs=rate_hz)
    return float(np.trapezoid(np.abs(h) ** 4, f))


def _peaks(freqs: np.ndarray, psd: np.ndarray, width: int, exclude_below: float) -> tuple[SpectralPeak, ...]:
    """Contiguous stretches of ``psd`` above PEAK_RATIO × its running median, strongest first."""
    from scipy.ndimage import median_filter  # scipy loads on first use, not with the package

    floor = median_filter(psd, size=2 * width + 1, mode="nearest")
    above = (psd > PEAK_RATIO * floor) & (freqs >= exclude_below)
    step = float(freqs[1] - freqs[0])
    found = []
    for a, b in _runs(above, 1):
        excess = float(np.sum(psd[a:b] - floor[a:b])) * step
        top = a + int(np.argmax(psd[a:b]))
        found.append(
            SpectralPeak(float(freqs[top]), math.sqrt(max(excess, 0.0)), float(psd[top] / floor[top]))
        )
    found.sort(key=lambda p: p.rms, reverse=True)
    return tuple(found[:MAX_PEAKS])


def _order_spectrum(
    series: list[np.ndarray], masks: list[np.ndarray], angles: list[np.ndarray]
) -> tuple[np.ndarray, np.ndarray, int]:
    """The residual's spectrum over the motor angle: (orders [cycles/rev], PSD per order, segments)."""
    step = 2.0 * math.pi / POINTS_PER_REVOLUTION
    nperseg = ORDER_SEGMENT_REVOLUTIONS * POINTS_PER_REVOLUTION
    orders = np.fft.rfftfreq(nperseg, 1.0 / POINTS_PER_REVOLUTION)
    total, count = None, 0
    window = np.hanning(nperseg)
    scale = 1.0 / (POINTS_PER_REVOLUTION * np.sum(window**2))
    for x, mask, theta in zip(series, masks, angles, strict=True):
        dtheta = np.abs(np.gradient(theta))
        slow = mask & (dtheta < math.pi / (2 * MAX_ORDER)) & (dtheta > 0)
        for a, b in _runs(slow, 16):
            th = theta[a:b]
            if not (np.all(np.diff(th) > 0) or np.all(np.diff(th) < 0)):
                continue
            if th[0] > th[-1]:
                th, values = th[::-1], x[a:b][::-1]
            else:
                values = x[a:b]
            grid = np.arange(th[0], th[-1], step)
            if grid.size < nperseg:
                continue
            resampled = np.interp(grid, th, values)
            for start in range(0, grid.size - nperseg + 1, nperseg // 2):
                piece = resampled[start : start + nperseg]
                spectrum = np.abs(np.fft.rfft((piece - piece.mean()) * window)) ** 2 * scale
                spectrum[1:-1] *= 2.0
                total = spectrum if total is None else total + spectrum
                count += 1
    if total is None:
        return orders, np.zeros_like(orders), 0
    return orders, total / count, count
