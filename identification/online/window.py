"""A window of live motor samples as the refit's signals: what :func:`~..signals.load_joint` makes of a
log, made of arrays.

The samples (stamp [ns], motor angle [rad], motor torque [N·m]) are placed on the drive's sampling grid
(:func:`~..sample_grid.place_on_grid`: period and phase fitted, holes counted and filled so that the
filters run, never fitted) and converted to the cart with r and i_r of the parameters (x = θ·r/i_r,
F = τ·i_r/r). The window carries no velocity: the fit differentiates the filtered position, as for
any log.
"""

from __future__ import annotations

import numpy as np

from ...model import AxisParams
from ..errors import IdentificationError
from ..sample_grid import place_on_grid
from ..signals import JointKind, JointSignals

MIN_WINDOW_SAMPLES = 1000
"""fewer samples than this (1 s at 1 kHz) are not a window"""


def window_signals(
    stamp_ns: np.ndarray, angle_rad: np.ndarray, torque_nm: np.ndarray, params: AxisParams, source: str
) -> JointSignals:
    """The motor joint's samples of a window as :class:`~..signals.JointSignals` in the cart's units
    (``source`` names the stream in messages, e.g. ``live axisflow/a0/state``). An
    :class:`IdentificationError` for too few samples, non-finite values, or stamps off any grid."""
    if stamp_ns.size < MIN_WINDOW_SAMPLES:
        raise IdentificationError(
            f"{source}: {stamp_ns.size} samples are too few for a window (at least {MIN_WINDOW_SAMPLES})"
        )
    finite = np.isfinite(angle_rad) & np.isfinite(torque_nm)
    if not finite.all():
        raise IdentificationError(
            f"{source}: {np.count_nonzero(~finite)} of {finite.size} samples have a non-finite angle or "
            "torque"
        )
    grid = place_on_grid(stamp_ns, source)
    scale = params.transmission.metres_per_radian
    return JointSignals(
        source=source,
        topic=source,
        joint="motor",
        kind=JointKind.MOTOR,
        start_ns=int(stamp_ns[0]),
        t_s=grid.times_s(),
        position_m=grid.spread(angle_rad) * scale,
        velocity_m_s=np.full(grid.size, np.nan),
        force_n=grid.spread(torque_nm) / scale,
        effort_per_force=scale,
        finite=np.ones(grid.size, dtype=bool),
        truncated=False,
        stamp_jitter_s=grid.jitter_s,
        grid=grid,
        velocity_logged=False,
    )
