"""``axisflow experiment``: the paper's 100-way-point experiment (offline for now)."""

from __future__ import annotations

import argparse
import json

from ..arguments import (
    add_params_option,
    add_solver_options,
    add_waypoint_options,
    backend_from_args,
    finite_float,
    params_from_args,
)
from ..experiment import run_offline, table_markdown
from ..model import AxisflowError
from ..model.files import check_output_dir, ensure_dir, write_atomic
from ..planner import DEFAULT_OMEGA


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "experiment",
        help="reproduce the paper's Table 2",
        description="Plan the moves through random way points for each case × law (Table 2 of the paper) "
        "and write DIR/table2.md, DIR/table2.json and DIR/limits.json (each row against the physical limit: "
        "T_poly/T_limit and E_poly/E_limit per move and in total).",
    )
    p.add_argument("--offline", action="store_true", help="plan only, no drive (the only mode for now)")
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
    if not args.offline:
        raise AxisflowError(
            "the online experiment needs the drive bridge, which is not built yet: run with --offline"
        )
    params = params_from_args(args)
    backend = backend_from_args(args)
    out = check_output_dir(args.out)  # a bad --out fails before the run, not after it
    result = run_offline(
        params, backend, seed=args.seed, waypoints=args.waypoints, omega=args.omega, limits=not args.no_limits
    )
    table = table_markdown(result)
    ensure_dir(out)
    write_atomic(out / "table2.json", json.dumps(result.to_json(), indent=1) + "\n")
    write_atomic(out / "limits.json", json.dumps(result.limits_json(), indent=1) + "\n")
    write_atomic(out / "table2.md", table)
    print(table, end="")
    print(f"\nwrote {out / 'table2.md'}, {out / 'table2.json'} and {out / 'limits.json'}")
    return 0
