"""``axisflow savings``: what axisflow saves against the profiles drives run today."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from ..arguments import add_params_option, finite_float, non_negative_int, waypoint_count
from ..experiment.paper import LAWS

OUTPUTS = ("savings.json", "savings.md", "savings.png", "savings.mcap")


def register(sub: argparse._SubParsersAction) -> None:
    from ..acquisition.drives.plant_profiles import DEFAULT_PROFILE, PROFILE_RESOURCES
    from ..planner.baseline_limits import BASELINE_LAWS
    from ..savings.settings import (
        DEFAULT_DAYS_PER_YEAR,
        DEFAULT_HOURS_PER_DAY,
        DEFAULT_LAW,
        DEFAULT_PRICE_PER_KWH,
    )

    p = sub.add_parser(
        "savings",
        help="energy saved against a trapezoid or S-curve at equal cycle time, measured on the axis",
        description="The moves of a recorded session (LOG.mcap: every move the axis completed), of a "
        "way-point file or random way points, run three ways on the identified model (--params): the "
        "baseline (a trapezoid or an S-curve under --limits, by Ruckig), axisflow's law at the baseline's "
        "duration of each move, and axisflow's law at the ω whose plans take the baseline's cycle time. "
        "All three run through a simulated bridge on loopback (recorded to DIR/savings.mcap); the "
        "energy measured from the recording stands beside the model's, per move and per cycle, with "
        "peak torque and power, kWh and cost per year. Writes DIR/savings.json, savings.md and "
        "savings.png (energy against cycle time: the law's Pareto front, the baselines as points). "
        "Energy is mechanical, at the motor shaft, under the axis's accounting; motor and drive "
        "efficiency are not modelled (docs/savings.md).",
    )
    p.add_argument(
        "recording", nargs="?", type=Path, metavar="LOG.mcap", help="a recording of the axis's moves"
    )
    p.add_argument("--waypoints", type=Path, metavar="FILE", help="way points (one position [m] per line)")
    p.add_argument(
        "--random",
        type=waypoint_count,
        metavar="N",
        help="N random way points as `axisflow experiment` draws them",
    )
    p.add_argument("--seed", type=non_negative_int, default=0, help="the random way points' seed (default 0)")
    p.add_argument(
        "--baseline",
        choices=BASELINE_LAWS,
        default="trapezoid",
        help="the profile to compare with: trapezoid (CiA 402 profile position mode) or scurve "
        "(jerk-limited, time-optimal) (default trapezoid)",
    )
    p.add_argument(
        "--limits",
        metavar="V,A[,J]",
        help="the baseline's velocity [m/s], acceleration [m/s²] and jerk [m/s³] limits (default: the "
        "[baseline] table of --params, else v_max and the acceleration the torque limit gives there; "
        "the S-curve's jerk defaults to a/0.1 s)",
    )
    p.add_argument("--law", choices=LAWS, default=DEFAULT_LAW, help=f"axisflow's law (default {DEFAULT_LAW})")
    p.add_argument(
        "--cycles-per-day",
        type=finite_float,
        metavar="N",
        help=f"cycles a day (default: the baseline's cycle back to back for {DEFAULT_HOURS_PER_DAY:g} h)",
    )
    p.add_argument(
        "--days-per-year",
        type=finite_float,
        default=DEFAULT_DAYS_PER_YEAR,
        metavar="D",
        help=f"working days a year (default {DEFAULT_DAYS_PER_YEAR:g})",
    )
    p.add_argument(
        "--price",
        type=finite_float,
        default=DEFAULT_PRICE_PER_KWH,
        metavar="PER_KWH",
        help=f"price of a kWh, in any currency (default {DEFAULT_PRICE_PER_KWH:g})",
    )
    p.add_argument(
        "--plant-profile",
        choices=sorted(PROFILE_RESOURCES),
        default=DEFAULT_PROFILE,
        help=f"the simulated axis's plant (default {DEFAULT_PROFILE}; docs/plant.md)",
    )
    p.add_argument("--model-only", action="store_true", help="plan and report on the model; run nothing")
    add_params_option(p)
    p.add_argument("--out", metavar="DIR", required=True, type=Path, help="output folder")
    p.add_argument("--overwrite", action="store_true", help="replace an earlier comparison in DIR")
    p.add_argument("--json", action="store_true", help="print the summary as one JSON object, nothing else")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..model.files import check_output_files
    from ..savings.settings import SavingsSettings
    from ..savings.study import run_savings

    inputs = [s for s in (args.recording, args.waypoints) if s is not None]
    if args.recording is not None:
        from ..acquisition.logs.reader import check_mcap

        check_mcap(args.recording)
    if args.params is not None:
        inputs.append(Path(args.params))
    out = check_output_files(args.out, OUTPUTS, inputs=inputs, overwrite=args.overwrite)
    settings = SavingsSettings(
        out=out,
        recording=args.recording,
        waypoints_file=args.waypoints,
        random_waypoints=args.random,
        seed=args.seed,
        params_path=args.params,
        baseline=args.baseline,
        limits=args.limits,
        law=args.law,
        cycles_per_day=args.cycles_per_day,
        days_per_year=args.days_per_year,
        price_per_kwh=args.price,
        measure=not args.model_only,
        plant_profile=args.plant_profile,
        overwrite=args.overwrite,
    )

    def progress(line: str) -> None:
        if not args.json:
            print(line, file=sys.stderr, flush=True)

    report = run_savings(settings, progress)
    if args.json:
        print(json.dumps(report.summary(), allow_nan=False))
        return 0
    print((out / "savings.md").read_text("utf-8"), end="")
    print(f"\nwrote {out / 'savings.md'}, {out / 'savings.json'} and {out / 'savings.png'}")
    return 0
