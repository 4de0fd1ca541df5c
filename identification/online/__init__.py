"""Online re-identification: eq. (1)'s friction (and M_eq) refit over a sliding window of live samples,
and the rules that decide whether an estimate replaces the accepted parameters (docs/adaptation.md).

* :mod:`.ring` — the newest samples of the motor joint, a fixed-size ring of numpy arrays;
* :mod:`.window` — a window of them as the refit's signals (on the drive's sampling grid, holes counted);
* :mod:`.drift_fit` — the fit of what drifts (M_eq, a2 and one common scale of a1 and a3 by default,
  and the offset and asymmetry where the axis has them),
  :func:`~axisflow.identification.fit.fit_window` warm-started from the last window;
* :mod:`.acceptance` — informative window, σ bounds, plausible change, better on held-out samples;
* :mod:`.adapter` — the state of one axis's adaptation: window → fit → verdict → a
  :class:`~axisflow.acquisition.wire.params_estimate.ParamsEstimate` record.

No Zenoh here: ``axisflow adapt`` (axisflow/nodes/adapt_node.py) feeds an :class:`~.adapter.Adapter` from the
bus; tests and benchmarks can feed it from anything.
"""

from __future__ import annotations

from .acceptance import AcceptanceRules, Verdict, WindowFacts
from .adapter import Adapter, AdaptSettings, load_fit_libraries
from .drift_fit import COULOMB, DEFAULT_TERMS, DriftFit, check_terms, default_terms, fit_drift, signed_scale
from .ring import SampleRing
from .window import window_signals

__all__ = [
    "COULOMB",
    "DEFAULT_TERMS",
    "AcceptanceRules",
    "AdaptSettings",
    "Adapter",
    "DriftFit",
    "SampleRing",
    "Verdict",
    "WindowFacts",
    "check_terms",
    "default_terms",
    "fit_drift",
    "load_fit_libraries",
    "signed_scale",
    "window_signals",
]
