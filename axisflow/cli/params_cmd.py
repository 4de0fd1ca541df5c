"""``axisflow params``: print the effective axis parameters (or those an adaptive node accepted, read
back from a recording, and write them as a parameter file)."""

from __future__ import annotations

import argparse
import json
from typing import TYPE_CHECKING

from ..acquisition.wire.keys import DEFAULT_AXIS, DEFAULT_PREFIX
from ..arguments import add_params_option, non_negative_int, params_from_args
from ..model import ParameterError
from ..model.parameter_ranges import MAX_MOTOR_SPEED_RAD_S, ranges_table
from ..model.units import PARAMETER_MEANINGS, PARAMETER_UNITS

if TYPE_CHECKING:
    from ..model import AxisParams


def ranges_epilog() -> str:
    """The physical range of every parameter, and the combination rules, as ``--help`` shows them."""
    rows = [f"  {key:<8} {text:<22} {why}" for key, text, why in ranges_table()]
    return "\n".join(
        [
            "physical ranges (a file outside them is refused at load; docs/parameters.md):",
            *rows,
            "  and F_max = tau_max·i_r/r must exceed a1 (the axis must move), v_max·i_r/r must stay",
            f"  below {MAX_MOTOR_SPEED_RAD_S:.6g} rad/s (60000 rpm, the fastest motor of the class)",
        ]
    )


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "params",
        help="print the effective axis parameters",
        description="Print the effective axis parameters (SI units), M_eq included. With --from, those of "
        "an adaptive node's accepted estimate recorded in LOG.mcap (the newest, or --version N; its M_eq and "
        "a1…a4 over the --params file), and with --out, write them as a parameter file every --params takes "
        "(docs/adaptation.md).",
        epilog=ranges_epilog(),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_params_option(p)
    p.add_argument("--json", action="store_true", help="one JSON object instead of a table")
    p.add_argument(
        "--from",
        dest="recording",
        metavar="LOG.mcap",
        default=None,
        help="read the parameters of `axisflow adapt`'s accepted estimates recorded in LOG.mcap",
    )
    p.add_argument(
        "--version",
        type=non_negative_int,
        default=None,
        metavar="N",
        help="with --from: version N (default: the newest)",
    )
    p.add_argument("--axis", default=DEFAULT_AXIS, help=f"with --from: the axis (default: {DEFAULT_AXIS})")
    p.add_argument(
        "--prefix", default=DEFAULT_PREFIX, help=f"with --from: the key prefix (default: {DEFAULT_PREFIX})"
    )
    p.add_argument(
        "--out", metavar="FILE.toml", default=None, help="with --from: write them as a parameter file"
    )
    p.add_argument("--overwrite", action="store_true", help="replace an existing --out file")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    params = params_from_args(args)
    if args.recording is None:
        if args.out is not None or args.version is not None:
            raise ParameterError(
                "--out and --version read an adaptive node's estimates: give --from LOG.mcap"
            )
    else:
        params = _adapted(args, params)
    data = params.to_dict()
    if args.json:
        print(json.dumps(data))
        return 0
    for key, value in data.items():
        unit = PARAMETER_UNITS.get(key, "")
        shown = f"{value:.6g}" if isinstance(value, float) else str(value)
        print(
            f"{key:>18} = {shown:<12} {unit:<7} {PARAMETER_MEANINGS.get(key, 'equivalent translating mass')}"
        )
    return 0


def _adapted(args: argparse.Namespace, base: AxisParams) -> AxisParams:
    """The accepted estimate's parameters over ``base``; written to ``--out`` if given."""
    from ..acquisition.logs.reader import check_mcap
    from ..acquisition.wire.keys import AxisKeys
    from ..identification.online.records import accepted_estimate, adapted_params_file
    from ..model.files import check_output_file, write_atomic

    recording = check_mcap(args.recording)
    out = None
    if args.out is not None:
        inputs = [recording] + ([args.params] if args.params else [])
        out = check_output_file(args.out, inputs=inputs, overwrite=args.overwrite, suffix=".toml")
    record = accepted_estimate(recording, AxisKeys(args.axis, args.prefix), args.version)
    params = record.applied_to(base)
    if out is not None:
        write_atomic(out, adapted_params_file(record, base, str(recording)))
        if not args.json:
            print(f"version {record.version} of axis {args.axis!r} written to {out}")
    return params
