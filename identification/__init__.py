"""Friction (and inertia) identification from recorded logs: the excitation that makes every term of
eq. (1) visible, and the SQP refit of M_eq and a1…a4 from any JointState MCAP log (docs/identification.md).

Uses the model and acquisition's records-and-logs layer (the fast log reader); loads no Zenoh. The
names of the fit (which needs CasADi) load on first use, so the excitation stays light.
"""

from __future__ import annotations

import importlib
from typing import Any

from .excitation import Burst, ExcitationPlan, design_excitation
from .preparation import PreparationSettings
from .signals import IdentificationError, JointKind, JointSignals, load_joint
from .uncertainty import Uncertainty, estimate_uncertainty

_FIT_NAMES: dict[str, str] = {
    "PARAMETERS": "fit",
    "FitResult": "fit",
    "FrictionFit": "fit",
    "FrictionValues": "fit",
    "fit_parameters": "fit",
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
    "IdentificationError",
    "JointKind",
    "JointSignals",
    "PreparationSettings",
    "Uncertainty",
    "design_excitation",
    "estimate_uncertainty",
    "load_joint",
    *_FIT_NAMES,
]
