"""``axisflow experiment``: the paper's 100-way-point experiment, planned offline (Table 2's planned
columns). The same experiment on an axis is ``axisflow planner`` recorded, then ``axisflow table2``."""

from __future__ import annotations

import argparse
import sys

from ..arguments import (
    add_params_option,
    add_solver_options,
    add_waypoint_options,
    backend_from_args,
    finite_float,
    params_from_args,
)
from ..planner import DEFAULT_OMEGA


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "experiment",
        help="reproduce the paper's Table 2, planned offline",
        description="Plan the moves through random way points for each case × law (Table 2 of the paper), "
        "with each move against the physical limit (T/T_limit, E/E_limit), and write DIR/table2.md and "
        "DIR/table2.json. The measured columns (E_exp, E%) come from running the moves on an axis: "
        "record `axisflow planner`, then `axisflow table2` (or `axisflow demo`).",
    )
    # accepted so that older scripts still run, with a note; not shown in --help
    p.add_argument("--offline", action="store_true", help=argparse.SUPPRESS)
    p.add_argument("--out", metavar="DIR", required=True, help="output directory (created if missing)")
    add_waypoint_options(p)
    p.add_argument(
        "--omega",
        type=finite_float,
        default=DEFAULT_OMEGA,
        help=f"time weight ω of the min-time-energy case (default {DEFAULT_OMEGA})",
    )
    p.add_argument(
        "--no-limits",
        action="store_true",
        help="skip the comparison with the physical limit (bang–cruise–bang time, least energy)",
    )
    add_params_option(p)
    # the experiment reproduces the paper, so its default stays the paper's solver
    add_solver_options(p, default="ipopt")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..experiment.offline import run_offline
    from ..experiment.table2_markdown import table_markdown, write_table2
    from ..model.files import check_output_dir

    params = params_from_args(args)
    backend = backend_from_args(args)
    out = check_output_dir(args.out)  # a bad --out fails before the run, not after it
    table = run_offline(
        params, backend, seed=args.seed, waypoints=args.waypoints, omega=args.omega, limits=not args.no_limits
    )
    json_path, md_path = write_table2(table, out)
    print(table_markdown(table), end="")
    print(f"\nwrote {md_path} and {json_path}")
    if args.offline:  # after the work: a refusal stays one line on stderr
        print(
            "note: --offline is no longer needed and will go (the experiment always plans offline; on an "
            "axis: record `axisflow planner`, then `axisflow table2`)",
            file=sys.stderr,
        )
    return 0
