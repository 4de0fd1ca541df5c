"""A Parquet file read into a :class:`~.table.ForeignTable` (pyarrow, loaded when a file is read).

Numeric columns become int64 or float64 arrays (a null is NaN; an integer column with nulls becomes
float64); a time-stamp or duration column becomes int64 nanoseconds with the unit ``ns``. Other
columns (text, lists, structs) are listed as what they are and cannot be mapped.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .errors import ForeignLogError
from .table import ForeignTable


def read_parquet(path: Path) -> ForeignTable:
    import pyarrow as pa
    import pyarrow.parquet as pq

    try:
        table = pq.read_table(path)
    except (pa.ArrowException, OSError) as exc:
        reason = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise ForeignLogError(f"{path} is not a Parquet file pyarrow can read: {reason}") from None
    if table.num_rows == 0:
        raise ForeignLogError(f"{path} holds no rows (its columns: {', '.join(table.column_names)})")
    columns: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}
    others: dict[str, str] = {}
    for name, column in zip(table.column_names, table.columns, strict=True):
        kind = column.type
        if pa.types.is_timestamp(kind) or pa.types.is_duration(kind):
            target = pa.timestamp("ns") if pa.types.is_timestamp(kind) else pa.duration("ns")
            values = column.cast(target).cast(pa.int64())
            if values.null_count:
                others[name] = f"a time column with {values.null_count} empty values"
                continue
            columns[name] = values.to_numpy()
            units[name] = "ns"
        elif pa.types.is_integer(kind) and column.null_count == 0:
            columns[name] = column.to_numpy().astype(np.int64)
        elif pa.types.is_integer(kind) or pa.types.is_floating(kind) or pa.types.is_decimal(kind):
            columns[name] = column.cast(pa.float64()).to_numpy(zero_copy_only=False)  # nulls → NaN
        else:
            others[name] = f"a column of {kind}"
    return ForeignTable(path=path, format="parquet", columns=columns, units=units, others=others)
