"""A refit from logs, end to end: read, prepare, align, fit, judge — the result object of ``identify``.

:func:`identify` reads the joint of every log (:mod:`.signals`), prepares it (:mod:`.preparation`),
estimates the torque/position time offset unless it is given (:mod:`.alignment`), fits the chosen
parameters by SQP (:mod:`.fit`), estimates their uncertainty (:mod:`.uncertainty`), and measures the
effort error of the refit and of the nominal parameters side by side, on the fitted samples and on
validation samples: a separate log (``validate``) or the last ``holdout`` fraction of each log, which
is then left out of the fit.

Errors are measured minus model effort at every usable sample (1 kHz, not decimated), both through the
same zero-phase filter as the fit (:mod:`.preparation`): a drive's torque carries content above the
filter's cut-off (its position loop acting on encoder steps) that no rigid-body model predicts; the
RMS of the unfiltered error is reported beside it.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..acquisition.wire.keys import AxisKeys, topic_for_key
from ..model import AxisParams
from .alignment import estimate_delay
from .fit import PARAMETERS, FitResult, FrictionValues, check_fit_names, fit_parameters
from .preparation import PreparationSettings, PreparedLog, fit_indices, fit_samples, prepare
from .signals import IdentificationError, JointKind, TimeWindow, joint_kind, load_joint
from .uncertainty import Uncertainty, estimate_uncertainty

DEFAULT_TOPIC = topic_for_key(AxisKeys().state)
DEFAULT_JOINT = "motor"


@dataclass(frozen=True)
class IdentifySettings:
    topic: str = DEFAULT_TOPIC
    joint: str = DEFAULT_JOINT
    joint_kind: str | None = None
    """motor or carriage; None: from the joint's name"""
    fit: tuple[str, ...] = PARAMETERS
    preparation: PreparationSettings = field(default_factory=PreparationSettings)
    torque_delay_s: float | None = None
    """the torque/position offset [s]; None: estimated"""
    holdout: float = 0.0
    """the last fraction of each log kept for validation (0: none)"""
    window: TimeWindow = field(default_factory=TimeWindow)
    """the part of each fitted log to use (default: all of it; validation logs are used whole)"""

    def __post_init__(self) -> None:
        object.__setattr__(self, "fit", check_fit_names(tuple(self.fit)))
        if not (math.isfinite(self.holdout) and 0.0 <= self.holdout < 0.9):
            raise IdentificationError(f"holdout = {self.holdout} must be a fraction in [0, 0.9)")
        if self.torque_delay_s is not None and not abs(self.torque_delay_s) <= 0.1:
            raise IdentificationError(f"torque delay = {self.torque_delay_s} s must be within ±0.1 s")


@dataclass(frozen=True)
class ErrorStats:
    """Measured minus model effort over some samples (units of the joint's effort: N·m or N)."""

    rms: float
    max_abs: float
    nrmse_pct: float
    """RMS error as a percentage of the RMS measured effort"""
    samples: int
    rms_unfiltered: float

    def to_json(self, kind: JointKind) -> dict[str, float | int]:
        u = kind.effort_key
        return {
            f"rms_{u}": self.rms,
            f"max_abs_{u}": self.max_abs,
            "nrmse_pct": self.nrmse_pct,
            "samples": self.samples,
            f"rms_unfiltered_{u}": self.rms_unfiltered,
        }


@dataclass(frozen=True, eq=False)
class Identification:
    """Everything :func:`identify` found (see the module docstring)."""

    settings: IdentifySettings
    nominal: AxisParams
    params: AxisParams
    """the nominal parameters with the refit ones (M_eq through the cart mass m)"""
    logs: tuple[PreparedLog, ...]
    fit: FitResult
    uncertainty: Uncertainty
    delay_s: float
    delay_estimated: bool
    errors: dict[str, ErrorStats]
    """'fit', 'fit_nominal' and, with validation, 'validation', 'validation_nominal'"""
    validation_source: str
    validation_logs: tuple[PreparedLog, ...]
    timing_s: dict[str, float]

    @property
    def kind(self) -> JointKind:
        return self.logs[0].signals.kind

    def traces(self, validation: bool = False) -> list[EffortTrace]:
        """Per log, measured and model effort over time (the paper's Fig. 2 data)."""
        logs = self.validation_logs if validation else self.logs
        out = []
        for log in logs:
            k = log.signals.effort_per_force
            everything = np.arange(len(log.signals.t_s))
            out.append(
                EffortTrace(
                    source=log.signals.source,
                    t_s=log.signals.t_s,
                    measured=k * log.force_at(everything, self.delay_s),
                    refit=k * self.fit.values.force_n(log.velocity_m_s, log.acceleration_m_s2),
                    nominal=k * self.fit.initial.force_n(log.velocity_m_s, log.acceleration_m_s2),
                    usable=log.usable,
                    unit=log.signals.kind.effort_unit,
                )
            )
        return out


@dataclass(frozen=True, eq=False)
class EffortTrace:
    """One log's effort over time: measured (filtered, aligned), the refit and the nominal model."""

    source: str
    t_s: np.ndarray
    measured: np.ndarray
    refit: np.ndarray
    nominal: np.ndarray
    usable: np.ndarray
    unit: str


def identify(
    paths: Sequence[str | Path],
    nominal: AxisParams,
    settings: IdentifySettings | None = None,
    validate: Sequence[str | Path] = (),
) -> Identification:
    """Refit from the logs at ``paths`` (see the module docstring)."""
    s = settings or IdentifySettings()
    if s.holdout and validate:
        raise IdentificationError("give either validation logs or a holdout fraction, not both")
    t0 = time.perf_counter()
    kind = joint_kind(s.joint, s.joint_kind)
    signals = [load_joint(p, s.topic, s.joint, nominal, kind.value, s.window) for p in paths]
    held = [load_joint(p, s.topic, s.joint, nominal, kind.value) for p in validate]
    t_read = time.perf_counter()
    limit = nominal.tau_max if kind is JointKind.MOTOR else nominal.f_max
    logs = [prepare(sig, s.preparation, limit) for sig in signals]
    val_logs = [prepare(sig, s.preparation, limit) for sig in held]
    fit_keep, val_keep = _split(logs, s.holdout)
    parts = fit_indices(logs, s.preparation.fit_rate_hz, fit_keep)
    t_prepare = time.perf_counter()
    delay = s.torque_delay_s
    if delay is None:
        delay = estimate_delay(logs, parts, nominal, s.fit)
    samples = fit_samples(logs, parts, delay)
    result = fit_parameters(samples, nominal, s.fit)
    if not result.success:
        raise IdentificationError(
            f"the SQP did not converge ({result.status}, {result.iterations} iterations)"
        )
    uncertainty = estimate_uncertainty(
        result.fitted, result.values.as_dict(), result.jacobian, result.residuals
    )
    t_solve = time.perf_counter()
    errors = {
        "fit": error_stats(result.values, logs, fit_keep, delay),
        "fit_nominal": error_stats(result.initial, logs, fit_keep, delay),
    }
    source = ""
    if val_logs:
        errors["validation"] = error_stats(result.values, val_logs, None, delay)
        errors["validation_nominal"] = error_stats(result.initial, val_logs, None, delay)
        source = ", ".join(str(p) for p in validate)
    elif s.holdout:
        errors["validation"] = error_stats(result.values, logs, val_keep, delay)
        errors["validation_nominal"] = error_stats(result.initial, logs, val_keep, delay)
        source = f"the last {s.holdout:.0%} of each log (held out of the fit)"
    t_end = time.perf_counter()
    return Identification(
        settings=s,
        nominal=nominal,
        params=refit_params(nominal, result.values, result.fitted),
        logs=tuple(logs),
        fit=result,
        uncertainty=uncertainty,
        delay_s=delay,
        delay_estimated=s.torque_delay_s is None,
        errors=errors,
        validation_source=source,
        validation_logs=tuple(val_logs),
        timing_s={
            "read": t_read - t0,
            "prepare": t_prepare - t_read,
            "solve": t_solve - t_prepare,
            "total": t_end - t0,
        },
    )


def _split(
    logs: list[PreparedLog], holdout: float
) -> tuple[list[np.ndarray] | None, list[np.ndarray] | None]:
    """Per log, the samples of the fit and of the holdout (None, None without a holdout)."""
    if not holdout:
        return None, None
    fit_keep, val_keep = [], []
    for log in logs:
        t = log.signals.t_s
        cut = t[0] + (1.0 - holdout) * (t[-1] - t[0])
        fit_keep.append(t < cut)
        val_keep.append(t >= cut)
    return fit_keep, val_keep


def error_stats(
    values: FrictionValues, logs: Sequence[PreparedLog], keep: list[np.ndarray] | None, delay_s: float
) -> ErrorStats:
    """Measured (filtered) minus model effort at every usable sample of ``logs`` (within ``keep``)."""
    err, measured, raw_err = [], [], []
    for i, log in enumerate(logs):
        mask = log.usable if keep is None else log.usable & keep[i]
        idx = np.flatnonzero(mask)
        k = log.signals.effort_per_force
        model = k * values.force_n(log.velocity_m_s[idx], log.acceleration_m_s2[idx])
        filtered = k * log.force_at(idx, delay_s)
        raw = k * np.interp(log.signals.t_s[idx] + delay_s, log.signals.t_s, log.signals.force_n)
        err.append(filtered - model)
        measured.append(filtered)
        raw_err.append(raw - model)
    e, m, r = np.concatenate(err), np.concatenate(measured), np.concatenate(raw_err)
    if e.size == 0:
        raise IdentificationError("no usable sample to measure the error on (all stationary or trimmed)")
    rms = float(np.sqrt(np.mean(e**2)))
    return ErrorStats(
        rms=rms,
        max_abs=float(np.max(np.abs(e))),
        nrmse_pct=100.0 * rms / float(np.sqrt(np.mean(m**2))),
        samples=int(e.size),
        rms_unfiltered=float(np.sqrt(np.mean(r**2))),
    )


def refit_params(nominal: AxisParams, values: FrictionValues, fitted: tuple[str, ...]) -> AxisParams:
    """The nominal parameters with the fitted ones; a fitted M_eq goes into the cart mass m (the
    rotor, gearbox and pulley inertias keep their nominal values)."""
    changes: dict[str, float] = {name: getattr(values, name) for name in fitted if name != "M_eq"}
    if "M_eq" in fitted:
        rotating = nominal.M_eq - nominal.m
        m = values.M_eq - rotating
        if m <= 0.0:
            raise IdentificationError(
                f"the refit M_eq = {values.M_eq:.6g} kg is below the rotating parts' share {rotating:.6g} kg "
                "of the nominal parameters: the log does not determine the inertia (fit without M_eq)"
            )
        changes["m"] = m
    return nominal.replace(**changes)
