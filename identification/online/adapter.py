"""One axis's online re-identification: samples in, a decision record out every few seconds.

:class:`Adapter` holds the newest motor samples (:class:`~.ring.SampleRing`), the accepted parameters
and their version (0: the starting set, e.g. a one-time refit), the torque/position offset, and the last
window's fit (the next one starts there). Each :meth:`Adapter.step` — due every ``every_s`` of drive
time (the samples' stamps, so at any bridge speed) once ``window_s`` of samples are held —

1. takes the newest ``window_s`` of samples (:func:`~.window.window_signals`: on the drive's grid) and
   prepares them as ``identify`` does (:func:`~..preparation.prepare`: one zero-phase filter, the
   derivatives of the filtered position), with a shorter guard around stops (``guard_s`` 0.1 s instead
   of 0.3 s: a point-to-point move lasts about half a second, and 0.3 s at each end would leave
   nothing of it);
2. splits the window: the newest ``holdout_s`` are held out; the rest is fitted, decimated to the
   fit's rate, every sample with the same weight (the window is the forgetting: older samples weigh
   nothing);
3. measures the window (:class:`~.acceptance.WindowFacts`) and checks it is informative;
4. until the torque/position offset is known, estimates it on the window as ``identify`` does
   (:func:`~..alignment.estimate_delay`), on windows that do not overlap (independent estimates), and
   combines them (inverse-variance mean): once the combination is resolvable (3σ within a sample
   period) it is held from then on (a drive's timing does not drift); until then the fits use 0, as
   ``identify`` does with an offset it cannot resolve; after :data:`DELAY_WINDOWS` windows it stays 0.
   ``torque_delay_s`` fixes it instead;
5. fits the terms (:func:`~.drift_fit.fit_drift`, warm-started from the last window's result; by
   default those of :func:`~.drift_fit.default_terms`: the paper's drift and the terms beside eq. (1)
   the starting set has on);
6. checks σ, the change and the held-out error (:mod:`.acceptance`) and, if all pass, makes the
   estimate the new accepted set (version + 1).

Every step returns a :class:`~axisflow.acquisition.wire.params_estimate.ParamsEstimate` — accepted or
not, with the reason, and the whole friction law (a term not fitted carries its accepted value) — for
the caller to publish.
"""

from __future__ import annotations

import dataclasses
import importlib
import math
from dataclasses import dataclass, field

import numpy as np

from ...acquisition.wire.params_estimate import PARAMETER_NAMES, Decision, ParamsEstimate
from ...model import AxisParams
from ..alignment import DelayEstimate, estimate_delay
from ..errors import IdentificationError
from ..fit import FitResult, FrictionValues
from ..preparation import PreparationSettings, PreparedLog, fit_samples, prepare
from .acceptance import (
    AcceptanceRules,
    HoldoutErrors,
    Verdict,
    WindowFacts,
    check_change,
    check_holdout,
    check_uncertainty,
    check_window,
)
from .drift_fit import COULOMB, COULOMB_SCALE, CoulombColumn, DriftFit, check_terms, default_terms, fit_drift
from .ring import SampleRing
from .window import window_signals

NS_PER_S = 1_000_000_000
DELAY_WINDOWS = 10
"""windows the offset is estimated on at most (without overlap) before it is held at 0 as unresolvable"""
RING_RATE_HZ = 1000.0
"""the sample rate the ring is sized for (the drives' 1 kHz); a slower drive fills it more slowly"""


def load_fit_libraries() -> None:
    """Import what a step imports on first use (scipy's filters and optimiser, CasADi). A node that
    leaves it to its first step holds its sample intake for the second or more the imports take (tens
    of seconds of drive time from a fast simulated bridge); ``axisflow adapt`` loads them while it
    joins and takes the first window's samples."""
    for name in ("scipy.signal", "scipy.optimize", "casadi"):
        importlib.import_module(name)


def _preparation() -> PreparationSettings:
    return PreparationSettings(guard_s=0.1)


@dataclass(frozen=True)
class AdaptSettings:
    """The window, its schedule and the rules (docs/adaptation.md justifies the numbers)."""

    window_s: float = 30.0
    """drive time of samples in each window, the held-out part included [s]"""
    holdout_s: float = 5.0
    """the newest part of each window, left out of the fit and used to judge it [s]"""
    every_s: float = 5.0
    """drive time between two steps [s]"""
    terms: tuple[str, ...] | None = None
    """what to fit (:func:`~.drift_fit.check_terms`); None: :func:`~.drift_fit.default_terms` of the
    starting set"""
    preparation: PreparationSettings = field(default_factory=_preparation)
    torque_delay_s: float | None = None
    """the torque/position offset [s]; None: estimated on the first informative window"""
    rules: AcceptanceRules = field(default_factory=AcceptanceRules)

    def __post_init__(self) -> None:
        if self.terms is not None:
            object.__setattr__(self, "terms", check_terms(self.terms))
        for name, value, low in (
            ("window", self.window_s, 2.0),
            ("hold-out", self.holdout_s, 0.5),
            ("period", self.every_s, 0.1),
        ):
            if not (math.isfinite(value) and low <= value <= 3600.0):
                raise IdentificationError(f"adaptation {name} = {value} s must be in [{low:g}, 3600] s")
        if not self.holdout_s <= 0.5 * self.window_s:
            raise IdentificationError(
                f"adaptation hold-out = {self.holdout_s:g} s must be at most half the window = "
                f"{self.window_s:g} s"
            )
        if self.torque_delay_s is not None and not abs(self.torque_delay_s) <= 0.1:
            raise IdentificationError(f"torque delay = {self.torque_delay_s} s must be within ±0.1 s")


@dataclass(frozen=True, eq=False)
class _Window:
    """One window, prepared and split."""

    log: PreparedLog
    start_ns: int
    end_ns: int
    fit_idx: np.ndarray
    hold_idx: np.ndarray
    facts: WindowFacts


class Adapter:
    """The adaptation of one axis (see the module docstring)."""

    def __init__(self, axis: str, params: AxisParams, settings: AdaptSettings | None = None) -> None:
        self.axis = axis
        self.settings = settings or AdaptSettings()
        self.initial = params
        """version 0: the starting set"""
        self.terms = self.settings.terms if self.settings.terms is not None else default_terms(params)
        """what each window fits"""
        self.accepted = params
        """the accepted set now (version :attr:`version`)"""
        self.version = 0
        self.delay: DelayEstimate | None = None
        """the combined offset estimate so far (None: none yet, or fixed by the settings)"""
        self.delay_windows: list[DelayEstimate] = []
        """the offset searches of the windows it was estimated on"""
        self._delay_held = self.settings.torque_delay_s is not None
        self._delay_after_ns = 0
        """the next offset search takes a window that starts at or after this stamp"""
        s = self.settings
        self.ring = SampleRing(round((s.window_s + 2.0 * s.every_s) * RING_RATE_HZ))
        self._last: FitResult | None = None
        self._next_ns: int | None = None
        self.steps = 0
        self.source = f"live samples of axis {axis!r}"

    @property
    def delay_s(self) -> float:
        """The offset the fits use now [s] (see the module docstring)."""
        if self.settings.torque_delay_s is not None:
            return self.settings.torque_delay_s
        return 0.0 if self.delay is None else self.delay.value_s

    @property
    def delay_held(self) -> bool:
        """Whether the offset is settled (fixed, resolved, or given up as unresolvable)."""
        return self._delay_held

    def initial_record(self, stamp_ns: int) -> ParamsEstimate:
        """Version 0: the starting set, as a record (published when the node starts)."""
        values = FrictionValues.of(self.initial).as_dict()
        return ParamsEstimate(
            stamp_ns,
            self.axis,
            0,
            0,
            Decision.INITIAL,
            "the starting parameters",
            values=tuple(values[name] for name in PARAMETER_NAMES),
        )

    def add(self, stamp_ns: np.ndarray, angle_rad: np.ndarray, torque_nm: np.ndarray) -> None:
        """Motor samples (stamps [ns], angle [rad], torque [N·m]), in order."""
        restarts = self.ring.restarts
        self.ring.extend(stamp_ns, angle_rad, torque_nm)
        if self.ring.restarts != restarts:  # the stream began again: so does the schedule
            self._next_ns = None

    def due(self) -> bool:
        """Whether a step is due: a whole window held and ``every_s`` passed since the last step."""
        newest, oldest = self.ring.newest_ns, self.ring.oldest_ns
        if newest is None or oldest is None:
            return False
        if self._next_ns is None:
            self._next_ns = oldest + round(self.settings.window_s * NS_PER_S)
        return newest >= self._next_ns

    def step(self) -> ParamsEstimate:
        """Fit the newest window and decide (see the module docstring)."""
        s = self.settings
        end_ns = self.ring.newest_ns
        if end_ns is None:
            raise IdentificationError(f"{self.source}: no sample yet")
        self._next_ns = end_ns + round(s.every_s * NS_PER_S)
        self.steps += 1
        start_ns = end_ns - round(s.window_s * NS_PER_S)
        try:
            window = self._window(start_ns, end_ns)
        except IdentificationError as exc:
            return self._record(Verdict(Decision.FIT_FAILED, str(exc)), start_ns, end_ns)
        verdict = check_window(window.facts, s.rules, s.preparation.fit_rate_hz)
        if verdict is not None:
            return self._record(verdict, window.start_ns, window.end_ns)
        terms = self.terms
        held_mass = ""
        if "M_eq" in terms and window.facts.inertial_share < s.rules.min_inertial_share:
            terms = tuple(t for t in terms if t != "M_eq")
            held_mass = (
                f" (M_eq held: inertial share {100 * window.facts.inertial_share:.1f} % below "
                f"{100 * s.rules.min_inertial_share:g} %)"
            )
        try:
            delay_s = self._delay(window, terms)
            samples = fit_samples([window.log], [window.fit_idx], delay_s)
            drift = fit_drift(samples, self.accepted, terms, start=self._last)
        except IdentificationError as exc:
            return self._record(Verdict(Decision.FIT_FAILED, str(exc)), window.start_ns, window.end_ns)
        self._last = drift.result
        errors = None
        verdict = check_uncertainty(drift, s.rules)
        if verdict is None:
            change = check_change(drift, self.accepted, s.rules)
            if isinstance(change, Verdict):
                verdict = change
            else:
                errors = self._holdout(window, drift.values, delay_s)
                verdict = check_holdout(errors, s.rules, self.version)
                if verdict.decision is Decision.ACCEPTED:
                    self.accepted = change
        verdict = dataclasses.replace(verdict, reason=verdict.reason + held_mass)
        return self._record(verdict, window.start_ns, window.end_ns, drift, errors)

    # ---- the steps ---------------------------------------------------------------------------------
    def _window(self, start_ns: int, end_ns: int) -> _Window:
        s = self.settings
        stamps, angle, torque = self.ring.since(start_ns)
        signals = window_signals(stamps, angle, torque, self.accepted, self.source)
        log = prepare(signals, s.preparation, self.accepted.tau_max)
        t = log.signals.t_s
        fit_part = t < t[-1] - s.holdout_s
        fit_idx = log.fit_indices(s.preparation.fit_rate_hz, fit_part)
        hold_idx = np.flatnonzero(log.usable & ~fit_part)
        facts = WindowFacts.of(
            log, fit_idx, hold_idx, fit_part, self.accepted.M_eq, s.preparation.stationary_speed_m_s
        )
        return _Window(log, int(stamps[0]), int(stamps[-1]), fit_idx, hold_idx, facts)

    def _delay(self, window: _Window, terms: tuple[str, ...]) -> float:
        if self._delay_held or window.start_ns < self._delay_after_ns:
            return self.delay_s
        fitted = tuple(t for t in terms if t != COULOMB)
        columns = [CoulombColumn(window.log, self.accepted)] if COULOMB in terms else None
        names, scales = ((COULOMB,), (COULOMB_SCALE,)) if COULOMB in terms else ((), ())
        log, idx = [window.log], [window.fit_idx]
        found = estimate_delay(log, idx, self.accepted, fitted, columns, names, scales)
        self._delay_after_ns = window.end_ns + 1
        if math.isfinite(found.std_s) and found.std_s > 0.0:
            self.delay_windows.append(found)
        if self.delay_windows:
            weights = np.array([1.0 / d.std_s**2 for d in self.delay_windows])
            estimate = float(np.dot(weights, [d.estimate_s for d in self.delay_windows]) / weights.sum())
            combined = DelayEstimate(0.0, estimate, float(1.0 / np.sqrt(weights.sum())), found.period_s)
            if combined.resolvable:
                combined = dataclasses.replace(combined, value_s=estimate)
                self._delay_held = True
            self.delay = combined
        if len(self.delay_windows) >= DELAY_WINDOWS:
            self._delay_held = True
        return self.delay_s

    def _holdout(self, window: _Window, estimate: FrictionValues, delay_s: float) -> HoldoutErrors:
        log, idx = window.log, window.hold_idx
        k = log.signals.effort_per_force
        measured = log.force_at(idx, delay_s)
        v, a = log.velocity_m_s[idx], log.acceleration_m_s2[idx]

        def rms(values: FrictionValues) -> float:
            return float(k * np.sqrt(np.mean((measured - values.force_n(v, a)) ** 2)))

        accepted, initial = FrictionValues.of(self.accepted), FrictionValues.of(self.initial)
        return HoldoutErrors(rms(estimate), rms(accepted), rms(initial), int(idx.size))

    def _record(
        self,
        verdict: Verdict,
        start_ns: int,
        end_ns: int,
        drift: DriftFit | None = None,
        errors: HoldoutErrors | None = None,
    ) -> ParamsEstimate:
        base = self.version
        if verdict.decision is Decision.ACCEPTED:
            self.version += 1
        values = std = (math.nan,) * len(PARAMETER_NAMES)
        samples, fit_rms = 0, math.nan
        if drift is not None:
            found = drift.values.as_dict()
            values = tuple(found[name] for name in PARAMETER_NAMES)
            std = tuple(drift.std[name] for name in PARAMETER_NAMES)
            samples, fit_rms = drift.window.samples, drift.window.rms
        return ParamsEstimate(
            stamp_ns=end_ns,
            axis=self.axis,
            version=self.version,
            base_version=base,
            decision=verdict.decision,
            reason=verdict.reason,
            fitted=drift.terms if drift is not None else (),
            values=values,
            std=std,
            window_start_ns=start_ns,
            window_end_ns=end_ns,
            samples=samples,
            fit_rms_nm=fit_rms,
            holdout_rms_nm=errors.estimate if errors is not None else math.nan,
            holdout_rms_kept_nm=errors.accepted if errors is not None else math.nan,
        )
