"""``axisflow params``: print the effective axis parameters."""

from __future__ import annotations

import argparse
import json

from ..arguments import add_params_option, params_from_args
from ..model.units import PARAMETER_MEANINGS, PARAMETER_UNITS


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "params",
        help="print the effective axis parameters",
        description="Print the effective axis parameters (SI units), M_eq included.",
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
