"""Friction (and inertia) identification from recorded logs: the excitation that makes every term of
eq. (1) visible, and the SQP refit of M_eq and a1…a4 from any JointState MCAP log (docs/identification.md).

Uses the model and acquisition's records-and-logs layer (the fast log reader); loads no Zenoh.
"""

from .excitation import Burst, ExcitationPlan, design_excitation
from .fit import PARAMETERS, FitResult, FrictionFit, FrictionValues, fit_parameters
from .preparation import PreparationSettings
from .refit import ErrorStats, Identification, IdentifySettings, identify
from .signals import IdentificationError, JointKind, JointSignals, load_joint
from .uncertainty import Uncertainty, estimate_uncertainty

__all__ = [
    "PARAMETERS",
    "Burst",
    "ErrorStats",
    "ExcitationPlan",
    "FitResult",
    "FrictionFit",
    "FrictionValues",
    "Identification",
    "IdentificationError",
    "IdentifySettings",
    "JointKind",
    "JointSignals",
    "PreparationSettings",
    "Uncertainty",
    "design_excitation",
    "estimate_uncertainty",
    "fit_parameters",
    "identify",
    "load_joint",
]
