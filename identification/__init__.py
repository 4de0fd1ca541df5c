"""Friction (and inertia) identification from recorded logs: the excitation that makes every term of
eq. (1) visible, and the SQP refit of M_eq and a1…a4 from any JointState MCAP log — lost samples,
jittered stamps and all — with what the model leaves unexplained (docs/identification.md). The fit
over a window of samples (:func:`~.fit.fit_window`, warm-startable) is what an adaptive node reuses.

Uses the model and acquisition's records-and-logs layer (the fast log reader); loads no Zenoh. The
names of the fit (which needs CasADi) load on first use, so the excitation stays light.
"""

from __future__ import annotations

import importlib
from typing import Any

from .errors import IdentificationError
from .excitation import Burst, ExcitationPlan, design_excitation
from .extra_terms import ExtraTerms
from .preparation import PreparationSettings
from .sample_grid import SampleGrid, place_on_grid
from .signals import JointKind, JointSignals, load_joint
from .uncertainty import Uncertainty, estimate_uncertainty

_FIT_NAMES: dict[str, str] = {
    "PARAMETERS": "fit",
    "FitResult": "fit",
    "FrictionFit": "fit",
    "FrictionValues": "fit",
    "WindowFit": "fit",
    "fit_parameters": "fit",
    "fit_window": "fit",
    "ErrorStats": "refit",
    "Identification": "refit",
    "IdentifySettings": "refit",
    "identify": "refit",
}


def __getattr__(name: str) -> Any:
    """Load a name of the fit (and CasADi) on first use."""
    module = _FIT_NAMES.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f".{module}", __name__), name)


__all__ = [
    "Burst",
    "ExcitationPlan",
    "ExtraTerms",
    "IdentificationError",
    "JointKind",
    "JointSignals",
    "PreparationSettings",
    "SampleGrid",
    "Uncertainty",
    "design_excitation",
    "estimate_uncertainty",
    "load_joint",
    "place_on_grid",
    *_FIT_NAMES,
]
