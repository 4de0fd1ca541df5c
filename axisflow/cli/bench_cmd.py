"""``axisflow bench NAME``: run one benchmark from ``axisflow.benchmarks``.

Each benchmark module ``axisflow.benchmarks.<name>`` provides ``add_arguments(parser)`` and
``run(args) -> int``; it prints a table with ratios against a baseline measured in the same run
(``--json``: one JSON object instead).
"""

from __future__ import annotations

import argparse
import importlib

# benchmark modules under axisflow.benchmarks, by the name used on the command line
BENCHMARKS: dict[str, str] = {
    "pipeline": "pipeline",
    "planner": "planner",
    "identify": "identify",
    "view": "view",
    "faults": "faults",
    "plant": "plant",
    "drives": "drives",
    "joins": "joins",
    "adapt": "adapt",
    "moves": "moves",
    "startup": "startup",
    "all": "all",
    "cell": "cell",
    "ros2": "ros2",
}


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "bench",
        help="run a benchmark (speed/memory goals against an in-run baseline)",
        description="Run a benchmark; each prints a table with ratios against a baseline "
        "measured in the same run.",
    )
    names = p.add_subparsers(dest="benchmark", metavar="NAME", required=True)
    for name, module in BENCHMARKS.items():
        mod = importlib.import_module(f"axisflow.benchmarks.{module}")
        bp = names.add_parser(
            name,
            help=(mod.__doc__ or "").strip().splitlines()[0] if mod.__doc__ else None,
            description=mod.__doc__,
        )
        bp.add_argument("--json", action="store_true", help="print one JSON object instead of a table")
        mod.add_arguments(bp)
        bp.set_defaults(func=mod.run, cli_verbs=_verbs)


def _verbs() -> list[str]:
    """The verbs of ``axisflow``, as its parser lists them (for ``bench startup``)."""
    from . import build_parser

    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    return list(sub.choices)
