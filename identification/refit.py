"""A refit from logs, end to end: read, prepare, align, fit, judge — the result object of ``identify``.

:func:`identify` reads the joint of every log (:mod:`.signals`: on the drive's sampling grid, holes
counted), prepares it (:mod:`.preparation`: filtered, differentiated, what holes, stops and saturation
touch left out), chooses the terms the data support unless they are fixed (:mod:`.selection`,
``--terms auto``; fixed terms: :mod:`.fit_terms`), builds the columns of the extra terms
(:mod:`.extra_terms`: Coulomb friction along the stroke, cogging orders), estimates the
torque/position time offset unless it is given (:mod:`.alignment`, with its σ, or "not
resolvable"), fits eq. (1)'s chosen parameters and the
extra terms by SQP (:func:`.fit.fit_window`, with σ and correlations), and judges the result: the
effort error of the refit and of the nominal parameters side by side, on the fitted samples and on
validation samples (a separate log, ``validate``, or the last ``holdout`` fraction of each log, then
left out of the fit), and what the model leaves unexplained (:mod:`.residuals`: the noise floor, the
residual's peaks in Hz and in cycles per motor revolution). With ``--cogging auto`` (the default), a
residual peak that stands far out at a whole number of cycles per motor revolution is cogging: the
fit is done again with those orders taken in (:func:`auto_cogging_orders`), and the report says so.
With the selection, a term the final fit does not support (σ larger than its value) is dropped and
the fit done again without it.

Errors are measured minus model effort at every usable sample (1 kHz, not decimated), both through the
same zero-phase filter as the fit (:mod:`.preparation`): a drive's torque carries content above the
filter's cut-off (its position loop acting on encoder steps) that no rigid-body model predicts; the
RMS of the unfiltered error is reported beside it. The velocity the model uses is always the
derivative of the zero-phase filtered position; a logged velocity (a drive's own filtered estimate)
is not used, and its lag behind that derivative is reported.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..model import AxisParams, ParameterError
from ..model.terms import TERMS, canonical_terms
from .alignment import DelayEstimate, estimate_delay
from .errors import IdentificationError
from .extra_terms import DEFAULT_STROKE_TERMS, ExtraTerms, TermColumns, covered_stretch
from .fit import (
    PARAMETERS,
    SIGNED_PARAMETERS,
    FitResult,
    FrictionValues,
    WindowFit,
    check_fit_names,
    fit_window,
)
from .fit_terms import FitChoice, choose_parameters
from .preparation import PreparationSettings, PreparedLog, fit_indices, fit_samples, prepare
from .residuals import ResidualAnalysis, analyse_residuals, analysed_span
from .selection import (
    BASE_TERMS,
    Selection,
    Structure,
    fit_plan,
    select_structure,
    typical_speed_m_s,
    unsupported_terms,
    without_terms,
)
from .signals import DEFAULT_JOINT, DEFAULT_TOPIC, JointKind, TimeWindow, joint_kind, load_joint
from .uncertainty import Uncertainty


@dataclass(frozen=True)
class IdentifySettings:
    topic: str = DEFAULT_TOPIC
    joint: str = DEFAULT_JOINT
    joint_kind: str | None = None
    """motor or carriage; None: from the joint's name"""
    fit: tuple[str, ...] | None = None
    """the parameters to fit (:data:`~.fit.PARAMETERS` names); None: every parameter of the terms
    that are on (:mod:`.fit_terms`)"""
    terms: tuple[str, ...] | None = None
    """the friction law's terms that are on (:mod:`axisflow.model.terms` names); None: the parameter
    file's (:mod:`.fit_terms`)"""
    given: frozenset[str] | None = None
    """the keys the user's own parameter file gives; None: every nominal value is the user's own"""
    preparation: PreparationSettings = field(default_factory=PreparationSettings)
    torque_delay_s: float | None = None
    """the torque/position offset [s]; None: estimated"""
    holdout: float = 0.0
    """the last fraction of each log kept for validation (0: none)"""
    window: TimeWindow = field(default_factory=TimeWindow)
    """the part of each fitted log to use (default: all of it; validation logs are used whole)"""
    extra: ExtraTerms = field(default_factory=lambda: ExtraTerms(DEFAULT_STROKE_TERMS, auto_cogging=True))
    """terms beyond eq. (1): friction along the stroke, cogging (by default the orders the residual
    shows: :func:`auto_cogging_orders`)"""
    select: bool = True
    """choose the terms by the data (``--terms auto``, :mod:`.selection`): ``extra`` then offers the
    stroke terms as a candidate, and its cogging orders join the chosen structure (kept if the final
    fit supports them); False: fit ``fit`` and ``extra`` as they are"""

    def __post_init__(self) -> None:
        if self.fit is not None:
            object.__setattr__(self, "fit", check_fit_names(tuple(self.fit)))
        if self.terms is not None:
            object.__setattr__(self, "terms", canonical_terms(tuple(self.terms)))
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
    window_fit: WindowFit
    delay: DelayEstimate | None
    """the offset search (None: the offset was given)"""
    delay_s: float
    """the torque/position offset the fit used [s]"""
    extra: ExtraTerms
    """the extra terms fitted (with any cogging orders the residual showed, ``--cogging auto``)"""
    stretch_m: tuple[float, float]
    """the stretch of the stroke the fitted samples cover [m] (the extra stroke terms' span)"""
    columns: tuple[TermColumns, ...]
    """per log, the extra terms' columns (cart force per unit of coefficient)"""
    errors: dict[str, ErrorStats]
    """'fit', 'fit_nominal' and, with validation, 'validation', 'validation_nominal'"""
    residuals: ResidualAnalysis
    validation_source: str
    validation_logs: tuple[PreparedLog, ...]
    validation_columns: tuple[TermColumns, ...]
    timing_s: dict[str, float]
    cogging_found: tuple[int, ...] = ()
    """cogging orders the first pass's residual showed and the fit then took in (``--cogging auto``)"""
    choice: FitChoice | None = None
    """the terms on, the parameters fitted and held (:mod:`.fit_terms`; with ``--terms auto``, the
    selection's choice)"""
    selection: Selection | None = None
    """the candidates compared and the structure chosen (``--terms auto``; None: fixed terms)"""
    dropped: tuple[str, ...] = ()
    """terms the final fit did not support (σ larger than the value), dropped and fitted again without"""

    @property
    def at_bound(self) -> tuple[str, ...]:
        """Fitted friction parameters stuck at their lower bound 0 (a1…a4): the log does not support
        the term, or the model lacks another one; the report says so."""
        values = self.fit.values.as_dict()
        bounded = [n for n in self.fit.fitted if n not in SIGNED_PARAMETERS and n != "M_eq"]
        return tuple(n for n in bounded if values[n] <= 0.0)

    @property
    def fit(self) -> FitResult:
        return self.window_fit.result

    @property
    def uncertainty(self) -> Uncertainty:
        return self.window_fit.uncertainty

    @property
    def delay_estimated(self) -> bool:
        return self.delay is not None

    @property
    def kind(self) -> JointKind:
        return self.logs[0].signals.kind

    def model_force(
        self, log: PreparedLog, columns: TermColumns, nominal: bool = False, idx: np.ndarray | None = None
    ) -> np.ndarray:
        """The model's cart force [N] at the samples ``idx`` of ``log`` (None: all): eq. (1) with the
        refit (or nominal) values, plus the extra terms (the refit's; none for the nominal model)."""
        values = FrictionValues.of(self.nominal) if nominal else self.fit.values
        v, a = (
            (log.velocity_m_s, log.acceleration_m_s2)
            if idx is None
            else (
                log.velocity_m_s[idx],
                log.acceleration_m_s2[idx],
            )
        )
        force = values.force_n(v, a)
        if nominal or not self.fit.extra:
            return force
        return force + columns.force(self.fit.extra_vector, idx)

    def traces(self, validation: bool = False) -> list[EffortTrace]:
        """Per log, measured and model effort over time (the paper's Fig. 2 data)."""
        logs = self.validation_logs if validation else self.logs
        columns = self.validation_columns if validation else self.columns
        out = []
        for log, cols in zip(logs, columns, strict=True):
            k = log.signals.effort_per_force
            everything = np.arange(len(log.signals.t_s))
            out.append(
                EffortTrace(
                    source=log.signals.source,
                    t_s=log.signals.t_s,
                    measured=k * log.force_at(everything, self.delay_s),
                    refit=k * self.model_force(log, cols),
                    nominal=k * self.model_force(log, cols, nominal=True),
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
    selecting = s.select and s.terms is None and s.fit is None
    choice = None
    if not selecting:  # fixed terms: what the file and --terms/--fit say (:mod:`.fit_terms`)
        choice = choose_parameters(nominal, s.terms, s.fit, s.given)
        nominal = choice.start
        s = dataclasses.replace(s, fit=choice.fitted, terms=choice.terms, select=False)
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
    run = _FitPass(s, nominal, logs, val_logs, fit_keep, val_keep, parts)
    selection = _select(run, s) if selecting else None
    t_select = time.perf_counter()
    structure = None  # with the selection: its choice, and the cogging orders given
    if selection is not None:
        structure = dataclasses.replace(selection.chosen, cogging_orders=s.extra.cogging_orders)
    extra = s.extra if structure is None else _extra_for(s.extra, structure)
    ident = run.fit(extra, structure)
    found = auto_cogging_orders(ident.residuals, ident.extra) if s.extra.auto_cogging else ()
    if found:
        orders = tuple(sorted(ident.extra.cogging_orders + found))
        structure = None if structure is None else dataclasses.replace(structure, cogging_orders=orders)
        ident = run.fit(dataclasses.replace(ident.extra, cogging_orders=orders), structure)
    dropped: tuple[str, ...] = ()
    if structure is not None:
        dropped = unsupported_terms(structure, ident.fit.estimates, ident.uncertainty)
        dropped = tuple(t for t in dropped if t not in BASE_TERMS)
        if dropped:
            structure = without_terms(structure, dropped)
            ident = run.fit(_extra_for(ident.extra, structure), structure)
    if structure is not None:
        choice = run.choice_of(structure, ident.fit.fitted)
    t_end = time.perf_counter()
    return dataclasses.replace(
        ident,
        choice=choice,
        cogging_found=found,
        selection=selection,
        dropped=dropped,
        timing_s={
            "read": t_read - t0,
            "prepare": t_prepare - t_read,
            "select": t_select - t_prepare,
            "solve": run.solve_s,
            "judge": run.judge_s,
            "total": t_end - t0,
        },
    )


def _select(run: _FitPass, s: IdentifySettings) -> Selection:
    """The structure the data support (:mod:`.selection`), scored on held-out blocks of the fit samples
    and on the validation samples (validation logs, or each log's held-out last part)."""
    rate = s.preparation.fit_rate_hz
    if run.val_logs:
        val_logs, val_parts = run.val_logs, [log.fit_indices(rate) for log in run.val_logs]
    elif run.val_keep is not None:
        val_logs, val_parts = (
            run.logs,
            [log.fit_indices(rate, k) for log, k in zip(run.logs, run.val_keep, strict=True)],
        )
    else:
        val_logs, val_parts = [], []
    return select_structure(
        run.logs,
        run.parts,
        val_logs,
        val_parts,
        run.nominal,
        s.preparation,
        run.stretch,
        s.extra.stroke_terms,
        s.torque_delay_s,
        given=s.given,
        speed_m_s=run.speed_m_s,
    )


def _parameters_of(terms: tuple[str, ...]) -> tuple[str, ...]:
    return ("M_eq", *(p for t in terms if t in TERMS for p in TERMS[t].parameters))


def _extra_for(extra: ExtraTerms, structure: Structure) -> ExtraTerms:
    """``extra`` with the stroke terms and cogging orders of ``structure``."""
    return dataclasses.replace(
        extra, stroke_terms=structure.stroke_terms, cogging_orders=structure.cogging_orders
    )


AUTO_COGGING_RATIO = 20.0
"""a residual peak at a whole number of cycles per motor revolution this many times above its
neighbours is cogging (or torque ripple) the fit takes in (``--cogging auto``)"""
AUTO_COGGING_MAX = 4


def auto_cogging_orders(residuals: ResidualAnalysis, extra: ExtraTerms) -> tuple[int, ...]:
    """The orders of the residual's angle-domain peaks that stand :data:`AUTO_COGGING_RATIO` above
    their neighbours at a whole number of cycles per revolution (±0.25) and are not fitted yet."""
    found: list[int] = []
    for peak in residuals.peaks_order:
        order = round(peak.frequency)
        whole = abs(peak.frequency - order) <= 0.25
        if (
            whole
            and peak.ratio >= AUTO_COGGING_RATIO
            and order not in extra.cogging_orders
            and order not in found
        ):
            found.append(order)
    return tuple(found[:AUTO_COGGING_MAX])


class _FitPass:
    """One fit of prepared logs with a set of extra terms: columns, the offset, the SQP, the judgement."""

    def __init__(
        self,
        settings: IdentifySettings,
        nominal: AxisParams,
        logs: list[PreparedLog],
        val_logs: list[PreparedLog],
        fit_keep: list[np.ndarray] | None,
        val_keep: list[np.ndarray] | None,
        parts: list[np.ndarray],
    ) -> None:
        self.settings, self.nominal = settings, nominal
        self.logs, self.val_logs = logs, val_logs
        self.fit_keep, self.val_keep, self.parts = fit_keep, val_keep, parts
        self.stretch = covered_stretch(logs, parts)
        self.speed_m_s = typical_speed_m_s(logs, parts)
        self.solve_s = 0.0
        """wall time of the offset searches and the fits [s]"""
        self.judge_s = 0.0
        """wall time of the errors and the residual analyses [s]"""

    def choice_of(self, structure: Structure, fitted: tuple[str, ...]) -> FitChoice:
        """What a fit of ``structure`` had on, fitted and held, in the terms of :mod:`.fit_terms`."""
        given = self.settings.given
        _names, start = fit_plan(structure, self.nominal, given, self.speed_m_s)
        # held: the file's values a term on keeps (a given f0); da1 = 0 beside a fitted f0 is no value
        # of the file's but the convention that f0 takes the constant per direction
        in_model = _parameters_of(start.terms)
        held = tuple(
            n for n in PARAMETERS if n not in fitted and n in in_model and (given is None or n in given)
        )
        switched = tuple(t for t in self.nominal.terms if t not in start.terms)
        return FitChoice(start, start.terms, fitted, held, switched)

    def fit(self, extra: ExtraTerms, structure: Structure | None = None) -> Identification:
        """Fit ``extra`` beside eq. (1)'s parameters: those of ``structure`` (from its starting values:
        :func:`.selection.fit_plan`), or without one the settings' ``fit`` from the nominal values."""
        t0 = time.perf_counter()
        s, nominal, logs, parts = self.settings, self.nominal, self.logs, self.parts
        if structure is None:
            fit, start = s.fit or (), nominal
        else:
            fit, start = fit_plan(structure, nominal, s.given, self.speed_m_s)
        columns = [extra.columns(log, self.stretch, nominal, s.preparation) for log in logs]
        val_columns = [extra.columns(log, self.stretch, nominal, s.preparation) for log in self.val_logs]
        names, scales = extra.names, extra.scales(nominal)
        delay = None
        if s.torque_delay_s is None:
            delay = estimate_delay(logs, parts, start, fit, columns, names, scales)
        delay_s = delay.value_s if delay is not None else s.torque_delay_s
        assert delay_s is not None
        samples = fit_samples(logs, parts, delay_s, columns)
        window_fit = fit_window(samples, start, fit, extra_names=names, extra_scales=scales)
        if not window_fit.success:
            result = window_fit.result
            raise IdentificationError(
                f"the SQP did not converge ({result.status}, {result.iterations} iterations)"
            )
        ident = Identification(
            settings=s,
            nominal=nominal,
            params=refit_params(start, window_fit.values, window_fit.result.fitted),
            logs=tuple(logs),
            window_fit=window_fit,
            delay=delay,
            delay_s=delay_s,
            extra=extra,
            stretch_m=self.stretch,
            columns=tuple(columns),
            errors={},
            residuals=_placeholder_residuals(),
            validation_source="",
            validation_logs=tuple(self.val_logs),
            validation_columns=tuple(val_columns),
            timing_s={},
        )
        t1 = time.perf_counter()
        errors, source = _judge(ident, self.fit_keep, self.val_keep)
        residuals = _residuals(ident, self.fit_keep)
        self.solve_s += t1 - t0
        self.judge_s += time.perf_counter() - t1
        return dataclasses.replace(ident, errors=errors, residuals=residuals, validation_source=source)


def _judge(
    ident: Identification, fit_keep: list[np.ndarray] | None, val_keep: list[np.ndarray] | None
) -> tuple[dict[str, ErrorStats], str]:
    """The effort errors of the refit and of the nominal parameters, on the fit's samples and on the
    validation samples; and where those came from."""
    logs, columns = list(ident.logs), list(ident.columns)
    errors = {
        "fit": error_stats(ident, logs, columns, fit_keep),
        "fit_nominal": error_stats(ident, logs, columns, fit_keep, nominal=True),
    }
    source = ""
    if ident.validation_logs:
        val_logs, val_cols = list(ident.validation_logs), list(ident.validation_columns)
        errors["validation"] = error_stats(ident, val_logs, val_cols, None)
        errors["validation_nominal"] = error_stats(ident, val_logs, val_cols, None, nominal=True)
        source = ", ".join(log.signals.source for log in ident.validation_logs)
    elif ident.settings.holdout:
        errors["validation"] = error_stats(ident, logs, columns, val_keep)
        errors["validation_nominal"] = error_stats(ident, logs, columns, val_keep, nominal=True)
        source = f"the last {ident.settings.holdout:.0%} of each log (held out of the fit)"
    return errors, source


def _residuals(ident: Identification, fit_keep: list[np.ndarray] | None) -> ResidualAnalysis:
    """What the refit leaves unexplained on the fitted logs (:mod:`.residuals`), over the span of each
    log the spectra use."""
    spectral = [
        log.moving if fit_keep is None else log.moving & fit_keep[i] for i, log in enumerate(ident.logs)
    ]
    rate = min(log.signals.rate_hz for log in ident.logs)
    spans = analysed_span(spectral, rate)
    raw, angle = [], []
    for i, (log, end) in enumerate(zip(ident.logs, spans, strict=True)):
        k = log.signals.effort_per_force
        t = log.signals.t_s
        idx = np.arange(end)
        model = ident.model_force(log, ident.columns[i], idx=idx)
        raw.append(k * (np.interp(t[:end] + ident.delay_s, t, log.signals.force_n) - model))
        angle.append(log.signals.position_m[:end] * ident.nominal.transmission.radians_per_metre)
    spectral = [mask[:end] for mask, end in zip(spectral, spans, strict=True)]
    p = ident.settings.preparation
    return analyse_residuals(raw, spectral, angle, rate, p.cutoff_hz, p.order)


def _placeholder_residuals() -> ResidualAnalysis:
    return ResidualAnalysis(math.nan, math.nan, (0.0, 0.0), (), (), 0, 0)


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
    ident: Identification,
    logs: Sequence[PreparedLog],
    columns: Sequence[TermColumns],
    keep: list[np.ndarray] | None,
    nominal: bool = False,
) -> ErrorStats:
    """Measured (filtered) minus model effort at every usable sample of ``logs`` (within ``keep``), the
    refit model or (``nominal``) eq. (1) with the nominal parameters."""
    err, measured, raw_err = [], [], []
    delay_s = ident.delay_s
    for i, log in enumerate(logs):
        mask = log.usable if keep is None else log.usable & keep[i]
        idx = np.flatnonzero(mask)
        k = log.signals.effort_per_force
        model = k * ident.model_force(log, columns[i], nominal, idx)
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
    params = nominal.replace(**changes)
    if "M_eq" not in fitted:
        return params
    try:
        return params.with_equivalent_mass(values.M_eq)
    except ParameterError:
        rotating = nominal.M_eq - nominal.m
        raise IdentificationError(
            f"the refit M_eq = {values.M_eq:.6g} kg is below the rotating parts' share {rotating:.6g} kg "
            "of the nominal parameters: the log does not determine the inertia (fit without M_eq)"
        ) from None
