"""``axisflow params``: print the effective axis parameters."""

from __future__ import annotations

import argparse
import json

from ..arguments import add_params_option, params_from_args
from ..model.parameter_ranges import MAX_MOTOR_SPEED_RAD_S, ranges_table
from ..model.units import PARAMETER_MEANINGS, PARAMETER_UNITS


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
        description="Print the effective axis parameters (SI units), M_eq included.",
        epilog=ranges_epilog(),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_params_option(p)
    p.add_argument("--json", action="store_true", help="one JSON object instead of a table")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    params = params_from_args(args)
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
