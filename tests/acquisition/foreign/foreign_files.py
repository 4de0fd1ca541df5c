"""Foreign log files for the tests, written as other tools write them: a scope's CSV, Parquet by
pyarrow, MATLAB v5 by scipy and v7.3 (HDF5 with MATLAB's 512-byte header) by h5py."""

from __future__ import annotations

from pathlib import Path

import numpy as np


def write_csv(
    path: Path,
    header: list[str] | None,
    columns: list[np.ndarray],
    *,
    delimiter: str = ";",
    decimal: str = ",",
    units: list[str] | None = None,
    preamble: tuple[str, ...] = (),
) -> Path:
    """A CSV file: ``preamble`` lines, the header row, the units row, then one line per sample (each
    number written with ``repr``, its decimal point replaced by ``decimal``)."""
    lines = list(preamble)
    for row in (header, units):
        if row is not None:
            lines.append(delimiter.join(row))
    for values in zip(*(c.tolist() for c in columns), strict=True):
        fields = ("" if isinstance(v, float) and np.isnan(v) else repr(v) for v in values)
        lines.append(delimiter.join(f.replace(".", decimal) for f in fields))
    path.write_text("\n".join(lines) + "\n")
    return path


def write_parquet(path: Path, columns: dict[str, np.ndarray]) -> Path:
    import pyarrow as pa
    import pyarrow.parquet as pq

    pq.write_table(pa.table(columns), path)
    return path


def write_mat_v5(path: Path, variables: dict[str, object]) -> Path:
    from scipy.io import savemat

    savemat(path, variables)  # vectors become 1×n, as MATLAB saves a row vector
    return path


MAT73_HEADER = b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created by: axisflow tests HDF5 schema 1.00 ."


def write_mat_v73(path: Path, variables: dict[str, np.ndarray | float]) -> Path:
    """A MATLAB -v7.3 file: HDF5 behind a 512-byte user block whose first 128 bytes are MATLAB's
    header (text, then version 0x0200 and the endian mark 'IM' at bytes 124–127); each variable a
    dataset with its MATLAB_class, its dimensions reversed as MATLAB writes them (an n×1 column
    vector is stored 1×n)."""
    import h5py

    with h5py.File(path, "w", userblock_size=512) as f:
        for name, value in variables.items():
            array = np.atleast_2d(np.asarray(value, dtype=np.float64))
            if array.shape[0] == 1 and array.size > 1:
                array = array.T  # an n×1 column in MATLAB
            dataset = f.create_dataset(name, data=array.T)
            dataset.attrs["MATLAB_class"] = np.bytes_(b"double")
    header = MAT73_HEADER.ljust(116, b" ") + b"\x00" * 8 + b"\x00\x02" + b"IM"
    with open(path, "r+b") as fh:
        fh.write(header)
    return path
