"""A MATLAB .mat file read into a :class:`~.table.ForeignTable`: version 5 (MATLAB's ``-v6``/``-v7``,
the default) through ``scipy.io.loadmat``, version 7.3 (``-v7.3``, an HDF5 file) through h5py (loaded
only for such a file).

Numeric variables (and the fields of structs, named ``struct.field``, at any depth) sort into vectors
(n×1 or 1×n, n ≥ 2: the columns), scalars (1×1: e.g. a gain) and the rest (matrices, text, cell
arrays, empty arrays), which are listed as what they are and cannot be mapped. Logical values count
as numbers.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .errors import ForeignLogError
from .table import ForeignTable

_SKIPPED_GROUPS = ("#refs#", "#subsystem#")
"""MATLAB's own groups in a v7.3 file (references of cell arrays, objects)"""


class _Variables:
    """Sorts a file's variables into vectors, scalars and the rest."""

    def __init__(self) -> None:
        self.columns: dict[str, np.ndarray] = {}
        self.scalars: dict[str, float] = {}
        self.others: dict[str, str] = {}

    def add(self, name: str, value: np.ndarray, matlab_class: str | None = None) -> None:
        shape = value.shape
        numeric = value.dtype.kind in "biuf" and matlab_class not in ("char", "cell")
        if not numeric:
            what = matlab_class or value.dtype.name
            self.others[name] = f"a {'×'.join(map(str, shape)) or 'scalar'} {what} array"
            return
        if value.size == 0:
            self.others[name] = "an empty array"
        elif value.size == 1:
            self.scalars[name] = float(value.reshape(-1)[0])
        elif sum(d > 1 for d in shape) == 1:
            values = value.reshape(-1)
            self.columns[name] = values.astype(np.float64) if values.dtype.kind in "bf" else values
        else:
            self.others[name] = f"a {'×'.join(map(str, shape))} matrix"


def read_mat(path: Path) -> ForeignTable:
    from scipy.io.matlab import MatReadError, matfile_version

    try:
        with open(path, "rb") as fh:
            major, _minor = matfile_version(fh)
    except (MatReadError, ValueError, OSError) as exc:
        raise ForeignLogError(
            f"{path} is not a MATLAB file: {str(exc).strip() or type(exc).__name__}"
        ) from None
    found = _Variables()
    if major == 2:
        _read_hdf5(path, found)
    else:
        _read_v5(path, found)
    if not found.columns and not found.scalars and not found.others:
        raise ForeignLogError(f"{path} holds no variables")
    return ForeignTable(
        path=path, format="mat", columns=found.columns, scalars=found.scalars, others=found.others
    )


def _read_v5(path: Path, found: _Variables) -> None:
    from scipy.io import loadmat

    try:
        contents = loadmat(path, squeeze_me=False, struct_as_record=True)
    except Exception as exc:  # scipy raises many kinds for a damaged file
        raise ForeignLogError(f"{path} cannot be read as a MATLAB file: {exc}") from None
    for name, value in contents.items():
        if not name.startswith("__"):
            _add_v5(found, name, np.asarray(value))


def _add_v5(found: _Variables, name: str, value: np.ndarray) -> None:
    if value.dtype.names is not None:  # a struct: its fields (of a 1×1 struct) by dotted names
        if value.size != 1:
            found.others[name] = f"a {'×'.join(map(str, value.shape))} struct array"
            return
        record = value.reshape(-1)[0]
        for field in value.dtype.names:
            _add_v5(found, f"{name}.{field}", np.asarray(record[field]))
        return
    found.add(name, value, "cell" if value.dtype == object else None)


def _read_hdf5(path: Path, found: _Variables) -> None:
    import h5py

    try:
        handle = h5py.File(path, "r")
    except OSError as exc:
        raise ForeignLogError(f"{path} cannot be read as a MATLAB v7.3 (HDF5) file: {exc}") from None
    with handle:

        def visit(name: str, item: object) -> None:
            if name.split("/")[0] in _SKIPPED_GROUPS or not isinstance(item, h5py.Dataset):
                return
            matlab_class = item.attrs.get("MATLAB_class")
            if isinstance(matlab_class, bytes):
                matlab_class = matlab_class.decode()
            dotted = name.replace("/", ".")
            if item.attrs.get("MATLAB_empty"):
                found.others[dotted] = "an empty array"
                return
            value = item[()]
            if item.dtype.names is not None:  # complex numbers are stored as (real, imag) pairs
                found.others[dotted] = f"a complex {'×'.join(map(str, value.shape))} array"
                return
            # HDF5 holds MATLAB's column-major arrays with their dimensions reversed
            found.add(dotted, np.asarray(value).T, matlab_class)

        handle.visititems(visit)
