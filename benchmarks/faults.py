"""Faults: runs the fault scenarios of :mod:`axisflow.benchmarks.fault_scenarios` and prints them as one
table.

Each scenario (one module of :mod:`axisflow.benchmarks.fault_scenarios`) starts real processes,
measures what survives a fault and returns a result object whose rows this prints;
tests/benchmarks/fault_scenarios asserts on the same objects.
``--only NAME`` runs one; ``--json`` prints one JSON object; the exit code is 1 if a contract failed.
"""

from __future__ import annotations

import argparse
import importlib
import json
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from axisflow.model import AxisflowError

if TYPE_CHECKING:
    from axisflow.benchmarks.fault_scenarios.outcome import FaultResult, Outcome

SCENARIOS: dict[str, Callable[[Path, Any], FaultResult]] = {
    "recorder_kill": lambda work, _args: _scenario("recorder_kill")(work),
    "bridge_kill": lambda work, _args: _scenario("bridge_kill")(work),
    "planner_kill": lambda work, _args: _scenario("planner_kill")(work),
    "bad_payloads": lambda work, args: _scenario("bad_payloads")(work, per_sender=args.payloads),
    "move_flood": lambda work, _args: _scenario("move_flood")(work),
    "session_faults": lambda work, args: _scenario("session_faults")(work, peers=args.peers),
    "quick_stop": lambda work, _args: _scenario("quick_stop")(work),
}
"""the scenarios by the name ``--only`` takes, in the order they run"""


def _scenario(name: str) -> Callable[..., FaultResult]:
    """The function of scenario ``name``: its module :mod:`axisflow.benchmarks.fault_scenarios.<name>`
    (with Zenoh) loads when it runs, not when ``axisflow`` parses its command line."""
    return getattr(importlib.import_module(f"axisflow.benchmarks.fault_scenarios.{name}"), name)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from axisflow.arguments import positive_int

    parser.add_argument(
        "--only",
        action="append",
        choices=list(SCENARIOS),
        metavar="NAME",
        help=f"run only this scenario (repeatable): {', '.join(SCENARIOS)}",
    )
    parser.add_argument(
        "--payloads", type=positive_int, default=1000, help="bad payloads per sender (default 1000)"
    )
    parser.add_argument(
        "--peers", type=positive_int, default=30, help="Zenoh peers opened and closed (default 30)"
    )
    parser.add_argument(
        "--keep",
        metavar="DIR",
        default=None,
        help="keep the recordings and process logs in DIR (default: none)",
    )


def run_scenario(name: str, work: Path, args: argparse.Namespace) -> tuple[list[Outcome], float]:
    """One scenario's rows and its wall time [s]; a scenario that cannot run is one failed row."""
    work.mkdir(parents=True, exist_ok=True)
    from axisflow.benchmarks.fault_scenarios.outcome import Outcome

    t0 = time.monotonic()
    try:
        rows = SCENARIOS[name](work, args).outcomes()
    except Exception as exc:  # a benchmark reports a broken scenario and goes on with the others
        rows = [
            Outcome(
                name,
                False,
                f"could not run: {type(exc).__name__}: {exc}",
                f"axisflow bench faults --only {name}",
            )
        ]
    return rows, time.monotonic() - t0


def run(args: argparse.Namespace) -> int:
    """All (or ``--only``) scenarios; the table, or one JSON object; exit 1 if a contract failed."""
    from axisflow.acquisition.drives.plant import load_plant
    from axisflow.model import default_params

    names = list(dict.fromkeys(args.only or SCENARIOS))
    if args.keep and Path(args.keep).exists() and any(Path(args.keep).iterdir()):
        raise AxisflowError(
            f"--keep {args.keep} is not empty: give a new folder (recordings are never overwritten)"
        )
    rows: list[dict[str, Any]] = []
    plant = load_plant(None, default_params()).describe()  # what every bridge of the scenarios runs
    if not args.json:
        print(f"faults: the bridges drive the simulated axis, plant {plant}", file=sys.stderr, flush=True)
    with tempfile.TemporaryDirectory(prefix="axisflow-faults-") as tmp:
        base = Path(args.keep) if args.keep else Path(tmp)
        for name in names:
            outcomes, seconds = run_scenario(name, base / name, args)
            rows += [{"scenario": name, "seconds": seconds, **o.to_dict()} for o in outcomes]
            if not args.json:
                held = "held" if all(o.passed for o in outcomes) else "FAILED"
                print(f"{name}: {held} ({seconds:.0f} s)", file=sys.stderr, flush=True)
    if args.json:
        summary = {"plant": plant, "faults": rows, "all_held": all(r["passed"] for r in rows)}
        print(json.dumps(summary, indent=1, default=str))
    else:
        print_table(rows)
    return 0 if all(r["passed"] for r in rows) else 1


def print_table(rows: list[dict[str, Any]]) -> None:
    """The fault table in Markdown (docs/trust.md keeps one)."""
    print("| fault | held | outcome (measured) | command |")
    print("|---|---|---|---|")
    for r in rows:
        print(f"| {r['fault']} | {'yes' if r['passed'] else '**no**'} | {r['outcome']} | `{r['command']}` |")
