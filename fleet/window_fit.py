"""One window identified: the fleet's one adapter to identification.

:func:`fit_window_row` runs :func:`axisflow.identification.refit.identify` — the code behind
``axisflow identify`` — on the window's logs, restricted to the window's time, with the last
:attr:`FitSettings.holdout` of each log held out for the held-out error, and turns the result into a
:class:`~.fits.FitRow`.

**A fixed structure.** ``axisflow identify`` chooses by default the terms each log supports
(``--terms auto``, :mod:`axisflow.identification.selection`). A fleet's trend needs parameters that
mean the same from window to window: if one day's fit drops the atan term, its a1 takes in what a3
held, and the trend of a1 jumps while the axis has not changed. So every window is fitted with the
same terms — the parameter file's (``--params``; eq. (1)'s Coulomb, viscous and atan friction for
the packaged axis), each of their parameters fitted — with :attr:`FitSettings.stroke_terms` terms of
friction along the stroke, and with the torque/position offset and the cogging orders of the axis's
calibration held (:mod:`.axis_calibration`; without one, the window estimates its own).

It runs on a Dask worker and reads the logs there; what it returns is the small row. A window that
cannot be identified is a row too: ``too_little_motion`` from the catalog's motion figures (no fit is
tried), ``failed`` with the one-line reason of any error.

The Coulomb friction at speed: F(v) = a1 + a2·v + a3·atan(a4·v) at v = :data:`COULOMB_SPEED_M_S`
(:func:`axisflow.model.forward_friction`, the model's law), with σ² = gᵀ·C·g, g = ∂F/∂(a1…a4)
(:func:`axisflow.model.friction.friction_regressors`, the model's parameter Jacobian) and C the fit's
covariance of a1…a4 (σ and correlations of :class:`~axisflow.identification.uncertainty.Uncertainty`).
"""

from __future__ import annotations

import hashlib
import math
import os
import resource
import socket
import time
from dataclasses import dataclass, field

import numpy as np

from ..identification.extra_terms import DEFAULT_STROKE_TERMS, ExtraTerms
from ..identification.refit import Identification, IdentifySettings, identify
from ..identification.signals import TimeWindow
from ..model import AxisflowError, AxisParams, forward_friction, params_to_toml
from ..model.energy import trace_energy_at
from ..model.friction import FRICTION_PARAMETERS, friction_regressors
from .axis_calibration import CALIBRATION_WINDOWS, AxisCalibration
from .fits import DEFAULT_HOLDOUT, FAILED, FITTED, OK, TOO_LITTLE_MOTION, FitRow
from .windows import MotionRule, Window

COULOMB_SPEED_M_S = 0.2
"""the speed at which the Coulomb-like friction is trended [m/s]"""


@dataclass(frozen=True)
class FitSettings:
    """How every window is identified (part of each window's key through :meth:`method`)."""

    nominal: AxisParams
    holdout: float = DEFAULT_HOLDOUT
    """the last fraction of each log kept out of the fit for the held-out error"""
    stroke_terms: int = DEFAULT_STROKE_TERMS
    motion: MotionRule = field(default_factory=MotionRule)

    def identify_settings(self, window: Window, calibration: AxisCalibration | None) -> IdentifySettings:
        """The settings of ``axisflow identify`` for this window's logs: the fixed structure, and the
        calibration's offset and cogging orders held (None: estimated, cogging found in the residual)."""
        first = window.parts[0]
        held = calibration if calibration is not None and calibration.ok else None
        return IdentifySettings(
            topic=first.topic,
            joint=first.joint,
            joint_kind=first.joint_kind or None,
            holdout=self.holdout,
            window=TimeWindow(0.0, (window.end_ns - 1 - window.start_ns) * 1e-9, window.start_ns),
            extra=ExtraTerms(self.stroke_terms, held.orders if held else (), auto_cogging=held is None),
            torque_delay_s=calibration.delay_s if calibration is not None else None,
            select=False,
        )

    def method(self) -> str:
        """What the fit of a window depends on besides its logs: the settings and the nominal
        parameters (a change of either makes every window new)."""
        params = hashlib.blake2b(params_to_toml(self.nominal).encode(), digest_size=8).hexdigest()
        m = self.motion
        return (
            f"identify terms=file holdout={self.holdout:g} stroke_terms={self.stroke_terms} "
            f"calibration={CALIBRATION_WINDOWS} windows "
            f"motion={m.moving_s:g}s/{m.reversals}/{m.speed_high_m_s:g}m/s nominal={params}"
        )


@dataclass(frozen=True)
class WindowResult:
    """What a worker returns for one window: the row and the worker process's peak RSS."""

    row: FitRow
    peak_rss_mb: float


def fit_window_row(
    window: Window, settings: FitSettings, calibration: AxisCalibration | None = None
) -> WindowResult:
    """The row of one window (see the module docstring), with its axis's ``calibration`` held (None:
    none); never raises for a window's own trouble."""
    t0 = time.perf_counter()
    shortfall = settings.motion.shortfall(window.moving_s, window.reversals, window.speed_high_m_s)
    if shortfall:
        row = empty_row(window, TOO_LITTLE_MOTION, shortfall, time.perf_counter() - t0)
    elif len({(p.topic, p.joint, p.joint_kind) for p in window.parts}) > 1:
        row = empty_row(window, FAILED, "the window's logs name the axis's joint differently", 0.0)
    else:
        try:
            ident = identify(
                [p.path for p in window.parts],
                settings.nominal,
                settings.identify_settings(window, calibration),
            )
            row = _fit_row(window, ident, calibration, time.perf_counter() - t0)
        except AxisflowError as exc:
            row = empty_row(window, FAILED, str(exc), time.perf_counter() - t0)
        except Exception as exc:
            row = empty_row(window, FAILED, f"{type(exc).__name__}: {exc}", time.perf_counter() - t0)
    return WindowResult(row, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0)


def _worker_name() -> str:
    return f"{socket.gethostname()}:{os.getpid()}"


def empty_row(window: Window, status: str, reason: str, wall_s: float) -> FitRow:
    nan = math.nan
    values: dict[str, float] = {}
    for name in FITTED:
        values[name] = nan
        values[f"{name}_std"] = nan
    return FitRow(
        key=window.key,
        axis=window.axis,
        window_start_ns=window.start_ns,
        window_end_ns=window.end_ns,
        logs=len(window.parts),
        samples=0,
        samples_used=0,
        **values,
        coulomb_n=nan,
        coulomb_std_n=nan,
        coulomb_sys_std_n=nan,
        energy_per_m_j=nan,
        fit_rms=nan,
        heldout_rms=nan,
        effort_unit="",
        stretch_low_m=nan,
        stretch_high_m=nan,
        torque_delay_s=nan,
        torque_delay_std_s=nan,
        status=status,
        reason=reason,
        wall_s=wall_s,
        worker=_worker_name(),
    )


def coulomb_at_speed(ident: Identification, speed_m_s: float = COULOMB_SPEED_M_S) -> tuple[float, float]:
    """(F(v), σ) at ``speed_m_s`` (see the module docstring)."""
    values = ident.fit.values
    unc = ident.uncertainty
    force = float(forward_friction(speed_m_s, values))
    gradient = friction_regressors(speed_m_s, values)[0]
    names = [n for n in FRICTION_PARAMETERS if n in unc.names]
    if not names:
        return force, 0.0
    index = [unc.names.index(n) for n in names]
    g = np.array([gradient[FRICTION_PARAMETERS.index(n)] for n in names])
    std = np.array([unc.std[n] for n in names])
    cov = unc.correlation[np.ix_(index, index)] * np.outer(std, std)
    return force, math.sqrt(max(float(g @ cov @ g), 0.0))


def energy_per_metre(ident: Identification) -> float:
    """Energy the drive put in per metre travelled over the window's samples [J/m]: the measured
    force times the velocity (the filtered position's derivative), counted with the nominal
    parameters' accounting, over the distance."""
    energy = distance = 0.0
    accounting = ident.nominal.energy_accounting
    for log in ident.logs:
        t, v, f = log.signals.t_s, log.velocity_m_s, log.signals.force_n
        energy += trace_energy_at(t, v, f, accounting)
        distance += float(np.sum(np.abs(v[1:] + v[:-1]) * 0.5 * np.diff(t)))
    return energy / distance if distance > 0 else math.nan


def _fit_row(
    window: Window, ident: Identification, calibration: AxisCalibration | None, wall_s: float
) -> FitRow:
    values = ident.fit.values.as_dict()
    std = ident.uncertainty.std
    columns: dict[str, float] = {}
    for name in FITTED:
        columns[name] = float(values[name])
        columns[f"{name}_std"] = float(std.get(name, math.nan))
    coulomb, coulomb_std = coulomb_at_speed(ident)
    heldout = ident.errors.get("validation")
    if ident.delay is not None:  # estimated here: its own σ, no systematic part known
        delay_std, coulomb_sys = ident.delay.std_s, math.nan
    else:
        assert calibration is not None  # the offset is held only from a calibration
        delay_std, coulomb_sys = calibration.torque_delay_std_s, calibration.coulomb_n_sys_std
    return FitRow(
        key=window.key,
        axis=window.axis,
        window_start_ns=window.start_ns,
        window_end_ns=window.end_ns,
        logs=len(window.parts),
        samples=int(sum(log.signals.observed.sum() for log in ident.logs)),
        samples_used=ident.window_fit.samples,
        **columns,
        coulomb_n=coulomb,
        coulomb_std_n=coulomb_std,
        coulomb_sys_std_n=coulomb_sys,
        energy_per_m_j=energy_per_metre(ident),
        fit_rms=ident.errors["fit"].rms,
        heldout_rms=heldout.rms if heldout is not None else math.nan,
        effort_unit=ident.kind.effort_unit,
        stretch_low_m=ident.stretch_m[0],
        stretch_high_m=ident.stretch_m[1],
        torque_delay_s=ident.delay_s,
        torque_delay_std_s=delay_std,
        status=OK,
        reason="",
        wall_s=wall_s,
        worker=_worker_name(),
    )
