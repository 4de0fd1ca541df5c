"""The axis's position encoder: the smallest distance the drive resolves.

The paper measures the cart's position only through the driven pulley's angle. Its encoder (and the
simulated plant's, acquisition/drives/plant_ideal.toml) has 2^17 counts per pulley revolution, so
one count is 2π·r/131072 of cart travel: 1.917 µm at the default r = 0.04 m. On the other
transmission kinds the encoder turns with the driven element (screw, pinion; a linear motor's scale
counts over :data:`~axisflow.model.transmission.LINEAR_SCALE_PERIOD_M`): one count is that element's
travel per turn over the counts. A move shorter than one
count cannot be observed by the drive, nor commanded to it in any meaningful way: the planner plans it
as a zero move (docs/planner.md, "Zero moves").
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .drive_units import metres_per_count

if TYPE_CHECKING:
    from .params import AxisParams

ENCODER_COUNTS_PER_REV = 131072
"""counts per pulley revolution of the axis's encoder (17 bit)"""


def encoder_resolution_m(r_m: float, counts_per_rev: int = ENCODER_COUNTS_PER_REV) -> float:
    """Cart travel of one encoder count [m]: 2π·r/counts_per_rev (r: pulley pitch radius [m])."""
    return metres_per_count(counts_per_rev, 1.0, r_m)  # the encoder turns with the pulley


def axis_resolution_m(params: AxisParams, counts_per_rev: int = ENCODER_COUNTS_PER_REV) -> float:
    """Cart travel of one count of an encoder on the axis's driven element [m]: its travel per turn
    (:attr:`~axisflow.model.transmission.Transmission.output_travel_m`) over ``counts_per_rev``."""
    return params.transmission.output_travel_m / counts_per_rev
