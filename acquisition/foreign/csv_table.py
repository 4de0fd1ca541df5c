"""A CSV file as a drive's scope exports it, read into a :class:`~.table.ForeignTable`.

What is understood, from the top of the file down:

* **comment lines** (their first non-blank characters are ``#``, ``//``, ``%`` or ``!``) and blank
  lines anywhere: skipped;
* **metadata lines** (``Sample rate;1 kHz``, ``Trigger: rising``): lines before the data whose number
  of fields differs from the data's, skipped;
* **header rows**: the rows just above the data with as many fields as the data. The last of them is
  the **units row** when it is not the only one and its fields are units (``s``, ``[mm]``, ``V``, or
  empty) and at least one of them is a unit :mod:`axisflow.model.units` knows; the row above it (or the
  last one, without a units row) holds the column names; rows further up are skipped. A name
  ``Position [mm]`` or ``Position (mm)`` gives the column's unit too. Without a header row the columns
  are named ``1`` … ``n``;
* **data**: every line from the first line of as many numbers as the last line has, to the end. An empty field
  and ``nan`` are missing values; a field that is not a number is an error naming its line and
  column.

The **delimiter** is found from the last data lines unless given: the first of tab, ``;``, ``,``, ``|``
and runs of spaces that splits them all into the same number (≥ 2) of numbers. The **decimal mark**
is ``,`` when a number of the data has a comma in it (only possible when the delimiter is not a
comma), else ``.``. A column whose every value is an integer (a time stamp in ns, a count) is read as
int64, exactly; the others as float64. Text is UTF-8 (a byte-order mark allowed), else Latin-1.
"""

from __future__ import annotations

import csv
import re
from pathlib import Path

import numpy as np

from ...model.units import SIGNAL_UNITS, UNIT_ALIASES
from .errors import ForeignLogError
from .table import CsvOptions, ForeignTable, split_unit

COMMENT_PREFIXES = ("#", "//", "%", "!")
DELIMITERS = ("\t", ";", ",", "|", " ")
"""tried in this order; ``" "`` stands for any run of spaces and tabs"""
SNIFF_LINES = 50
"""the last data lines the delimiter and decimal mark are found from"""
_NUMBER = re.compile(
    r"^[+-]?(\d+([.,]\d*)?|[.,]\d+)([eE][+-]?\d+)?$|^[+-]?(nan|inf|infinity)$", re.IGNORECASE
)
_KNOWN_UNITS = (
    {u for table in SIGNAL_UNITS.values() for u in table} | set(UNIT_ALIASES) | {"counts", "counts/s"}
)


def _is_number(text: str, decimal: str) -> bool:
    text = text.strip()
    if text == "":
        return True  # a missing value
    if not _NUMBER.match(text):
        return False
    return decimal == "," or "," not in text


def _split(line: str, delimiter: str) -> list[str]:
    if delimiter == " ":
        return line.split()
    return next(csv.reader([line], delimiter=delimiter))


def _content_lines(text: str) -> list[tuple[int, str]]:
    """(line number from 1, line) of the lines that are neither blank nor comments."""
    out = []
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if stripped and not stripped.startswith(COMMENT_PREFIXES):
            out.append((number, line))
    return out


def _numeric_tail(rows: list[list[str]], decimal: str) -> int:
    """How many of the last ``rows`` are numbers, as many as the last row has."""
    width, k = len(rows[-1]), len(rows)
    while k > 0 and len(rows[k - 1]) == width and all(_is_number(f, decimal) for f in rows[k - 1]):
        k -= 1
    return len(rows) - k


def _sniff(path: Path, lines: list[str], options: CsvOptions) -> tuple[str, str]:
    """(delimiter, decimal mark) that split the most of ``lines`` (the last lines of the file) into
    one number of numbers each (two or more, unless no delimiter does); ties go to the earlier
    delimiter of :data:`DELIMITERS`."""
    delimiters = (options.delimiter,) if options.delimiter is not None else DELIMITERS
    best: tuple[int, str, str] | None = None  # (rows, delimiter, decimal)
    for wide in (True, False):
        for delimiter in delimiters:
            decimals = (options.decimal,) if options.decimal else ((".",) if delimiter == "," else (",", "."))
            rows = [_split(line, delimiter) for line in lines]
            if wide and len(rows[-1]) < 2:
                continue
            for decimal in decimals:
                n = _numeric_tail(rows, decimal)
                if n and (best is None or n > best[0]):
                    uses_comma = decimal == "," and any("," in f for row in rows[-n:] for f in row)
                    best = (n, delimiter, "," if uses_comma or options.decimal == "," else ".")
        if best is not None:
            return best[1], best[2]
    if options.delimiter is not None:
        shown = {"\t": "tab", " ": "space"}.get(options.delimiter, repr(options.delimiter))
        raise ForeignLogError(
            f"{path}: its last line does not split at {shown} into numbers: check the delimiter (and "
            "the decimal mark)"
        )
    raise ForeignLogError(
        f"{path}: cannot tell its delimiter from its last lines (tried tab, ';', ',', '|', spaces): its "
        "last line is not a row of numbers"
    )


def _is_units_row(fields: list[str]) -> bool:
    """Whether a header row holds units: short fields (``s``, ``[mm]``, empty), one of them a known unit."""
    units = [f.strip().strip("[]()").strip() for f in fields]
    return all(len(u) <= 12 for u in units) and any(u in _KNOWN_UNITS for u in units)


def read_csv(path: Path, options: CsvOptions) -> ForeignTable:
    """The CSV file at ``path`` as a table (see the module docstring)."""
    raw = path.read_bytes()
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    lines = _content_lines(text)
    if not lines:
        raise ForeignLogError(f"{path} holds no data lines (only blank lines and comments)")
    delimiter, decimal = _sniff(path, [line for _, line in lines[-SNIFF_LINES:]], options)
    texts = [line for _, line in lines]
    rows = (
        [line.split() for line in texts] if delimiter == " " else list(csv.reader(texts, delimiter=delimiter))
    )
    width = len(rows[-1])
    first = next(  # the first data row: data run from there to the end of the file
        k for k, row in enumerate(rows) if len(row) == width and all(_is_number(f, decimal) for f in row)
    )
    numbers = [number for number, _ in lines[first:]]
    data = rows[first:]
    ragged = next((i for i, row in enumerate(data) if len(row) != width), None)
    if ragged is not None:
        raise ForeignLogError(
            f"{path} line {numbers[ragged]} has {len(data[ragged])} fields, the data lines {width}"
        )
    header: list[list[str]] = []
    k = first - 1
    while k >= 0 and len(rows[k]) == width:
        header.insert(0, rows[k])
        k -= 1
    units_row = header[-1] if len(header) >= 2 and _is_units_row(header[-1]) else None
    names_row = (header[-2] if units_row is not None else header[-1]) if header else None
    names, units = _names(path, names_row, units_row, width)
    columns = {}
    for j, name in enumerate(names):
        fields = [row[j] for row in data]
        try:
            columns[name] = _column(fields, decimal)
        except ValueError:
            i = next(i for i, f in enumerate(fields) if not _is_number(f, decimal))
            raise ForeignLogError(
                f"{path} line {numbers[i]}, column {j + 1}: {fields[i].strip()!r} is not a number"
            ) from None
    return ForeignTable(
        path=path, format="csv", columns=columns, units=units, lines=np.array(numbers, dtype=np.int64)
    )


def _names(
    path: Path, names_row: list[str] | None, units_row: list[str] | None, width: int
) -> tuple[list[str], dict[str, str]]:
    if names_row is None:
        return [str(j + 1) for j in range(width)], {}
    names: list[str] = []
    units: dict[str, str] = {}
    for j, cell in enumerate(names_row):
        name = cell.strip() or str(j + 1)
        if name in names:
            name = f"{name} ({j + 1})"  # a repeated name: told apart by its column number
        names.append(name)
        unit = split_unit(name)[1]
        if units_row is not None and units_row[j].strip():
            unit = units_row[j].strip().strip("[]()").strip() or unit
        if unit:
            units[name] = unit
    return names, units


def _column(fields: list[str], decimal: str) -> np.ndarray:
    """The numbers of one column: int64 if every field is an integer, else float64 (empty: NaN); a
    ``ValueError`` if a field is not a number."""
    texts = np.array([f.strip() for f in fields], dtype="U")
    try:
        return texts.astype(np.int64)
    except (ValueError, OverflowError):
        pass  # not all integers (or beyond int64): floats
    if decimal == ",":
        texts = np.char.replace(texts, ",", ".")
    texts[texts == ""] = "nan"
    return texts.astype(np.float64)
