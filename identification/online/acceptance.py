"""When an estimate may replace the accepted parameters, and why not.

An adaptive scheme must never make things worse than the fixed fit, and must say why it changed its
mind. An estimate over a window is checked, in this order (the first rule it breaks is the verdict,
:class:`~axisflow.acquisition.wire.params_estimate.Decision`):

1. **informative window** (``uninformative``): at least ``min_fit_samples`` samples to fit (at the
   fit's rate, after the stationary, saturated and hole-touched ones are left out) and
   ``min_holdout_samples`` held-out ones (1 kHz); a speed range (5th to 95th percentile of |ẋ| over
   the fitted samples) of at least ``min_speed_range_m_s`` — a2·ẋ and the Coulomb-like terms are told
   apart by how the force changes with the speed; at least ``min_reversals`` direction changes — the
   Coulomb-like terms change sign with the motion, an offset of the torque does not. Whether M_eq is
   estimated at all depends on ``min_inertial_share``: the RMS of M_eq·ẍ over the RMS of the force (a
   window of slow moves holds the inertia at its accepted value, it is not turned down);
2. **the solver converged** (``fit_failed``);
3. **σ below its bound** (``uncertain``): σ/|value| of each estimated term at most
   ``max_relative_std`` of it (σ from the fit's covariance with the residuals' colour taken in:
   :mod:`..uncertainty`; the signed f0, da1, da2 over the friction they shift,
   :func:`~.drift_fit.signed_scale`);
4. **a plausible change** (``implausible``): the new set inside the physical ranges of every parameter
   (:mod:`axisflow.model.parameter_ranges`, the combinations that let the axis move and hold itself),
   and each parameter within ``max_relative_change`` of its accepted value (f0, da1, da2: the change
   over :func:`~.drift_fit.signed_scale` of the accepted set);
5. **better on held-out samples** (``no_improvement``): the newest ``holdout_s`` of the window is left
   out of the fit; on its samples (1 kHz, the same filter) the estimate's RMS torque error must be
   below the accepted set's by the relative ``holdout_margin``, and not above the starting set's
   (version 0, the fixed fit) — so an accepted estimate is never worse than the fixed fit where it was
   checked.

Otherwise it is ``accepted``. The numbers are those of docs/adaptation.md, where they are justified.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ...acquisition.wire.params_estimate import Decision
from ...model import AxisParams, ParameterError
from ..errors import IdentificationError
from ..fit import PARAMETERS, SIGNED_PARAMETERS, FrictionValues
from ..preparation import PreparedLog
from .drift_fit import COULOMB, DriftFit, signed_scale


def _default_std() -> dict[str, float]:
    friction = {"f0": 0.05, "da1": 0.05, "da2": 0.05}  # over signed_scale: the friction they shift
    return {"M_eq": 0.02, "a1": 0.05, "a2": 0.05, "a3": 0.05, "a4": 0.10, COULOMB: 0.03} | friction


def _default_change() -> dict[str, float]:
    friction = {"f0": 0.25, "da1": 0.25, "da2": 0.30}  # as a1 and a2, over signed_scale
    return {"M_eq": 0.10, "a1": 0.25, "a2": 0.30, "a3": 0.25, "a4": 0.50} | friction


@dataclass(frozen=True)
class AcceptanceRules:
    """The numbers of the rules (see the module docstring)."""

    min_fit_samples: int = 200
    """samples to fit, at the fit's rate (100 Hz: 2 s of usable motion)"""
    min_holdout_samples: int = 500
    """held-out samples at the drive's rate (1 kHz: 0.5 s of usable motion)"""
    min_speed_range_m_s: float = 0.2
    min_reversals: int = 4
    min_inertial_share: float = 0.1
    """M_eq is estimated when RMS(M_eq·ẍ)/RMS(F) over the fitted samples reaches this"""
    max_relative_std: dict[str, float] = field(default_factory=_default_std)
    """σ/|value| per term (``coulomb``: σ of the relative change β)"""
    max_relative_change: dict[str, float] = field(default_factory=_default_change)
    """|new/accepted − 1| per parameter"""
    holdout_margin: float = 0.02
    """the estimate's held-out RMS error must be below (1 − margin) × the accepted set's"""

    def __post_init__(self) -> None:
        for name, value in (
            ("min_speed_range_m_s", self.min_speed_range_m_s),
            ("min_inertial_share", self.min_inertial_share),
            ("holdout_margin", self.holdout_margin),
            *((f"max_relative_std[{k}]", v) for k, v in self.max_relative_std.items()),
            *((f"max_relative_change[{k}]", v) for k, v in self.max_relative_change.items()),
        ):
            if not (math.isfinite(value) and value >= 0.0):
                raise IdentificationError(f"acceptance rule {name} = {value} must be a finite number >= 0")
        if not 0.0 <= self.holdout_margin < 1.0:
            raise IdentificationError(
                f"acceptance rule holdout_margin = {self.holdout_margin} must be in [0, 1)"
            )
        for name, value in (
            ("min_fit_samples", self.min_fit_samples),
            ("min_holdout_samples", self.min_holdout_samples),
            ("min_reversals", self.min_reversals),
        ):
            if isinstance(value, bool) or not isinstance(value, int) or value < 0:
                raise IdentificationError(f"acceptance rule {name} = {value!r} must be a whole number >= 0")
        unknown = sorted(
            (set(self.max_relative_std) - {*PARAMETERS, COULOMB})
            | (set(self.max_relative_change) - {*PARAMETERS})
        )
        if unknown:
            raise IdentificationError(f"acceptance rules name unknown parameters: {', '.join(unknown)}")


@dataclass(frozen=True)
class Verdict:
    """A decision and the reason in words, with the numbers that decided it."""

    decision: Decision
    reason: str


@dataclass(frozen=True)
class WindowFacts:
    """What a window holds, as the rules measure it."""

    fit_samples: int
    holdout_samples: int
    speed_range_m_s: float
    """5th to 95th percentile of |ẋ| over the fitted samples [m/s]"""
    reversals: int
    """direction changes of the motion in the fitted part (between samples moving either way)"""
    inertial_share: float
    """RMS(M_eq·ẍ)/RMS(F) over the fitted samples, with the accepted M_eq"""

    @classmethod
    def of(
        cls,
        log: PreparedLog,
        fit_idx: np.ndarray,
        hold_idx: np.ndarray,
        fit_part: np.ndarray,
        M_eq: float,
        stationary_speed_m_s: float,
    ) -> WindowFacts:
        """The facts of the window ``log``: ``fit_idx`` the fitted samples (decimated), ``hold_idx``
        the held-out ones, ``fit_part`` the mask of the fitted part of the window."""
        if fit_idx.size == 0:
            return cls(0, int(hold_idx.size), 0.0, 0, 0.0)
        speed = np.abs(log.velocity_m_s[fit_idx])
        low, high = np.percentile(speed, [5.0, 95.0])
        v = log.velocity_m_s[fit_part]
        moving = np.sign(v[np.abs(v) >= stationary_speed_m_s])
        reversals = int(np.count_nonzero(moving[1:] != moving[:-1]))
        force = log.force_n[fit_idx]
        inertial = M_eq * log.acceleration_m_s2[fit_idx]
        rms_force = float(np.sqrt(np.mean(force**2)))
        share = float(np.sqrt(np.mean(inertial**2))) / rms_force if rms_force > 0.0 else 0.0
        return cls(int(fit_idx.size), int(hold_idx.size), float(high - low), reversals, share)


def check_window(facts: WindowFacts, rules: AcceptanceRules, fit_rate_hz: float) -> Verdict | None:
    """Rule 1: None if the window is informative, else the verdict saying what it lacks."""
    lacks = []
    if facts.fit_samples < rules.min_fit_samples:
        lacks.append(
            f"{facts.fit_samples} samples to fit at {fit_rate_hz:g} Hz (at least {rules.min_fit_samples})"
        )
    if facts.holdout_samples < rules.min_holdout_samples:
        lacks.append(f"{facts.holdout_samples} held-out samples (at least {rules.min_holdout_samples})")
    if facts.speed_range_m_s < rules.min_speed_range_m_s:
        lacks.append(
            f"a speed range of {facts.speed_range_m_s:.3f} m/s (at least {rules.min_speed_range_m_s:g} m/s)"
        )
    if facts.reversals < rules.min_reversals:
        lacks.append(f"{facts.reversals} direction changes (at least {rules.min_reversals})")
    if not lacks:
        return None
    return Verdict(Decision.UNINFORMATIVE, "uninformative window: " + "; ".join(lacks))


def check_uncertainty(drift: DriftFit, rules: AcceptanceRules) -> Verdict | None:
    """Rules 2 and 3: None if the fit converged with every σ within its bound."""
    if not drift.success:
        r = drift.result
        why = f"the fit did not converge ({r.status}, {r.iterations} iterations)"
        return Verdict(Decision.FIT_FAILED, why)
    over = []
    for name, relative in drift.relative_std.items():
        bound = rules.max_relative_std.get(name, math.inf)
        if not relative <= bound:
            over.append(f"σ({name}) {100 * relative:.2f} % (bound {100 * bound:g} %)")
    if not over:
        return None
    return Verdict(Decision.UNCERTAIN, "too uncertain: " + "; ".join(over))


def check_change(drift: DriftFit, accepted: AxisParams, rules: AcceptanceRules) -> Verdict | AxisParams:
    """Rule 4: the new parameters if the change is plausible, else the verdict saying why not."""
    try:
        candidate = drift.params()
    except ParameterError as exc:
        return Verdict(Decision.IMPLAUSIBLE, f"outside the physical ranges: {exc}")
    new, old = drift.values.as_dict(), FrictionValues.of(accepted).as_dict()
    over = []
    for name in PARAMETERS:
        bound = rules.max_relative_change.get(name, math.inf)
        of = ""
        if name in SIGNED_PARAMETERS:
            scale = signed_scale(name, accepted)
            if scale == 0.0:
                continue
            change, of = (new[name] - old[name]) / scale, f" of {scale:.5g}"
        elif old[name] == 0.0:
            continue
        else:
            change = new[name] / old[name] - 1.0
        if not abs(change) <= bound:
            over.append(
                f"{name} {old[name]:.5g} → {new[name]:.5g} ({100 * change:+.1f} %{of}, "
                f"bound ±{100 * bound:g} %)"
            )
    if over:
        return Verdict(Decision.IMPLAUSIBLE, "implausible change: " + "; ".join(over))
    return candidate


@dataclass(frozen=True)
class HoldoutErrors:
    """RMS torque errors [N·m] on the held-out samples."""

    estimate: float
    accepted: float
    initial: float
    samples: int


def check_holdout(errors: HoldoutErrors, rules: AcceptanceRules, version: int) -> Verdict:
    """Rule 5, the last: accepted if the estimate beats the accepted set (version ``version``) by the
    margin on the held-out samples and is not worse than the starting set there."""
    gain = 1.0 - errors.estimate / errors.accepted if errors.accepted > 0.0 else 0.0
    numbers = (
        f"held-out RMS error {errors.estimate:.5f} N·m against {errors.accepted:.5f} N·m of version "
        f"{version} ({-100 * gain:+.1f} %) and {errors.initial:.5f} N·m of version 0, "
        f"on {errors.samples} samples"
    )
    if not gain >= rules.holdout_margin:
        return Verdict(
            Decision.NO_IMPROVEMENT,
            f"no improvement: {numbers}; needs {-100 * rules.holdout_margin:.1f} % on version {version}",
        )
    if errors.estimate > errors.initial:
        return Verdict(Decision.NO_IMPROVEMENT, f"worse than the starting set: {numbers}")
    return Verdict(Decision.ACCEPTED, f"accepted: {numbers}")
