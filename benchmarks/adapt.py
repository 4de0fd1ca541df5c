"""Adapt: online re-identification against nominal parameters and a one-time refit, on a warming axis.

Runs the adaptation experiment of :mod:`axisflow.demo.adaptation` (three simulated warm-up axes: the
nominal parameters, a one-time refit, online adaptation; its docstring tells what runs and what it
writes into ``--out``) and prints its table (``--json``: its results as one JSON object).

Goals (issue 21): with adaptation, median |E%| ≤ 1 % in every minute after the first two; the one-time
refit drifts past 3 %; the adapted plans compared with the stale ones at the same ω.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--minutes", type=float, default=10.0, help="axis time of way points per way (default 10)"
    )
    parser.add_argument("--waypoints", type=int, default=50, help="way points per pass (default 50)")
    parser.add_argument("--seed", type=int, default=0, help="way point seed (default 0)")
    parser.add_argument(
        "--adapt-from",
        choices=("refit", "nominal"),
        default="refit",
        help="the adaptive way's starting parameters (default: the one-time refit)",
    )
    parser.add_argument(
        "--out", default="logs/bench-adapt", metavar="DIR", help="output folder (new or empty)"
    )
    parser.add_argument("--no-rrd", action="store_true", help="do not write the rerun view session.rrd")


def run(args: argparse.Namespace) -> int:
    from ..demo.adaptation import AdaptationSettings, adaptation_markdown, run_adaptation
    from ..deploy.processes import stop_on_signals

    settings = AdaptationSettings(
        out=Path(args.out),
        minutes=args.minutes,
        waypoints=args.waypoints,
        seed=args.seed,
        adapt_from=args.adapt_from,
        rrd=not args.no_rrd,
    )
    say = (lambda _line: None) if args.json else (lambda line: print(line, flush=True))
    with stop_on_signals() as stop:
        results = run_adaptation(settings, say, stop)
    print(json.dumps(results, indent=1) if args.json else adaptation_markdown(results, settings))
    return 0
