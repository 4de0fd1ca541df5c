"""``axisflow import``: foreign logs (a drive scope's CSV, Parquet, MATLAB .mat) → a JointState MCAP."""

from __future__ import annotations

import argparse
import json

from .column_options import add_column_options, column_map_from_args, csv_options_from_args


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "import",
        help="import CSV, Parquet or MATLAB logs as a JointState MCAP (what identify reads)",
        description="Read one joint's time, position, velocity and effort from the columns of FILE (a "
        "drive scope's CSV export, a Parquet file, a MATLAB .mat file of version 5 or 7.3), convert "
        "them to SI units (m, m/s, N on the carriage side; rad, rad/s, N·m on the motor side) with "
        "integer-nanosecond stamps, and write them as the recorder writes a log: one "
        "sensor_msgs/msg/JointState topic of one joint in an MCAP file (ROS 2 profile). Several FILEs "
        "make one log in time order, each with its own time range (overlapping ranges are refused: "
        "import separate runs into separate files). A single missing value (NaN, an empty field) drops "
        "its row as a lost sample; a run of them is refused. The output is written whole or not at all.",
    )
    p.add_argument("files", nargs="+", metavar="FILE", help="the logs (.csv, .tsv, .parquet, .mat)")
    p.add_argument("--out", required=True, metavar="LOG.mcap", help="the MCAP file to write")
    p.add_argument("--overwrite", action="store_true", help="replace LOG.mcap if it exists")
    p.add_argument(
        "--topic", default=None, metavar="T", help="the JointState topic to write (default /joint_states)"
    )
    p.add_argument(
        "--format",
        choices=("csv", "parquet", "mat"),
        default=None,
        help="the files' format (default: by their suffix)",
    )
    p.add_argument("--json", action="store_true", help="print what was written as JSON")
    add_column_options(p, joint=True)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..acquisition.foreign import DEFAULT_TOPIC, import_logs

    result = import_logs(
        args.files,
        column_map_from_args(args, args.joint),
        args.out,
        topic=args.topic or DEFAULT_TOPIC,
        overwrite=args.overwrite,
        file_format=args.format,
        csv=csv_options_from_args(args),
    )
    if args.json:
        print(json.dumps(result.as_dict(), indent=1))
    else:
        print(result.describe())
    return 0
