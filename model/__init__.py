"""The shared model of the axis: parameters, eq. (1) dynamics, friction, motion laws, energy, limits,
and the drive's 1 kHz sampling rule.

Installs as ``axisflow.model`` from the folder ``model/`` (pyproject.toml maps each top-level
folder to a sub-package of ``axisflow``; docs/architecture.md draws their imports).

This is the bottom layer of axisflow: it depends on numpy/scipy only, and everything else
(acquisition, identification, planner, viz, the command line) imports it, never the reverse.

Each public name is loaded with its module on first use, so that importing one module of the model
(``axisflow.model.errors``, say) costs that module only.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # what a type checker sees; at run time __getattr__ loads each name from _HOMES
    from .braking import StopProfile, braking_acceleration, stop_profile  # noqa: F401
    from .dynamics import (  # noqa: F401
        cart_force,
        cart_force_from_torque,
        mechanical_power,
        motor_angle,
        motor_speed,
        motor_torque,
    )
    from .energy import count_power, motion_energy, move_energy, trace_energy, trace_energy_at  # noqa: F401
    from .errors import AxisflowError, AxisflowWarning, MoveError, ParameterError  # noqa: F401
    from .friction import (  # noqa: F401
        FRICTION_PARAMETERS,
        ForwardLaw,
        FrictionLaw,
        forward_friction,
        friction_curvature,
        friction_expression,
        friction_force,
        friction_law,
        friction_regressors,
        friction_slope,
    )
    from .limits import LimitReport, check_limits, execution_times  # noqa: F401
    from .motion_laws import (  # noqa: F401
        MAX_MOVE_DURATION_S,
        POLYNOMIAL_LAWS,
        Motion,
        Move,
        MoveSamples,
        PolynomialLaw,
        polynomial_law,
    )
    from .params import AxisParams, EnergyAccounting, default_params, load_params, params_to_toml  # noqa: F401
    from .sampling import (  # noqa: F401
        EXECUTION_PERIOD_NS,
        EXECUTION_PERIOD_S,
        EXECUTION_RATE_HZ,
        move_ticks,
        sample_count,
        ticks_to_seconds,
    )
    from .terms import LAW_TERMS, TERMS, parse_terms  # noqa: F401
    from .trajectory import SampledTrajectory  # noqa: F401
    from .transmission import TRANSMISSION_KINDS, Transmission  # noqa: F401

# each public name → its module, relative to this package
_HOMES: dict[str, str] = {
    "StopProfile": "braking",
    "braking_acceleration": "braking",
    "stop_profile": "braking",
    "cart_force": "dynamics",
    "cart_force_from_torque": "dynamics",
    "mechanical_power": "dynamics",
    "motor_angle": "dynamics",
    "motor_speed": "dynamics",
    "motor_torque": "dynamics",
    "count_power": "energy",
    "motion_energy": "energy",
    "move_energy": "energy",
    "trace_energy": "energy",
    "trace_energy_at": "energy",
    "AxisflowError": "errors",
    "AxisflowWarning": "errors",
    "MoveError": "errors",
    "ParameterError": "errors",
    "FRICTION_PARAMETERS": "friction",
    "ForwardLaw": "friction",
    "FrictionLaw": "friction",
    "forward_friction": "friction",
    "friction_law": "friction",
    "friction_curvature": "friction",
    "friction_expression": "friction",
    "friction_force": "friction",
    "friction_regressors": "friction",
    "friction_slope": "friction",
    "LimitReport": "limits",
    "check_limits": "limits",
    "execution_times": "limits",
    "MAX_MOVE_DURATION_S": "motion_laws",
    "POLYNOMIAL_LAWS": "motion_laws",
    "Motion": "motion_laws",
    "Move": "motion_laws",
    "MoveSamples": "motion_laws",
    "PolynomialLaw": "motion_laws",
    "polynomial_law": "motion_laws",
    "AxisParams": "params",
    "EnergyAccounting": "params",
    "default_params": "params",
    "load_params": "params",
    "params_to_toml": "params",
    "EXECUTION_PERIOD_NS": "sampling",
    "EXECUTION_PERIOD_S": "sampling",
    "EXECUTION_RATE_HZ": "sampling",
    "move_ticks": "sampling",
    "sample_count": "sampling",
    "ticks_to_seconds": "sampling",
    "SampledTrajectory": "trajectory",
    "LAW_TERMS": "terms",
    "TERMS": "terms",
    "parse_terms": "terms",
    "TRANSMISSION_KINDS": "transmission",
    "Transmission": "transmission",
}


def lazy_names(package: str, homes: Mapping[str, str]) -> Callable[[str], Any]:
    """The module ``__getattr__`` of ``package`` that loads each name of ``homes`` (``{name: module}``,
    the module relative to the package) from its module on first use; any other name is an
    ``AttributeError``. Every package of axisflow that lists its names this way uses it (here, so that
    it costs no module of the model: tests/test_package_names.py)."""

    def load(name: str) -> Any:
        module = homes.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        return getattr(importlib.import_module(f".{module}", package), name)

    return load


__getattr__ = lazy_names(__name__, _HOMES)


__all__ = sorted(_HOMES)
