"""The shared model of the axis: parameters, eq. (1) dynamics, motion laws, energy, limits.

This is the bottom layer of axisflow: it depends on numpy/scipy only, and everything else
(acquisition, identification, planner, viz, the command line) imports it, never the reverse.
"""

from .dynamics import (
    cart_force,
    cart_force_from_torque,
    friction_force,
    mechanical_power,
    motor_angle,
    motor_speed,
    motor_torque,
)
from .energy import count_power, move_energy, trace_energy
from .errors import AxisflowError, MoveError, ParameterError
from .limits import EXECUTION_RATE_HZ, LimitReport, check_limits, execution_times
from .motion_laws import (
    MAX_MOVE_DURATION_S,
    POLYNOMIAL_LAWS,
    Move,
    MoveSamples,
    PolynomialLaw,
    polynomial_law,
)
from .params import AxisParams, EnergyAccounting, default_params, load_params, params_to_toml

__all__ = [
    "EXECUTION_RATE_HZ",
    "MAX_MOVE_DURATION_S",
    "POLYNOMIAL_LAWS",
    "AxisParams",
    "AxisflowError",
    "EnergyAccounting",
    "LimitReport",
    "Move",
    "MoveError",
    "MoveSamples",
    "ParameterError",
    "PolynomialLaw",
    "cart_force",
    "cart_force_from_torque",
    "check_limits",
    "count_power",
    "default_params",
    "execution_times",
    "friction_force",
    "load_params",
    "mechanical_power",
    "motor_angle",
    "motor_speed",
    "motor_torque",
    "move_energy",
    "params_to_toml",
    "polynomial_law",
    "trace_energy",
]
