"""The options that map a foreign log's columns to a joint (``axisflow import``, and ``axisflow
identify`` given .csv, .parquet or .mat files), shared by both commands like the Zenoh options."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ..arguments import finite_float

if TYPE_CHECKING:
    from ..acquisition.foreign import ColumnMap, CsvOptions

_MAPPED = ("time", "rate", "position", "velocity", "effort")
_DELIMITER_NAMES = {"tab": "\t", "\\t": "\t", "space": " ", "spaces": " ", "semicolon": ";", "comma": ","}


def add_column_options(parser: argparse.ArgumentParser, *, joint: bool) -> None:
    """The column map (``--time``/``--rate``, ``--position``, ``--velocity``, ``--effort``, their units
    and scale, ``--counts-per-unit``) and how to split a CSV file; ``joint``: also ``--joint``."""
    g = parser.add_argument_group(
        "foreign logs (.csv, .tsv, .parquet, .mat)",
        "which columns (or MATLAB variables) are the joint's signals, each in a unit: time s, ms, us, "
        "ns; position m, mm, um, nm (carriage) or rad, deg, rev (motor) or counts; velocity m/s, mm/s, "
        "um/s, m/min or rad/s, deg/s, rev/s, rpm or counts/s; effort N, kN or N·m, mN·m, or V, A with "
        "a scale. A column is named by its header, its header without [unit], or its number from 1; a "
        "unit the file gives (a units row, 'name [unit]') is used when none is given",
    )
    timing = g.add_mutually_exclusive_group()
    timing.add_argument("--time", metavar="COL", default=None, help="the time column")
    timing.add_argument(
        "--rate",
        metavar="HZ",
        type=finite_float,
        default=None,
        help="the sample rate, for a log without time",
    )
    g.add_argument(
        "--time-unit", metavar="UNIT", default=None, help="unit of --time (default: the file's, else s)"
    )
    g.add_argument(
        "--time-offset",
        metavar="S",
        type=finite_float,
        default=0.0,
        help="added to every time [s] (stamps must not be negative; default 0)",
    )
    for name, what in (("position", "required"), ("velocity", "optional"), ("effort", "optional")):
        g.add_argument(f"--{name}", metavar="COL", default=None, help=f"the {name} column ({what})")
        g.add_argument(f"--{name}-unit", metavar="UNIT", default=None, help=f"unit of --{name}")
    g.add_argument(
        "--effort-scale",
        metavar="K|VAR",
        default=None,
        help="effort = K × the effort column (a number, or a scalar variable of the file, e.g. gtau): N "
        "or N·m per unit of --effort-unit, required for V and A",
    )
    g.add_argument(
        "--counts-per-unit",
        metavar="N/UNIT",
        default=None,
        help="for positions in counts (velocities in counts/s): counts per a unit of position, e.g. "
        "131072/rev (motor side) or 20/um (carriage side)",
    )
    g.add_argument(
        "--delimiter",
        metavar="D",
        default=None,
        help="CSV delimiter: a character, 'tab' or 'space' (default: found from the data lines)",
    )
    g.add_argument(
        "--decimal", choices=(".", ","), default=None, help="CSV decimal mark (default: found from the data)"
    )
    if joint:
        g.add_argument(
            "--joint",
            metavar="NAME",
            default=None,
            help="the joint's name (default: carriage for carriage-side units, motor for motor-side)",
        )


def column_options_given(args: argparse.Namespace) -> list[str]:
    """The column options the command line names (``--position``, …)."""
    return [f"--{name}" for name in _MAPPED if getattr(args, name) is not None]


def column_map_from_args(args: argparse.Namespace, joint: str | None) -> ColumnMap:
    """The column map of the options (a :class:`ForeignLogError` for a missing --position or time)."""
    from ..acquisition.foreign import ColumnMap, ForeignLogError, Signal, parse_counts_per, parse_scale

    if args.position is None:
        raise ForeignLogError(
            "a foreign log needs its position column: --position COL (and its --position-unit)"
        )
    if args.time is None and args.rate is None:
        raise ForeignLogError("a foreign log needs its time: --time COL, or --rate HZ for a log without time")

    def signal(name: str) -> Signal | None:
        column = getattr(args, name)
        return None if column is None else Signal(column, getattr(args, f"{name}_unit"))

    return ColumnMap(
        position=Signal(args.position, args.position_unit),
        time=signal("time"),
        rate_hz=args.rate,
        time_offset_s=args.time_offset,
        velocity=signal("velocity"),
        effort=signal("effort"),
        effort_scale=None if args.effort_scale is None else parse_scale(args.effort_scale),
        counts_per=None if args.counts_per_unit is None else parse_counts_per(args.counts_per_unit),
        joint=joint,
    )


def csv_options_from_args(args: argparse.Namespace) -> CsvOptions:
    from ..acquisition.foreign import CsvOptions

    delimiter = args.delimiter
    if delimiter is not None:
        delimiter = _DELIMITER_NAMES.get(delimiter.lower(), delimiter)
    return CsvOptions(delimiter=delimiter, decimal=args.decimal)
