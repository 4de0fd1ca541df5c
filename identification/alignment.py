"""The time offset between a drive's torque samples and its position samples.

A drive reports, at each tick, the position it measured at that instant and a torque that may
describe another instant: the simulated drive's torque sample k is the torque it applied during the
tick before (centred 0.5 ms earlier); a real drive's current loop and its filters have their own
offset. Fitting eq. (1) with torque and acceleration out of step by δ biases the inertia most
(measured on the simulated axis: M_eq −0.17 % at δ = 0 against −0.05 % at the true 0.5 ms, where
σ is 0.04 %).

So the offset is estimated, not assumed: the force is taken δ later (interpolated, on the filtered
signal, see :meth:`~axisflow.identification.preparation.PreparedLog.force_at`) and δ is the one that
minimises the fit's residual RMS over ±:data:`MAX_DELAY_S` (bounded Brent search; each step is one
SQP solve with the same solver, on at most :data:`SEARCH_SAMPLES` evenly chosen samples). The value
is reported; ``--torque-delay S`` fixes it instead.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import minimize_scalar

from ..model import AxisParams
from .fit import FrictionFit
from .preparation import PreparedLog, fit_samples

MAX_DELAY_S = 0.003
SEARCH_SAMPLES = 20_000
_TOLERANCE_S = 1e-5


def estimate_delay(
    logs: list[PreparedLog], parts: list[np.ndarray], nominal: AxisParams, fit: tuple[str, ...]
) -> float:
    """δ [s] minimising the residual RMS of a fit of ``fit`` on samples ``parts`` of ``logs``."""
    total = sum(p.size for p in parts)
    step = max(1, total // SEARCH_SAMPLES)
    chosen = [p[::step] for p in parts]
    base = fit_samples(logs, chosen)  # the force is taken again per delay tried, below
    problem = FrictionFit(base.velocity_m_s, base.acceleration_m_s2, base.effort_per_force, nominal, fit)

    def rms(delay_s: float) -> float:
        force = np.concatenate([log.force_at(p, delay_s) for log, p in zip(logs, chosen, strict=True)])
        return problem.solve(force).rms

    result = minimize_scalar(
        rms, bounds=(-MAX_DELAY_S, MAX_DELAY_S), method="bounded", options={"xatol": _TOLERANCE_S}
    )
    return float(result.x)
