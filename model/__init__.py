"""The shared model of the axis: parameters, eq. (1) dynamics, friction, motion laws, energy, limits,
and the drive's 1 kHz sampling rule.

This is the bottom layer of axisflow: it depends on numpy/scipy only, and everything else
(acquisition, identification, planner, viz, the command line) imports it, never the reverse.
"""

from .braking import StopProfile, braking_acceleration, stop_profile
from .dynamics import (
    cart_force,
    cart_force_from_torque,
    mechanical_power,
    motor_angle,
    motor_speed,
    motor_torque,
)
from .energy import count_power, move_energy, trace_energy, trace_energy_at
from .errors import AxisflowError, AxisflowWarning, MoveError, ParameterError
from .friction import (
    FRICTION_PARAMETERS,
    forward_friction,
    friction_curvature,
    friction_expression,
    friction_force,
    friction_regressors,
    friction_slope,
)
from .limits import LimitReport, check_limits, execution_times
from .motion_laws import (
    MAX_MOVE_DURATION_S,
    POLYNOMIAL_LAWS,
    Motion,
    Move,
    MoveSamples,
    PolynomialLaw,
    polynomial_law,
)
from .params import AxisParams, EnergyAccounting, default_params, load_params, params_to_toml
from .sampling import (
    EXECUTION_PERIOD_NS,
    EXECUTION_PERIOD_S,
    EXECUTION_RATE_HZ,
    move_ticks,
    sample_count,
    ticks_to_seconds,
)
from .trajectory import SampledTrajectory

__all__ = [
    "EXECUTION_PERIOD_NS",
    "EXECUTION_PERIOD_S",
    "EXECUTION_RATE_HZ",
    "FRICTION_PARAMETERS",
    "MAX_MOVE_DURATION_S",
    "POLYNOMIAL_LAWS",
    "AxisParams",
    "AxisflowError",
    "AxisflowWarning",
    "EnergyAccounting",
    "LimitReport",
    "Motion",
    "Move",
    "MoveError",
    "MoveSamples",
    "ParameterError",
    "PolynomialLaw",
    "SampledTrajectory",
    "StopProfile",
    "braking_acceleration",
    "cart_force",
    "cart_force_from_torque",
    "check_limits",
    "count_power",
    "default_params",
    "execution_times",
    "forward_friction",
    "friction_curvature",
    "friction_expression",
    "friction_force",
    "friction_regressors",
    "friction_slope",
    "load_params",
    "mechanical_power",
    "motor_angle",
    "motor_speed",
    "motor_torque",
    "move_energy",
    "move_ticks",
    "params_to_toml",
    "polynomial_law",
    "sample_count",
    "stop_profile",
    "ticks_to_seconds",
    "trace_energy",
    "trace_energy_at",
]
