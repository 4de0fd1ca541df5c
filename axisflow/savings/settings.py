"""What ``axisflow savings`` is to do (:class:`SavingsSettings`) and its defaults: the command line
offers them before it loads the comparison itself (:mod:`axisflow.savings.study`)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ..acquisition.drives.plant_profiles import DEFAULT_PROFILE
from ..model import AxisflowError

DEFAULT_HOURS_PER_DAY = 16.0
"""when no ``--cycles-per-day`` is given: the baseline's cycle back to back for two shifts"""
DEFAULT_DAYS_PER_YEAR = 250.0
"""working days a year (five days a week, fifty weeks)"""
DEFAULT_PRICE_PER_KWH = 0.20
"""the price of a kWh when none is given (in whatever currency the price is read in)"""
DEFAULT_LAW = "poly3"
"""axisflow's law of the comparison: of the paper's three, the one that spends least at a given
duration (its ∫s'² is the smallest: 1.2 against 1.43 and 1.66)"""


@dataclass(frozen=True)
class SavingsSettings:
    out: Path
    recording: Path | None = None
    waypoints_file: Path | None = None
    random_waypoints: int | None = None
    seed: int = 0
    params_path: str | None = None
    baseline: str = "trapezoid"
    limits: str | None = None
    """``V,A[,J]`` as given (None: the parameter file's [baseline] table, else the axis's own)"""
    law: str = DEFAULT_LAW
    cycles_per_day: float | None = None
    """None: the baseline's cycle back to back for :data:`DEFAULT_HOURS_PER_DAY` hours"""
    days_per_year: float = DEFAULT_DAYS_PER_YEAR
    price_per_kwh: float = DEFAULT_PRICE_PER_KWH
    measure: bool = True
    """run the comparison through a simulated bridge and measure it (else the model only)"""
    plant_profile: str = DEFAULT_PROFILE
    overwrite: bool = False
    """replace the recording of an earlier comparison in ``out``"""

    def __post_init__(self) -> None:
        given = [s for s in (self.recording, self.waypoints_file, self.random_waypoints) if s is not None]
        if len(given) != 1:
            raise AxisflowError("give the moves one way: LOG.mcap, --waypoints FILE or --random N")
        for name, value, unit in (
            ("cycles_per_day", self.cycles_per_day, ""),
            ("days_per_year", self.days_per_year, ""),
            ("price_per_kwh", self.price_per_kwh, " per kWh"),
        ):
            if value is not None and not value >= 0.0:
                raise AxisflowError(f"--{name.replace('_', '-')} = {value}{unit} must be >= 0")
        if self.days_per_year > 366.0:
            raise AxisflowError(f"--days-per-year = {self.days_per_year} is more than a year has (366)")

    @property
    def source(self) -> str:
        if self.recording is not None:
            return f"the moves the axis completed in {self.recording}"
        if self.waypoints_file is not None:
            return f"the way points of {self.waypoints_file}"
        n = self.random_waypoints
        return f"{n} random way points (seed {self.seed}, as `axisflow experiment` draws them)"
