"""What each move of the savings runs cost on the axis, read back from the recording.

The recording holds each move's plan record (labelled with its run), the bridge's move statuses (the
ticks it ran) and the 1 kHz state samples (motor speed ω_m and torque τ_m). Per move between way
points, as Table 2 measures it (:func:`axisflow.table2.recorded_runs`, the same code):

* E_exp = ∫ g(τ_m·ω_m) dt over the move's ticks, g the plans' energy accounting;

and from the same samples:

* the peak |τ_m| and the peak τ_m·ω_m (the mechanical power drawn from the drive);
* ∫τ_m² dt (trapezoidal rule over the ticks), the trend of the motor's copper losses.

A move that did not complete, or lost a stretch of samples in the recording, has no measurement
(None), as in Table 2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..acquisition import AxisKeys, read_joint_states, topic_for_key
from ..experiment.table2 import recorded_runs
from ..model import EXECUTION_PERIOD_NS, AxisflowError


@dataclass(frozen=True)
class MeasuredMove:
    """One move as the axis ran it."""

    index: int
    energy_j: float | None
    peak_torque_nm: float | None
    peak_power_w: float | None
    torque_sq_integral: float | None
    """∫τ_m² dt [N²·m²·s]"""
    samples_missing: int


def measure(path: str | Path, label: str, keys: AxisKeys | None = None) -> dict[int, MeasuredMove]:
    """The measured moves of run ``label`` in the recording ``path``, by way point index (from 1)."""
    keys = keys or AxisKeys()
    runs, _accounting = recorded_runs(path, keys, label)
    motor = read_joint_states(path, topic_for_key(keys.state)).joint("motor")
    order = np.argsort(motor.stamp_ns, kind="stable")
    stamps, speed, torque = motor.stamp_ns[order], motor.velocity[order], motor.effort[order]
    half = EXECUTION_PERIOD_NS // 2
    out: dict[int, MeasuredMove] = {}
    for run in runs:
        for move in run.moves:
            k = move.plan.waypoint_index
            if k in out:
                raise AxisflowError(f"{path}: run {label!r} holds way point {k} twice")
            acc = move.accepted
            if move.completed is None or acc is None or not math.isfinite(move.energy_measured_j):
                out[k] = MeasuredMove(k, None, None, None, None, move.samples_missing)
                continue
            lo = np.searchsorted(stamps, acc.stamp_of(acc.start_tick) - half, "left")
            hi = np.searchsorted(stamps, acc.stamp_of(acc.end_tick) + half, "left")
            t = (stamps[lo:hi] - stamps[lo]) * 1e-9
            tau, w = torque[lo:hi], speed[lo:hi]
            sq = float(np.dot(np.diff(t), 0.5 * (tau[1:] ** 2 + tau[:-1] ** 2)))
            out[k] = MeasuredMove(
                k,
                move.energy_measured_j,
                float(np.max(np.abs(tau))),
                float(np.max(tau * w)),
                sq,
                move.samples_missing,
            )
    return out
