"""The error of reading a foreign log: one line naming the file, the column or row, the value and the
limit."""

from __future__ import annotations

from ..errors import AcquisitionError


class ForeignLogError(AcquisitionError, ValueError):
    """A foreign log (CSV, Parquet, MATLAB) cannot be read or imported as asked: a missing column, an
    unknown unit, time that goes backwards, a run of missing values, an empty file."""
