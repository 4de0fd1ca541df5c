"""Start-up: ``axisflow --help`` and every verb's ``--help``, each in a fresh interpreter, against a bare
interpreter and one that only imports numpy, in this run.

Each command runs ``--repeat`` times; the table shows the median wall time and the ratio to the
numpy-only interpreter (what any command of a numpy program pays). Byte-code caching follows the
environment (``PYTHONDONTWRITEBYTECODE``, set on this machine: each run then compiles every module of
ours it imports, as no cache is written); ``--bytecode`` measures with the cache written and used, in a
temporary folder of the run's own (``PYTHONPYCACHEPREFIX``), so that it leaves no cache in the source
tree for a later run to read. The goal (issue 23): every one ≤ 0.3 s.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

from axisflow.arguments import positive_int

GOAL_S = 0.3
_CLI = "import sys; from axisflow.cli import main; sys.exit(main())"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--repeat", type=positive_int, default=5, help="runs of each command (default 5)")
    parser.add_argument(
        "--bytecode",
        action="store_true",
        help="let Python write and use its byte-code cache (unset PYTHONDONTWRITEBYTECODE)",
    )


def _median_s(argv: list[str], repeat: int, env: dict[str, str]) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        subprocess.run(argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def run(args: argparse.Namespace) -> int:
    env = dict(os.environ)
    with tempfile.TemporaryDirectory(prefix="axisflow-bytecode-") as cache:
        if args.bytecode:
            # written and read in a cache of this run's own: the source tree keeps none that a later
            # run without --bytecode would read
            env.pop("PYTHONDONTWRITEBYTECODE", None)
            env["PYTHONPYCACHEPREFIX"] = cache
            subprocess.run(
                [sys.executable, "-c", _CLI, "--help"], env=env, stdout=subprocess.DEVNULL, check=True
            )
        python = [sys.executable]
        bare = _median_s([*python, "-c", "pass"], args.repeat, env)
        numpy = _median_s([*python, "-c", "import numpy"], args.repeat, env)
        rows = {"axisflow --help": _median_s([*python, "-c", _CLI, "--help"], args.repeat, env)}
        for verb in args.cli_verbs():  # the command line hands its verbs in (benchmarks sit below it)
            argv = [*python, "-c", _CLI, verb, "--help"]
            rows[f"axisflow {verb} --help"] = _median_s(argv, args.repeat, env)
    worst = max(rows.values())
    result = {
        "bytecode_cache": "PYTHONDONTWRITEBYTECODE" not in env,
        "repeat": args.repeat,
        "bare_python_s": bare,
        "numpy_only_s": numpy,
        "commands_s": rows,
        "worst_s": worst,
        "goal_s": GOAL_S,
        "goal_met": worst <= GOAL_S,
    }
    if args.json:
        print(json.dumps(result, indent=2))
    else:
        print(table(result))
    return 0


def table(r: dict) -> str:
    cache = "written and used" if r["bytecode_cache"] else "off (PYTHONDONTWRITEBYTECODE)"
    lines = [
        f"start-up, median of {r['repeat']} fresh interpreters each; byte-code cache {cache}",
        f"baselines: bare python {r['bare_python_s']:.3f} s, "
        f"python -c 'import numpy' {r['numpy_only_s']:.3f} s",
        f"{'command':40} {'s':>7} {'÷ numpy':>8}",
    ]
    for name, seconds in r["commands_s"].items():
        lines.append(f"{name:40} {seconds:>7.3f} {seconds / r['numpy_only_s']:>8.2f}")
    lines.append(
        f"slowest {r['worst_s']:.3f} s; goal <= {r['goal_s']:g} s: {'met' if r['goal_met'] else 'NOT met'}"
    )
    return "\n".join(lines)
