"""Friction (and inertia) identification from recorded logs: the excitation that makes every term of
eq. (1) visible, and the SQP refit of M_eq and a1…a4 from any JointState MCAP log — lost samples,
jittered stamps and all — with what the model leaves unexplained (docs/identification.md). The fit
over a window of samples (:func:`~.fit.fit_window`, warm-startable) is what an adaptive node reuses.

Installs as ``axisflow.identification`` from the folder ``identification/`` (pyproject.toml maps each
top-level folder to a sub-package of ``axisflow``; docs/architecture.md draws their imports).

Uses the model and acquisition's records-and-logs layer (the fast log reader); loads no Zenoh. Every
name is loaded with its module on first use, so the excitation stays light: the names of the fit
(which needs CasADi) load CasADi only when used.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..model import lazy_names

if TYPE_CHECKING:  # what a type checker sees; at run time __getattr__ loads each name from _HOMES
    from .errors import IdentificationError  # noqa: F401
    from .excitation import Burst, ExcitationPlan, design_excitation  # noqa: F401
    from .extra_terms import ExtraTerms  # noqa: F401
    from .fit import (  # noqa: F401
        PARAMETERS,
        FitResult,
        FrictionFit,
        FrictionValues,
        WindowFit,
        fit_parameters,
        fit_window,
    )
    from .preparation import PreparationSettings  # noqa: F401
    from .refit import ErrorStats, Identification, IdentifySettings, identify  # noqa: F401
    from .sample_grid import SampleGrid, place_on_grid  # noqa: F401
    from .signals import JointKind, JointSignals, load_joint  # noqa: F401
    from .uncertainty import Uncertainty, estimate_uncertainty  # noqa: F401

# each public name → its module, relative to this package
_HOMES: dict[str, str] = {
    "IdentificationError": "errors",
    "Burst": "excitation",
    "ExcitationPlan": "excitation",
    "design_excitation": "excitation",
    "ExtraTerms": "extra_terms",
    "PreparationSettings": "preparation",
    "SampleGrid": "sample_grid",
    "place_on_grid": "sample_grid",
    "JointKind": "signals",
    "JointSignals": "signals",
    "load_joint": "signals",
    "Uncertainty": "uncertainty",
    "estimate_uncertainty": "uncertainty",
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


__getattr__ = lazy_names(__name__, _HOMES)


__all__ = sorted(_HOMES)
