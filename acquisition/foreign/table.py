"""A foreign log's contents as named numeric columns (and, for MATLAB files, scalars), whatever format
it came in; :func:`read_table` reads one by its suffix.

The columns of a file are its numeric vectors: a CSV file's columns (named by its header row, or
``1`` … ``n`` without one), a Parquet file's numeric and time-stamp columns, a MATLAB file's numeric
vectors (n×1 or 1×n; the fields of a struct as ``struct.field``). A column is found by its name, its
name without a bracketed unit (``Position [mm]`` by ``Position``), case aside when that is unambiguous,
or by its number (1 is the first). A MATLAB scalar (1×1) is a :meth:`ForeignTable.scalar`, e.g. a gain
that scales a column. What a file says about a column's unit (a CSV units row, ``name [unit]``) is
kept in :attr:`ForeignTable.units`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .errors import ForeignLogError

FORMATS = ("csv", "parquet", "mat")
SUFFIXES: dict[str, str] = {
    ".csv": "csv",
    ".tsv": "csv",
    ".parquet": "parquet",
    ".pq": "parquet",
    ".mat": "mat",
}
"""the file suffixes read as foreign logs, and their formats"""
_BRACKETED_UNIT = re.compile(r"^(?P<name>.*?)\s*(?:\[(?P<unit>[^\]]*)\]|\((?P<unit2>[^)]*)\))\s*$")


def split_unit(header: str) -> tuple[str, str | None]:
    """``Position [mm]`` → (``Position``, ``mm``); a name without a bracketed unit → (name, None)."""
    m = _BRACKETED_UNIT.match(header)
    if m is None or not m["name"]:
        return header, None
    return m["name"], (m["unit"] if m["unit"] is not None else m["unit2"]).strip() or None


def format_of(path: str | Path, given: str | None = None) -> str | None:
    """The format of ``path``: ``given``, else by its suffix (None: not a foreign log's suffix)."""
    if given is not None:
        if given not in FORMATS:
            raise ForeignLogError(f"format {given!r} is not one of {', '.join(FORMATS)}")
        return given
    return SUFFIXES.get(Path(path).suffix.lower())


@dataclass(frozen=True, eq=False)
class ForeignTable:
    """The numeric contents of one foreign log."""

    path: Path
    format: str
    columns: dict[str, np.ndarray]
    """name → 1-D array (int64 where every value of a CSV or Parquet column is an integer, else
    float64), in file order"""
    scalars: dict[str, float] = field(default_factory=dict)
    units: dict[str, str] = field(default_factory=dict)
    """name → the unit the file gives for that column"""
    others: dict[str, str] = field(default_factory=dict)
    """name → what it is, for variables that are neither vectors nor scalars (a 3×4 matrix, text)"""
    lines: np.ndarray | None = None
    """the file line (1-based) of each row of a text file; None: rows are numbered from 1"""

    def row_name(self, index: int) -> str:
        """The row at ``index`` (0-based) as a user finds it: ``line 57`` in a text file, else
        ``row 12`` (counted from 1)."""
        if self.lines is not None:
            return f"line {int(self.lines[index])}"
        return f"row {index + 1}"

    def _listing(self) -> str:
        names = ", ".join(self.columns) or "none"
        if self.format != "mat":
            return f"its columns: {names}"
        scalars = ", ".join(self.scalars) or "none"
        return f"its vectors: {names}; its scalars: {scalars}"

    def _find(self, name: str, names: list[str]) -> str | None:
        if name in names:
            return name
        bare = {n: split_unit(n)[0] for n in names}
        for matches in (
            [n for n in names if bare[n] == name],
            [n for n in names if n.lower() == name.lower()],
            [n for n in names if bare[n].lower() == name.lower()],
        ):
            if len(matches) == 1:
                return matches[0]
            if len(matches) > 1:
                raise ForeignLogError(
                    f"{self.path}: {name!r} could name the columns {', '.join(matches)}: give the whole name"
                )
        return None

    def column(self, name: str, what: str) -> tuple[str, np.ndarray]:
        """(its full name, the column) of ``name`` (see the module docstring); ``what`` (time,
        position, …) names it in the error for a name the file does not have."""
        names = list(self.columns)
        found = self._find(name, names)
        if found is None and name.isdigit() and 1 <= int(name) <= len(names):
            found = names[int(name) - 1]
        if found is not None:
            return found, self.columns[found]
        if name in self.scalars:
            raise ForeignLogError(f"{self.path}: {what} {name!r} is a scalar, not a vector of samples")
        if name in self.others:
            raise ForeignLogError(f"{self.path}: {what} {name!r} is {self.others[name]}, not a vector")
        raise ForeignLogError(f"{self.path} has no {what} column {name!r}; {self._listing()}")

    def scalar(self, name: str, what: str) -> float:
        """The scalar variable ``name`` (a MATLAB 1×1); a vector or a missing name is an error."""
        if name in self.scalars:
            return self.scalars[name]
        if name in self.columns:
            n = len(self.columns[name])
            raise ForeignLogError(f"{self.path}: {what} {name!r} is a vector of {n} values, not a scalar")
        if name in self.others:
            raise ForeignLogError(f"{self.path}: {what} {name!r} is {self.others[name]}, not a scalar")
        raise ForeignLogError(f"{self.path} has no {what} variable {name!r}; {self._listing()}")


def read_table(
    path: str | Path, file_format: str | None = None, csv: CsvOptions | None = None
) -> ForeignTable:
    """The numeric contents of the foreign log at ``path`` (format by its suffix unless given)."""
    from ...model.files import InputError, check_input_file

    try:
        p = check_input_file(path, "log")
    except InputError as exc:
        raise ForeignLogError(str(exc)) from None
    kind = format_of(p, file_format)
    if kind is None:
        raise ForeignLogError(
            f"{p}: its suffix {p.suffix or '(none)'} is not one of a foreign log "
            f"({', '.join(SUFFIXES)}): give its format"
        )
    if p.stat().st_size == 0:
        raise ForeignLogError(f"{p} is empty (0 bytes)")
    if kind == "csv":
        from .csv_table import read_csv

        return read_csv(p, csv or CsvOptions())
    if kind == "parquet":
        from .parquet_table import read_parquet

        return read_parquet(p)
    from .mat_table import read_mat

    return read_mat(p)


@dataclass(frozen=True)
class CsvOptions:
    """How to split a CSV file: its delimiter and decimal mark (None: found from its data lines)."""

    delimiter: str | None = None
    """one character, or ``" "`` for any run of spaces and tabs"""
    decimal: str | None = None
    """``.`` or ``,``"""

    def __post_init__(self) -> None:
        if self.delimiter is not None and len(self.delimiter) != 1:
            raise ForeignLogError(f"delimiter {self.delimiter!r} must be one character (or 'tab', 'space')")
        if self.decimal not in (None, ".", ","):
            raise ForeignLogError(f"decimal mark {self.decimal!r} must be '.' or ','")
        if self.decimal == "," and self.delimiter == ",":
            raise ForeignLogError("decimal mark ',' and delimiter ',' cannot both be a comma")
