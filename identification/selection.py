"""Which terms a log supports: candidate structures compared on held-out data (``identify --terms auto``).

A *structure* is the set of terms a fit takes in (their names: :mod:`axisflow.model.terms`): Coulomb
and viscous friction (always, with M_eq), then optionally the friction law's ``offset``, ``asymmetry``
and ``atan``, the Coulomb friction along the stroke and cogging (:mod:`.extra_terms`). Fitting all 2ⁿ
sets would be slow and pointless; the candidates are:

1. **the friction law's structures** (:func:`law_candidates`), built up the way a drive's friction
   is: the base alone, + the paper's atan term, + a constant force f0, + both, + an asymmetry, + all;
   and each candidate with a term the data do not support (below) is tried again without it.
   The asymmetry is the viscous one (da2) while f0 is fitted: moving, a Coulomb asymmetry da1 and f0
   are the same constant per direction, and no log tells them apart. When the parameter file gives
   f0 (gravity on a known incline, say), f0 stays at its value in every candidate, the offset is no
   candidate, and the asymmetry is both da1 and da2. A term a candidate does not take in is off
   (zero), never left at the nominal axis's value;
2. then the best of those (by the rule below) **with the stroke terms** (``--stroke-terms K`` > 0).

Cogging is no candidate here: the orders given (``--cogging ORDERS``) and those a first fit's residual
shows (``--cogging auto``) are taken in on the chosen structure (:mod:`.refit`), and dropped again if
the final fit does not support them (the σ rule below).

Each candidate is scored by **time-blocked cross-validation**: the fit samples of the logs, in time
order, are cut into contiguous blocks, which are dealt to :data:`FOLDS` folds in turn (block i to
fold i mod k: up to :data:`BLOCKS_PER_FOLD` blocks a fold, each at least :data:`MIN_BLOCK_S` of
the log); the candidate is fitted on all folds but one and its effort error (RMS, measured minus
model, through the fit's filter) is measured on the fold left out, for each fold in turn. Contiguous
blocks keep the neighbours of a held-out sample out of the fit (the filtered signals are correlated
over tens of milliseconds: a random split would score the fit on samples it has nearly seen); dealing
several blocks to each fold lets every fold's fit see every part of the log's program (all speeds,
the whole stretch of the stroke), so that a term that depends on where the cart is, the stroke's, is
scored on what it models and not on extrapolating to a stretch its fit never saw. With
``--validate`` logs, the candidate fitted on every fold is also scored on each validation log, which
counts as one more held-out score. The scores' mean and standard error (sd/√n) are the candidate's
held-out error. (A validation log with another program also catches what no split of one log can:
a term that fits a coincidence the whole log repeats, such as a speed tied to a place on the
stroke.)

**The one-standard-error rule** (Hastie, Tibshirani and Friedman, *The Elements of Statistical
Learning*, 2nd ed., §7.10): among the candidates whose terms the data support (below), the one of
lowest mean held-out error sets a threshold, its mean plus its standard error; the candidate chosen
is the simplest (fewest estimated parameters) whose mean is within that threshold. A term that
buys less than the noise between folds is not taken.

**Supported terms.** A term is *not supported* when its σ (from the fit on every block, inflated for
the effective sample size: :mod:`.uncertainty`) is larger than its value: for a term of one
parameter, σ > |value|; for the atan term, σ > value for a3 or for a4; for a term of several
coefficients (the stroke's Legendre terms, a cogging order's sine and cosine, an asymmetry of two
values), the same in the multivariate form √(βᵀC⁻¹β/p) < 1 (the coefficients' RMS in units of
their covariance). A candidate with an unsupported term is not chosen; the base terms are never
dropped (an unsupported Coulomb or viscous term is reported).

**Cost.** At most :data:`SELECTION_SAMPLES` fit samples take part (evenly thinned, in every block),
and each candidate is one problem (:class:`.fit.FrictionFit`) solved once per fold with the other
blocks' samples held out (scored, not fitted): an hour of log selects in about the time of one
fit. The torque/position offset is estimated once, on those samples, with the richest law
structure (or given). The chosen structure is then fitted on every sample, as a fixed structure is.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..model.terms import LAW_TERMS, TERMS, canonical_terms
from .alignment import estimate_delay
from .errors import IdentificationError
from .extra_terms import ExtraTerms
from .fit import FitResult, FrictionFit
from .preparation import PreparationSettings, PreparedLog, fit_samples
from .uncertainty import INSEPARABLE_CORRELATION, Uncertainty, estimate_uncertainty

if TYPE_CHECKING:
    from ..model import AxisParams

BASE_TERMS = ("coulomb", "viscous")
"""the terms every structure has (with the inertia M_eq)"""
OPTIONAL_TERMS = tuple(t for t in LAW_TERMS if t not in BASE_TERMS)
"""the friction law's optional terms (offset, asymmetry, atan), in the order a structure lists them"""


def law_candidates(offset_given: bool) -> tuple[tuple[str, ...], ...]:
    """The friction law's structures the selection tries (stage 1; module docstring)."""
    if offset_given:
        return ((), ("atan",), ("asymmetry",), ("asymmetry", "atan"))
    return (
        (),
        ("atan",),
        ("offset",),
        ("offset", "atan"),
        ("offset", "asymmetry"),
        ("offset", "asymmetry", "atan"),
    )


FOLDS = 5
BLOCKS_PER_FOLD = 4
MIN_BLOCK_S = 2.0
"""a cross-validation block spans at least this much of the logs [s] (the residuals' correlation is
a fraction of a second)"""
SELECTION_SAMPLES = 5000
"""at most this many fit samples (of all logs) take part in the selection"""
RULE = "one-standard-error rule over time-blocked cross-validation"


@dataclass(frozen=True)
class Structure:
    """The terms of one fit (module docstring)."""

    law: tuple[str, ...] = ()
    """optional terms of the friction law, in :data:`OPTIONAL_TERMS` order"""
    stroke_terms: int = 0
    cogging_orders: tuple[int, ...] = ()

    def __post_init__(self) -> None:
        unknown = [t for t in self.law if t not in OPTIONAL_TERMS]
        if unknown:
            raise IdentificationError(f"unknown law terms {unknown}: choose from {', '.join(OPTIONAL_TERMS)}")
        object.__setattr__(self, "law", tuple(t for t in OPTIONAL_TERMS if t in self.law))

    @property
    def terms(self) -> tuple[str, ...]:
        """Every term's name: the base, the law's, then ``stroke`` and ``cogging`` if taken in."""
        extra = ("stroke",) * bool(self.stroke_terms) + ("cogging",) * bool(self.cogging_orders)
        return BASE_TERMS + self.law + extra

    @property
    def label(self) -> str:
        return "+".join(self.terms)

    @property
    def extra(self) -> ExtraTerms:
        return ExtraTerms(self.stroke_terms, self.cogging_orders)


def offset_given(nominal: AxisParams, given: frozenset[str] | None = None) -> bool:
    """Whether the user's parameter file gives the constant force f0 (then it is held, and da1 may be
    fitted); ``given``: the keys the file gives (None: every value of ``nominal`` is the user's)."""
    return "offset" in nominal.terms and (given is None or "f0" in given)


ATAN_START_SPEED_FRACTION = 0.1
"""an atan term the file does not give starts bending at this fraction of the log's typical speed:
a4 = 1/(fraction × speed) (the fit moves it; a start of zero could not: a3·atan(0) has no slope)"""


def fit_plan(
    structure: Structure,
    nominal: AxisParams,
    given: frozenset[str] | None = None,
    speed_m_s: float | None = None,
) -> tuple[tuple[str, ...], AxisParams]:
    """The parameters a fit of ``structure`` estimates, and the parameters it starts from (their terms
    on, the others off: zero). Everything in the structure is fitted but a constant force the user's
    file gives (held: :func:`offset_given`); with f0 fitted, the asymmetry is the viscous one and
    da1 = 0 (f0 takes the constant per direction). An atan term the file lacks starts from a3 = a1/2
    and a4 from ``speed_m_s`` (the log's typical speed, :func:`typical_speed_m_s`)."""
    held_offset = offset_given(nominal, given)
    law = structure.law
    names = ["M_eq", "a1", "a2"]
    if "offset" in law and not held_offset:
        names.append("f0")
    if "asymmetry" in law:
        names += ["da1", "da2"] if held_offset else ["da2"]
    if "atan" in law:
        names += ["a3", "a4"]
    on = BASE_TERMS + (("offset",) if held_offset else ()) + law
    values: dict[str, float] = {p: 0.0 for t in TERMS if t not in on for p in TERMS[t].parameters}
    if "asymmetry" in law and not held_offset:
        values["da1"] = 0.0
    if "atan" in law and not (nominal.a3 and nominal.a4):
        speed = speed_m_s if speed_m_s and speed_m_s > 0.0 else nominal.v_max
        values["a3"] = 0.5 * nominal.a1 if nominal.a1 > 0.0 else 1.0
        values["a4"] = 1.0 / (ATAN_START_SPEED_FRACTION * speed)
    return tuple(names), nominal.replace(**values, terms=canonical_terms(on))


def typical_speed_m_s(logs: Sequence[PreparedLog], parts: Sequence[np.ndarray]) -> float:
    """The median speed [m/s] of the fit samples ``parts`` of ``logs`` (0 if none)."""
    speeds = [np.abs(log.velocity_m_s[p]) for log, p in zip(logs, parts, strict=True) if p.size]
    return float(np.median(np.concatenate(speeds))) if speeds else 0.0


def term_parameters(structure: Structure, fitted: tuple[str, ...]) -> dict[str, tuple[str, ...]]:
    """Each term of ``structure`` and the names of its parameters (or coefficients) among ``fitted``."""
    out: dict[str, tuple[str, ...]] = {}
    for term in BASE_TERMS + structure.law:
        names = tuple(n for n in TERMS[term].parameters if n in fitted)
        if names:
            out[term] = names
    extra = structure.extra.names
    if structure.stroke_terms:
        out["stroke"] = tuple(n for n in extra if not n.startswith("cog"))
    if structure.cogging_orders:
        out["cogging"] = tuple(n for n in extra if n.startswith("cog"))
    return out


PER_PARAMETER_TERMS = ("atan",)
"""terms whose every parameter must be supported on its own (a4 is meaningless without a3 and back)"""


def unsupported_terms(structure: Structure, estimates: dict[str, float], unc: Uncertainty) -> tuple[str, ...]:
    """The terms of ``structure`` whose σ is larger than their value (module docstring)."""
    out = []
    for term, names in term_parameters(structure, unc.names).items():
        if term in PER_PARAMETER_TERMS or len(names) == 1:
            if any(unc.std[n] > abs(estimates[n]) for n in names):
                out.append(term)
            continue
        index = [unc.names.index(n) for n in names]
        std = np.array([unc.std[n] for n in names])
        cov = unc.correlation[np.ix_(index, index)] * np.outer(std, std)
        beta = np.array([estimates[n] for n in names])
        wald = float(beta @ np.linalg.pinv(cov) @ beta) / len(names)
        if not wald >= 1.0:
            out.append(term)
    return tuple(out)


@dataclass(frozen=True, eq=False)
class CandidateScore:
    """One candidate's held-out errors and what its fit on every block says about its terms."""

    structure: Structure
    fold_rms: tuple[float, ...]
    """held-out RMS effort error of each block [effort units]"""
    validation_rms: tuple[float, ...]
    """RMS effort error on each validation log [effort units]"""
    estimates: dict[str, float]
    std: dict[str, float]
    condition_number: float
    unsupported: tuple[str, ...]
    """terms whose σ is larger than their value"""
    flagged: tuple[tuple[str, str, float], ...]
    """pairs of parameters the fit cannot separate (|ρ| above the uncertainty's limit)"""
    converged: bool
    parameters: int
    """estimated parameters (the simplicity the rule counts)"""

    @property
    def scores(self) -> tuple[float, ...]:
        return self.fold_rms + self.validation_rms

    @property
    def mean(self) -> float:
        return float(np.mean(self.scores))

    @property
    def standard_error(self) -> float:
        s = self.scores
        return float(np.std(s, ddof=1) / math.sqrt(len(s))) if len(s) > 1 else 0.0

    @property
    def eligible(self) -> bool:
        """Converged, and every optional term supported (the base terms never count against it)."""
        return self.converged and not [t for t in self.unsupported if t not in BASE_TERMS]


@dataclass(frozen=True, eq=False)
class Selection:
    """What the selection tried and chose (module docstring)."""

    candidates: tuple[CandidateScore, ...]
    chosen: Structure
    best: Structure
    """the eligible candidate of lowest mean held-out error"""
    threshold: float
    """the best's mean plus its standard error [effort units]"""
    folds: int
    validation_logs: int
    samples: int
    """fit samples that took part (all logs)"""
    delay_s: float
    """the torque/position offset the selection's fits used [s]"""
    notes: tuple[str, ...] = field(default=())
    """what the data support and what they cannot separate, in words"""

    def score_of(self, structure: Structure) -> CandidateScore:
        return next(c for c in self.candidates if c.structure == structure)


def choose(candidates: Sequence[CandidateScore]) -> tuple[CandidateScore, CandidateScore, float]:
    """(the chosen, the best, the threshold) by the one-standard-error rule among the eligible
    candidates (module docstring)."""
    eligible = [c for c in candidates if c.eligible]
    if not eligible:
        raise IdentificationError("no candidate structure converged to a fit the data support")
    best = min(eligible, key=lambda c: c.mean)
    threshold = best.mean + best.standard_error
    within = [c for c in eligible if c.mean <= threshold]
    chosen = min(within, key=lambda c: (c.parameters, c.mean))
    return chosen, best, threshold


def fold_labels(samples: int, span_s: float, folds: int = FOLDS) -> np.ndarray:
    """The fold of each of ``samples`` samples in time order spanning ``span_s`` of log: contiguous
    blocks of at least :data:`MIN_BLOCK_S` (at most :data:`BLOCKS_PER_FOLD` a fold), dealt to the
    folds in turn (module docstring)."""
    per_fold = min(BLOCKS_PER_FOLD, max(1, int(span_s / (folds * MIN_BLOCK_S))))
    blocks = folds * per_fold
    return (np.arange(samples) * blocks // samples) % folds


class _SelectionData:
    """The samples every candidate is fitted and scored on: thinned fit samples of the fit logs, labelled
    by block (0 … FOLDS−1), then those of each validation log (labelled FOLDS, FOLDS+1, …)."""

    def __init__(
        self,
        logs: Sequence[PreparedLog],
        parts: Sequence[np.ndarray],
        val_logs: Sequence[PreparedLog],
        val_parts: Sequence[np.ndarray],
        folds: int,
    ) -> None:
        fit_total = sum(p.size for p in parts)
        step = max(1, math.ceil(fit_total / SELECTION_SAMPLES))
        self.fit_parts = [p[::step] for p in parts]
        n_fit = sum(p.size for p in self.fit_parts)
        if n_fit < 2 * folds:
            raise IdentificationError(
                f"{n_fit} fit samples are too few to compare candidates in {folds} folds"
            )
        val_step = [max(1, math.ceil(p.size / SELECTION_SAMPLES)) for p in val_parts]
        self.val_parts = [p[::s] for p, s in zip(val_parts, val_step, strict=True)]
        self.logs = list(logs) + list(val_logs)
        self.parts = self.fit_parts + self.val_parts
        spans = [
            float(np.ptp(log.signals.t_s[p])) for log, p in zip(logs, self.fit_parts, strict=True) if p.size
        ]
        labels = [fold_labels(n_fit, sum(spans), folds)]
        labels += [np.full(p.size, folds + i) for i, p in enumerate(self.val_parts)]
        self.labels = np.concatenate(labels)
        self.folds = folds
        self.fitted = self.labels < folds
        self.samples = n_fit


def select_structure(
    logs: Sequence[PreparedLog],
    parts: Sequence[np.ndarray],
    val_logs: Sequence[PreparedLog],
    val_parts: Sequence[np.ndarray],
    nominal: AxisParams,
    preparation: PreparationSettings,
    stretch_m: tuple[float, float],
    stroke_terms: int,
    delay_s: float | None = None,
    folds: int = FOLDS,
    given: frozenset[str] | None = None,
    speed_m_s: float | None = None,
) -> Selection:
    """Choose the structure of a fit of ``logs`` (samples ``parts``), scored also on ``val_logs``
    (samples ``val_parts``), by the rule of the module docstring."""
    data = _SelectionData(logs, parts, val_logs, val_parts, folds)
    held_offset = offset_given(nominal, given)
    candidates = law_candidates(held_offset)

    def plan(structure: Structure) -> tuple[tuple[str, ...], AxisParams]:
        return fit_plan(structure, nominal, given, speed_m_s)

    if delay_s is None:
        names, start = plan(Structure(candidates[-1]))
        delay_s = estimate_delay(list(logs), data.fit_parts, start, names).value_s
    run = _Candidates(data, nominal, preparation, stretch_m, delay_s, plan)
    scores = run.scores([Structure(law) for law in candidates])
    chosen, _best, _threshold = choose(scores)
    law = chosen.structure.law
    scores += run.scores([Structure(law, stroke_terms)] if stroke_terms else [], scores)
    chosen, best, threshold = choose(scores)
    return Selection(
        candidates=tuple(scores),
        chosen=chosen.structure,
        best=best.structure,
        threshold=threshold,
        folds=folds,
        validation_logs=len(val_logs),
        samples=data.samples,
        delay_s=delay_s,
        notes=tuple(_notes(scores, chosen, held_offset)),
    )


def without_terms(structure: Structure, terms: Sequence[str]) -> Structure:
    """``structure`` with ``terms`` (optional ones: law terms, ``stroke``, ``cogging``) taken out."""
    law = tuple(t for t in structure.law if t not in terms)
    stroke = 0 if "stroke" in terms else structure.stroke_terms
    cogging = () if "cogging" in terms else structure.cogging_orders
    return Structure(law, stroke, cogging)


class _Candidates:
    """Scores candidate structures on one set of selection samples."""

    def __init__(
        self,
        data: _SelectionData,
        nominal: AxisParams,
        preparation: PreparationSettings,
        stretch_m: tuple[float, float],
        delay_s: float,
        plan: Callable[[Structure], tuple[tuple[str, ...], AxisParams]],
    ) -> None:
        self.data, self.nominal, self.preparation = data, nominal, preparation
        self.stretch, self.delay_s, self.plan = stretch_m, delay_s, plan

    def scores(
        self, structures: Sequence[Structure], done: Sequence[CandidateScore] = ()
    ) -> list[CandidateScore]:
        """The scores of ``structures`` and, for each with unsupported optional terms, of the structure
        without them (the selection drops a term the data do not support), each structure once."""
        seen = {c.structure for c in done}
        out: list[CandidateScore] = []
        queue = list(structures)
        while queue:
            structure = queue.pop(0)
            if structure in seen:
                continue
            seen.add(structure)
            score = self.score(structure)
            out.append(score)
            dropped = [t for t in score.unsupported if t not in BASE_TERMS]
            if dropped:
                queue.append(without_terms(structure, dropped))
        return out

    def score(self, structure: Structure) -> CandidateScore:
        d = self.data
        names, start = self.plan(structure)
        extra = structure.extra
        columns = [extra.columns(log, self.stretch, self.nominal, self.preparation) for log in d.logs]
        samples = fit_samples(d.logs, d.parts, self.delay_s, columns if len(extra) else None)
        problem = FrictionFit(
            samples.velocity_m_s,
            samples.acceleration_m_s2,
            samples.effort_per_force,
            start,
            names,
            extra=samples.extra,
            extra_names=extra.names,
            extra_scales=extra.scales(self.nominal),
        )
        full = problem.solve(samples.force_n, kept=d.fitted)
        converged = full.success
        fold_rms = []
        for j in range(d.folds):
            held = d.labels == j
            fold = problem.solve(samples.force_n, full.values, full.extra_vector, kept=d.fitted & ~held)
            converged = converged and fold.success
            fold_rms.append(_rms(fold.residuals[held]))
        validation_rms = tuple(_rms(full.residuals[d.labels == d.folds + i]) for i in range(len(d.val_parts)))
        unc = _uncertainty(full, d.fitted)
        estimates = full.estimates
        flagged = tuple(f for f in unc.flagged if abs(f[2]) > INSEPARABLE_CORRELATION)
        return CandidateScore(
            structure=structure,
            fold_rms=tuple(fold_rms),
            validation_rms=validation_rms,
            estimates=estimates,
            std=unc.std,
            condition_number=unc.condition_number,
            unsupported=unsupported_terms(structure, estimates, unc),
            flagged=flagged,
            converged=converged,
            parameters=len(full.terms),
        )


def _uncertainty(result: FitResult, fitted: np.ndarray) -> Uncertainty:
    return estimate_uncertainty(
        result.terms, result.estimates, result.jacobian[fitted], result.residuals[fitted]
    )


def _rms(x: np.ndarray) -> float:
    return float(np.sqrt(np.mean(x * x))) if x.size else math.nan


SEPARATION_REASONS = {
    frozenset(("a1", "a3")): (
        ": a3·atan(a4·v) is nearly the constant a3·π/2 above |v| ≈ 3/a4, where it adds to a1; only time "
        "at low speed tells them apart (a1 + a3·π/2 stays determined)"
    ),
    frozenset(
        ("a2", "a3")
    ): ": the atan term's slope stands in for viscous friction over the speeds the log covers",
    frozenset(("f0", "da1")): ": while the axis moves both are one constant force per direction",
}
"""why two parameters are hard to tell apart, where the physics says (docs/identification.md)"""


def _term_of(name: str) -> str:
    """The term a parameter (or coefficient) belongs to (``inertia`` for M_eq)."""
    if name == "M_eq":
        return "inertia"
    law = next((t.name for t in TERMS.values() if name in t.parameters), None)
    return law or ("cogging" if name.startswith("cog") else "stroke")


def _notes(scores: Sequence[CandidateScore], chosen: CandidateScore, given: bool) -> list[str]:
    """What the data support and what they cannot separate, in words."""
    notes = []
    taken = [t for t in chosen.structure.terms if t not in BASE_TERMS]
    offered = sorted({t for c in scores for t in c.structure.terms if t not in BASE_TERMS})
    left = [t for t in offered if t not in taken]
    notes.append(
        f"the data support {', '.join(taken) if taken else 'no term'} beyond Coulomb and viscous friction"
        + (f"; not taken: {', '.join(left)}" if left else "")
    )
    where: dict[str, list[str]] = {}
    for c in scores:
        for term in c.unsupported:
            where.setdefault(term, []).append(c.structure.label)
    for term, labels in where.items():
        action = "reported" if term in BASE_TERMS else "each tried again without it"
        notes.append(f"{term} is not supported (σ larger than its value) in {', '.join(labels)} ({action})")
    if given:
        notes.append("f0 is the parameter file's (held); the asymmetry is Coulomb (da1) and viscous (da2)")
    else:
        notes.append(
            "a Coulomb asymmetry da1 is not fitted beside f0: while the axis moves both are the same "
            "constant force per direction; give f0 in the parameter file (e.g. gravity on a known incline) "
            "to fit da1"
        )
    strongest: dict[tuple[str, str], tuple[str, str, float, str]] = {}
    for c in scores:  # each pair of parameters of different terms, where its correlation is strongest
        if not c.converged:
            continue
        for a, b, rho in c.flagged:
            if _term_of(a) == _term_of(b):
                continue
            if (a, b) not in strongest or abs(rho) > abs(strongest[(a, b)][2]):
                strongest[(a, b)] = (a, b, rho, c.structure.label)
    for a, b, rho, label in strongest.values():
        why = SEPARATION_REASONS.get(frozenset((a, b)), "")
        notes.append(
            f"the data cannot separate {a} ({_term_of(a)}) from {b} ({_term_of(b)}): correlation {rho:+.3f} "
            f"in {label}{why}"
        )
    return notes
