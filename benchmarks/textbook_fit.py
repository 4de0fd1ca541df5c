"""The textbook baseline of a drive's identification, and the issue's measure of a model on held-out data.

**The baseline** is the inverse-model least squares with four parameters (IDIM-LS): the measured
force is linear in the parameters,

    F_k = M·q̈_k + Fv·q̇_k + Fc·sign(q̇_k) + F0 + e_k,

so (M, Fv, Fc, F0) are the ordinary least-squares solution over the samples, q̇ and q̈ the derivatives
of the zero-phase filtered position. It is fitted here on exactly the samples ``axisflow identify``
fits (:func:`~axisflow.identification.preparation.prepare` with its default settings: the same filter,
the same samples left out, the same decimation), so that a comparison of the two differs in the model
only. ``offset=False`` drops F0 (the three-parameter variant).

**The measure** (the issue's): ‖F − F̂‖/‖F‖ over the samples of a log where the cart moves, F the
measured force and F̂ the model's, both through a zero-phase low-pass at :data:`SCORE_CUTOFF_HZ`
(Butterworth, order 4, forward and backward); F̂ is computed from the derivatives of the position
through the same filter. A model with a torque/position offset δ (``identify`` estimates one)
predicts the force at t from the kinematics at t − δ. Samples at rest (|q̇| below
:data:`MOVING_M_S` by that derivative) are not scored: there the force is whatever static friction
holds, which none of these models describes, and the sign of a filtered velocity that is zero but
for rounding would decide a Coulomb term of ±Fc by chance.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from ..identification.preparation import PreparationSettings, PreparedLog, prepare
from ..identification.signals import JointSignals

SCORE_CUTOFF_HZ = 100.0
SCORE_ORDER = 4
MOVING_M_S = 0.002
"""a sample is scored where the scoring filter's velocity is at least this [m/s]"""


@dataclass(frozen=True)
class TextbookFit:
    """The four (or three) parameters of the inverse-model least squares, SI units."""

    mass_kg: float
    viscous_n_s_per_m: float
    coulomb_n: float
    offset_n: float
    samples: int

    def force_n(self, velocity_m_s: np.ndarray, acceleration_m_s2: np.ndarray) -> np.ndarray:
        v = np.asarray(velocity_m_s, dtype=float)
        return (
            self.mass_kg * np.asarray(acceleration_m_s2)
            + self.viscous_n_s_per_m * v
            + self.coulomb_n * np.sign(v)
            + self.offset_n
        )


def fit_textbook(logs: Sequence[PreparedLog], offset: bool = True) -> TextbookFit:
    """The least squares over the fit samples of prepared ``logs`` (their usable samples decimated to
    the preparation's default fit rate, as ``identify`` fits them)."""
    rate = PreparationSettings().fit_rate_hz
    rows, forces = [], []
    for log in logs:
        idx = log.fit_indices(rate)
        v, a = log.velocity_m_s[idx], log.acceleration_m_s2[idx]
        columns = [a, v, np.sign(v)] + ([np.ones_like(v)] if offset else [])
        rows.append(np.column_stack(columns))
        forces.append(log.force_n[idx])
    x, f = np.vstack(rows), np.concatenate(forces)
    theta, *_ = np.linalg.lstsq(x, f, rcond=None)
    return TextbookFit(
        mass_kg=float(theta[0]),
        viscous_n_s_per_m=float(theta[1]),
        coulomb_n=float(theta[2]),
        offset_n=float(theta[3]) if offset else 0.0,
        samples=int(f.size),
    )


def scoring_log(signals: JointSignals) -> PreparedLog:
    """``signals`` through the measure's filter: the kinematics every model is scored with."""
    return prepare(signals, PreparationSettings(cutoff_hz=SCORE_CUTOFF_HZ, order=SCORE_ORDER), np.inf)


def relative_force_error(
    signals: JointSignals,
    model: Callable[[PreparedLog], np.ndarray],
    delay_s: float = 0.0,
) -> float:
    """‖F − F̂‖/‖F‖ over the moving samples of ``signals`` (module docstring); ``model`` gives the model's
    force [N] at every sample of the scoring log, ``delay_s`` the model's torque/position offset."""
    from scipy.signal import butter, sosfiltfilt  # scipy loads on first use

    log = scoring_log(signals)
    predicted = model(log)
    if delay_s:
        t = log.signals.t_s
        predicted = np.interp(t - delay_s, t, predicted)
    rate = signals.rate_hz
    sos = butter(SCORE_ORDER, SCORE_CUTOFF_HZ, fs=rate, output="sos")
    measured = log.force_n  # already through the same filter
    predicted = sosfiltfilt(sos, predicted)
    moving = np.abs(log.velocity_m_s) >= MOVING_M_S
    return float(np.linalg.norm((measured - predicted)[moving]) / np.linalg.norm(measured[moving]))
