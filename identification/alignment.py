"""The time offset between a drive's torque samples and its position samples.

A drive reports, at each tick, the position it measured at that instant and a torque that may
describe another instant: the simulated drive's torque sample k is the current of the torque it
applied through the tick before (centred 0.5 ms earlier); a real drive's current loop and its filters
have their own offset. Fitting eq. (1) with torque and acceleration out of step by δ biases the
inertia most (measured on the simulated axis: M_eq −0.17 % at δ = 0 against −0.05 % at the true
0.5 ms, where σ is 0.04 %).

So the offset is estimated, not assumed: the force is taken δ later (interpolated, on the filtered
signal, see :meth:`~axisflow.identification.preparation.PreparedLog.force_at`) and δ is the one that
minimises the fit's residual sum of squares S(δ) over ±:data:`MAX_DELAY_S` (bounded Brent search; each
step is one SQP solve with the same solver and the same extra terms, on at most
:data:`SEARCH_SAMPLES` evenly chosen samples, started where the previous step ended).

How well the log determines δ: S is a profile of the fit's objective, so near its minimum
S(δ) ≈ S* + ½·S''·(δ − δ*)² and, as for any least-squares parameter, σ_δ² = 2·s²/S'' with
s² = S*/(n − m) the residual variance (m: the parameters fitted with δ), inflated by n/n_eff for the
residuals' colour (:func:`~.uncertainty.effective_sample_size`). S'' is taken by central differences
at ±¼ sample period. δ is **resolvable** when 3·σ_δ is within one sample period; otherwise the log
cannot tell the offset from zero to within a sample, the fit uses δ = 0 and the report says so. Any
unmodelled effect that lags the motion (an elastic belt between the motor and the cart) shifts δ*
too; the report gives δ* and σ_δ so that the user can judge. ``--torque-delay S`` fixes δ instead.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..model import AxisParams
from .fit import FitResult, FrictionFit
from .preparation import Columns, PreparedLog, fit_samples
from .uncertainty import effective_sample_size

MAX_DELAY_S = 0.003
SEARCH_SAMPLES = 20_000
RESOLVING_SIGMAS = 3.0
"""δ is resolvable when this many σ fit in one sample period"""
_TOLERANCE_S = 1e-5


@dataclass(frozen=True)
class DelayEstimate:
    """The torque/position offset: what the search found, how well, and what the fit uses."""

    value_s: float
    """the offset the fit uses [s] (the estimate if resolvable, else 0)"""
    estimate_s: float
    """δ* of the search [s]"""
    std_s: float
    """σ of δ* [s] (inf where S(δ) is not convex around δ*)"""
    period_s: float
    """the logs' sample period [s]"""

    @property
    def resolvable(self) -> bool:
        return RESOLVING_SIGMAS * self.std_s <= self.period_s

    def describe(self) -> str:
        found = f"{self.estimate_s * 1e3:.3f} ± {self.std_s * 1e3:.3f} ms"
        if self.resolvable:
            return f"{self.value_s * 1e3:.3f} ms (estimated: {found})"
        return (
            f"not resolvable from this log (estimate {found}, more than a sample period of "
            f"{self.period_s * 1e3:.3g} ms within {RESOLVING_SIGMAS:g} σ): 0 used"
        )


def estimate_delay(
    logs: list[PreparedLog],
    parts: list[np.ndarray],
    nominal: AxisParams,
    fit: tuple[str, ...],
    extra: Sequence[Columns] | None = None,
    extra_names: tuple[str, ...] = (),
    extra_scales: tuple[float, ...] = (),
) -> DelayEstimate:
    """δ [s] minimising the residual sum of squares of a fit of ``fit`` (and the extra terms) on samples
    ``parts`` of ``logs``, with its σ (see the module docstring)."""
    from scipy.optimize import minimize_scalar  # scipy loads on first use, not with the package

    total = sum(p.size for p in parts)
    step = max(1, total // SEARCH_SAMPLES)
    chosen = [p[::step] for p in parts]
    base = fit_samples(logs, chosen, 0.0, extra)  # the force is taken again per delay tried, below
    problem = FrictionFit(
        base.velocity_m_s,
        base.acceleration_m_s2,
        base.effort_per_force,
        nominal,
        fit,
        extra=base.extra,
        extra_names=extra_names,
        extra_scales=extra_scales,
    )

    solved: dict[float, np.ndarray] = {}
    last: list[FitResult] = []  # the previous solve: each next one starts there (δ moves it little)

    def residuals(delay_s: float) -> np.ndarray:
        if delay_s not in solved:
            force = np.concatenate([log.force_at(p, delay_s) for log, p in zip(logs, chosen, strict=True)])
            start = last[-1] if last else None
            result = problem.solve(
                force, start.values if start else None, start.extra_vector if start else None
            )
            last[:] = [result]
            solved[delay_s] = result.residuals
        return solved[delay_s]

    def sum_of_squares(delay_s: float) -> float:
        r = residuals(delay_s)
        return float(np.dot(r, r))

    found = minimize_scalar(
        sum_of_squares, bounds=(-MAX_DELAY_S, MAX_DELAY_S), method="bounded", options={"xatol": _TOLERANCE_S}
    )
    best = float(found.x)
    period = min(1.0 / log.signals.rate_hz for log in logs)
    h = 0.25 * period
    at_best = residuals(best)
    s_best = float(np.dot(at_best, at_best))
    curvature = (sum_of_squares(best + h) - 2.0 * s_best + sum_of_squares(best - h)) / (h * h)
    n = at_best.size
    m = len(problem.names) + len(problem.extra_names) + 1
    variance = s_best / max(n - m, 1) * n / effective_sample_size(at_best)
    std = math.sqrt(2.0 * variance / curvature) if curvature > 0.0 else math.inf
    estimate = DelayEstimate(best, best, std, period)
    return estimate if estimate.resolvable else DelayEstimate(0.0, best, std, period)
