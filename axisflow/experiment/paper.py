"""Published figures of the source paper (Fabris et al., Table 2), for side-by-side comparison, and the
shape of its experiment: the laws of Table 2 and its way point counts."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class PaperRow:
    case: str
    law: str
    total_time_s: float
    energy_model_j: float
    energy_measured_j: float
    energy_error_pct: float
    t_opt_ms_mean: float
    t_opt_ms_std: float


PAPER_TABLE2: dict[tuple[str, str], PaperRow] = {
    (r.case, r.law): r
    for r in (
        PaperRow("min-time", "poly3", 47.80, 15475, 14001, 9.52, 3.97, 0.39),
        PaperRow("min-time", "poly5", 50.53, 14858, 13804, 7.09, 4.93, 0.57),
        PaperRow("min-time", "poly7", 58.21, 13961, 13237, 5.19, 7.46, 1.05),
        PaperRow("min-time-energy", "poly3", 335.73, 7515, 8390, -11.64, 3.79, 0.43),
        PaperRow("min-time-energy", "poly5", 322.64, 7625, 8719, -14.35, 5.53, 0.98),
        PaperRow("min-time-energy", "poly7", 319.62, 7658, 8527, -11.35, 7.47, 1.05),
    )
}
LAWS: tuple[str, ...] = ("poly3", "poly5", "poly7")
"""the polynomial laws of Table 2 (each planned in both cases)"""
PAPER_WAYPOINTS = 100
FIG5_WAYPOINTS = 25
"""the paper's Fig. 5 shows runs through 25 random way points"""
