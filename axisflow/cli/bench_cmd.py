"""``axisflow bench NAME``: run one benchmark from ``axisflow.benchmarks``.

Each benchmark module ``axisflow.benchmarks.<name>`` provides ``add_arguments(parser)`` and
``run(args) -> int``; it prints a table with ratios against a baseline measured in the same run
(``--json``: one JSON object instead).

A benchmark's module loads only when its name is parsed (``bench NAME …``), with its options
(:func:`add_benchmark`): the list of benchmarks (``bench --help``) shows each one's docstring read
from its source (:func:`benchmark_docstring`), so that no other command line loads a benchmark.
"""

from __future__ import annotations

import argparse
import ast
import functools
import importlib
import importlib.util
import tokenize
from collections.abc import Callable, Sequence
from typing import Any

# benchmark modules under axisflow.benchmarks, by the name used on the command line
BENCHMARKS: dict[str, str] = {
    "pipeline": "pipeline",
    "planner": "planner",
    "identify": "identify",
    "identify-real": "identify_real",
    "fleet": "fleet",
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
    names = p.add_subparsers(dest="benchmark", metavar="NAME", required=True, action=_Benchmarks)
    for name, module in BENCHMARKS.items():
        doc = benchmark_docstring(module)
        names.add_parser(name, help=doc.strip().splitlines()[0] if doc else None, description=doc)


class _Benchmarks(argparse._SubParsersAction):
    """The benchmarks by name: the one named on the command line gets its options before it parses."""

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: str | Sequence[Any] | None,
        option_string: str | None = None,
    ) -> None:
        name = values[0] if isinstance(values, list | tuple) and values else None
        if name in self.choices:
            add_benchmark(self.choices[name], BENCHMARKS[name])
        super().__call__(parser, namespace, values, option_string)


def add_benchmark(parser: argparse.ArgumentParser, module: str) -> None:
    """Load the benchmark ``module`` and give ``parser`` its options (once)."""
    if parser.get_default("func") is not None:
        return
    mod = importlib.import_module(f"axisflow.benchmarks.{module}")
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of a table")
    mod.add_arguments(parser)
    parser.set_defaults(func=functools.partial(_measured, mod.run), cli_verbs=_verbs)


def _measured(run: Callable[[argparse.Namespace], int], args: argparse.Namespace) -> int:
    """A benchmark's run, with the machine reference measured in it (benchmarks/machine.py)."""
    from ..benchmarks.machine import run_with_reference

    return run_with_reference(run, args)


def benchmark_docstring(module: str) -> str | None:
    """The docstring of the benchmark ``module``, read from the first statement of its source without
    importing it (None: it has none)."""
    spec = importlib.util.find_spec(f"axisflow.benchmarks.{module}")
    if spec is None or spec.origin is None:
        raise ModuleNotFoundError(f"no benchmark module axisflow.benchmarks.{module}")
    skip = (tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE, tokenize.ENCODING)
    with open(spec.origin, encoding="utf-8") as source:
        first = next(t for t in tokenize.generate_tokens(source.readline) if t.type not in skip)
    return ast.literal_eval(first.string) if first.type == tokenize.STRING else None


def _verbs() -> list[str]:
    """The verbs of ``axisflow``, as its parser lists them (for ``bench startup``)."""
    from . import build_parser

    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    return list(sub.choices)
