"""The fits table, ``DIR/fits.parquet``: one row per axis and window (:class:`FitRow`).

A row is a fit (status ``ok``: every parameter with its σ, the Coulomb friction at
:data:`~.window_fit.COULOMB_SPEED_M_S` with its σ, the energy per metre travelled, the fit's and the
held-out error), or says why there is none: ``too_little_motion`` (the catalog shows the window cannot
excite friction) or ``failed`` (the identification refused or failed; ``reason`` has its one line).
Rows are keyed by the window's key (:func:`~.windows.window_key`): a re-run replaces nothing it
already has. Like the catalog, the file is plain Parquet marked with :data:`FITS_FORMAT`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

from ..model.files import atomic_path
from .catalog import FORMAT_KEY, read_parquet_table
from .errors import FleetError

FITS_FILE = "fits.parquet"
FITS_FORMAT = "axisflow.fleet.fits/2"
OLDER_FITS_FORMATS = ("axisflow.fleet.fits/1",)
"""tables of an older method (each window fitted alone, the terms chosen per window): a re-run fits
every window again"""
OK, TOO_LITTLE_MOTION, FAILED = "ok", "too_little_motion", "failed"
STATUSES = (OK, TOO_LITTLE_MOTION, FAILED)
DEFAULT_HOLDOUT = 0.2
"""the last fraction of each log a window's fit leaves out, for ``heldout_rms``"""
FITTED = ("M_eq", "a1", "a2", "a3", "a4")
"""eq. (1)'s parameters, each a column with its ``_std`` beside it"""


@dataclass(frozen=True)
class FitRow:
    """One axis and window (see the module docstring). SI units; times integer ns since the Unix
    epoch; NaN where a value does not exist (a window without a fit, a parameter not fitted)."""

    key: str
    axis: str
    window_start_ns: int
    window_end_ns: int
    logs: int
    samples: int
    """samples the window's logs hold in it"""
    samples_used: int
    """samples the fit used (decimated to the fit's rate)"""
    M_eq: float
    M_eq_std: float
    a1: float
    a1_std: float
    a2: float
    a2_std: float
    a3: float
    a3_std: float
    a4: float
    a4_std: float
    coulomb_n: float
    """friction force at the reference speed [N] (the model's law with the fitted a1…a4)"""
    coulomb_std_n: float
    """its σ from the window's samples: the spread of this window's value around the axis's"""
    coulomb_sys_std_n: float
    """the axis's systematic σ of it, common to all its windows (from its calibration's offset:
    :mod:`.axis_calibration`; NaN: not known); against the truth, σ² = coulomb_std_n² + this²"""
    energy_per_m_j: float
    """mechanical energy the drive put in per metre travelled [J/m] (the parameters' energy accounting)"""
    fit_rms: float
    """filtered effort error on the fitted samples (the joint's unit: N·m or N)"""
    heldout_rms: float
    """the same on the held-out samples"""
    effort_unit: str
    stretch_low_m: float
    stretch_high_m: float
    """the stretch of the stroke the fitted samples cover (a1 is its average there)"""
    torque_delay_s: float
    """the torque/position offset the fit used [s] (the axis's calibration's, or the window's own)"""
    torque_delay_std_s: float
    status: str
    reason: str
    wall_s: float
    """the window's identification time on its worker [s]"""
    worker: str

    @property
    def ok(self) -> bool:
        return self.status == OK

    @property
    def coulomb_truth_std_n(self) -> float:
        """σ of ``coulomb_n`` against the truth: the window's and the axis's systematic σ together
        (the window's alone where the systematic one is not known)."""
        sys = self.coulomb_sys_std_n if math.isfinite(self.coulomb_sys_std_n) else 0.0
        return math.hypot(self.coulomb_std_n, sys)

    def value(self, parameter: str) -> tuple[float, float]:
        """(value, σ) of a trended parameter: one of :data:`FITTED`, ``coulomb_n``, ``energy_per_m_j``."""
        if parameter == "coulomb_n":
            return self.coulomb_n, self.coulomb_std_n
        if parameter == "energy_per_m_j":
            return self.energy_per_m_j, float("nan")
        return getattr(self, parameter), getattr(self, f"{parameter}_std")


_TYPES = {"int": "int64", "float": "float64", "str": "string"}


def _schema() -> Any:
    import pyarrow as pa

    types = {"int64": pa.int64(), "float64": pa.float64(), "string": pa.string()}
    cols = [pa.field(f.name, types[_TYPES[str(f.type)]], nullable=False) for f in fields(FitRow)]
    return pa.schema(cols, metadata={FORMAT_KEY: FITS_FORMAT.encode()})


def write_fits(folder: Path, rows: Sequence[FitRow]) -> Path:
    """``folder/fits.parquet`` (replaced atomically), sorted by axis and window start."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    ordered = sorted(rows, key=lambda r: (r.axis, r.window_start_ns, r.key))
    table = pa.table(
        {f.name: [getattr(r, f.name) for r in ordered] for f in fields(FitRow)}, schema=_schema()
    )
    path = folder / FITS_FILE
    with atomic_path(path) as part:
        pq.write_table(table, part)
    return path


def read_fits(folder: str | Path, missing_ok: bool = False) -> list[FitRow]:
    """The rows of ``folder/fits.parquet`` ([] when it does not exist and ``missing_ok``)."""
    path = Path(folder) / FITS_FILE
    if not path.exists() or (missing_ok and _format_of(path) in OLDER_FITS_FORMATS):
        if missing_ok:
            return []
        raise FleetError(
            f"{folder} has no {FITS_FILE}: run `axisflow fleet identify --catalog {folder}` first"
        )
    table = read_parquet_table(path, FITS_FORMAT, "fleet fits table")
    names = [f.name for f in fields(FitRow)]
    missing = [n for n in names if n not in table.column_names]
    if missing:
        raise FleetError(f"{path} lacks the column(s) {', '.join(missing)}")
    data = table.select(names).to_pydict()
    return [FitRow(**{n: data[n][i] for n in names}) for i in range(table.num_rows)]


def _format_of(path: Path) -> str:
    """The format mark of a Parquet file ("" if it has none or cannot be read)."""
    import pyarrow.parquet as pq

    try:
        metadata = pq.read_schema(path).metadata or {}
    except Exception:
        return ""
    return metadata.get(FORMAT_KEY, b"").decode(errors="replace")
