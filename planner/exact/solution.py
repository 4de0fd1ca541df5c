"""What the exact solver returns for one move: the duration, what decided it, and its proof."""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

from ..certificates import Certificate


class Active(StrEnum):
    """What decides the duration of an exact solution."""

    T_MIN = "t_min"
    """the lower duration bound"""
    VELOCITY = "velocity"
    """the velocity limit: the peak velocity c_v·D/T meets v_max"""
    TORQUE = "torque"
    """the torque limit: the peak motor torque meets tau_max"""
    T_MAX = "t_max"
    """the upper duration bound"""
    OPTIMUM = "optimum"
    """an interior minimum of the time-energy objective"""
    ZERO_LENGTH = "zero-length"
    """a zero move, shorter than one encoder count: duration 0, nothing to execute or prove"""


@dataclass(frozen=True)
class ExactSolution:
    """The bare answer of the exact solver (no 1 kHz scoring): duration, objective and proof."""

    duration_s: float
    objective: float
    energy_j: float
    """the move's energy [J] (case 2); NaN for minimum time, where the solve does not need it"""
    active: Active
    certificate: Certificate | None
    """the proof of optimality; None for a zero move"""
