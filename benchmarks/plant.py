"""Plant: the cost of one 1 ms tick of the simulated drive (read + apply) for each plant profile,
against the ideal profile measured in the same run.

The bridge runs the simulated axis in its 1 kHz loop in pure Python (~4000 integration steps per
second of drive time), so a tick's cost bounds how fast ``--speed 0`` runs. Each profile's drive
tracks the same setpoints (from rest at 0.1 m to 0.7 m and back every 2 s, a raised cosine, with the
model's feed-forward); the profiles take turns, ``--rounds`` times, and each keeps its fastest round (the
least disturbed by whatever else runs on the machine). Goal (issue 21): the realistic profiles cost
at most about twice the ideal one.

``--warm-up S`` then runs the ``warm-up`` profile's drive on the same motion for S seconds of drive time
and prints, once a minute, the lubricant's temperature and the true friction against its cold values
(:meth:`~axisflow.acquisition.drives.sim_axis.SimulatedAxis.true_params`): how fast the plant drifts
under continuous fast moves (peak 0.94 m/s).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import time
from typing import TYPE_CHECKING

from ..acquisition.drives.plant_profiles import PROFILE_RESOURCES

if TYPE_CHECKING:  # the simulated axis loads when the benchmark runs
    from ..acquisition.drives.drive import Setpoint

GOAL_RATIO = 2.0


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--ticks", type=int, default=2000, help="ticks per round (default 2000)")
    parser.add_argument("--rounds", type=int, default=40, help="rounds per profile (default 40)")
    parser.add_argument(
        "--warm-up",
        type=float,
        default=0.0,
        metavar="S",
        help="then run the warm-up plant for S seconds of drive time and print its drift (default: no)",
    )


def _setpoints(n: int) -> list[Setpoint]:
    """x = 0.1 + 0.3·(1 − cos ωt), ω = 2π·0.5 Hz: from rest at 0.1 m to 0.7 m and back, every 2 s."""
    from ..acquisition.drives.drive import Setpoint
    from ..model import cart_force, default_params

    p = default_params()
    w, amplitude = 2.0 * math.pi * 0.5, 0.3
    out = []
    for k in range(n):
        t = k * 1e-3
        x = 0.1 + amplitude * (1.0 - math.cos(w * t))
        v, a = amplitude * w * math.sin(w * t), amplitude * w * w * math.cos(w * t)
        out.append(Setpoint(x, v, a, float(cart_force(v, a, p))))
    return out


def run(args: argparse.Namespace) -> int:
    from ..acquisition.drives.plant import load_profile
    from ..acquisition.drives.sim_axis import SimulatedAxis
    from ..model import default_params

    nominal = default_params()
    setpoints = _setpoints(args.ticks)
    drives = {}
    for name in PROFILE_RESOURCES:
        plant = load_profile(name, nominal)
        plant = dataclasses.replace(
            plant, simulation=dataclasses.replace(plant.simulation, initial_position_m=0.1)
        )
        drives[name] = SimulatedAxis(plant, nominal, 1_700_000_000_000_000_000)
    best = dict.fromkeys(drives, math.inf)
    errors = dict.fromkeys(drives, 0.0)
    lost = dict.fromkeys(drives, 0)
    for _ in range(args.rounds):
        for name, drive in drives.items():
            t0 = time.perf_counter()
            for sp in setpoints:
                sample = drive.read()
                fresh = drive.status().fresh
                drive.apply(sp)
                if not fresh:
                    lost[name] += 1
                else:
                    errors[name] = max(errors[name], abs(sample.position_m - sp.position_m))
            best[name] = min(best[name], (time.perf_counter() - t0) / args.ticks)
    ideal = best["ideal"]
    result = {
        "ticks_per_round": args.ticks,
        "rounds": args.rounds,
        "goal_ratio": GOAL_RATIO,
        "profiles": {
            name: {
                "plant": drives[name].plant.describe(),
                "us_per_tick": best[name] * 1e6,
                "ratio_to_ideal": best[name] / ideal,
                "max_tracking_error_mm": errors[name] * 1e3,
                "samples_lost": lost[name],
            }
            for name in drives
        },
    }
    if args.warm_up > 0:
        result["warm_up"] = _warm_up(args.warm_up, setpoints if len(setpoints) == 2000 else _setpoints(2000))
    if args.json:
        print(json.dumps(result, indent=2))
        return 0
    print(f"plant benchmark: {args.ticks} ticks × {args.rounds} rounds per profile (fastest round kept)")
    print(f"{'profile':10} {'µs/tick':>8} {'× ideal':>8} {'max tracking error':>19} {'lost':>6}")
    for name, r in result["profiles"].items():
        print(
            f"{name:10} {r['us_per_tick']:8.2f} {r['ratio_to_ideal']:7.2f}× "
            f"{r['max_tracking_error_mm']:16.3f} mm {r['samples_lost']:6d}"
        )
    print(f"goal: the realistic profiles within {GOAL_RATIO:g}× the ideal per tick")
    if "warm_up" in result:
        print(f"\nwarm-up plant, {args.warm_up:g} s of drive time (0.1 → 0.7 m and back every 2 s):")
        print(f"{'minute':>6} {'T [°C]':>7} {'a1':>8} {'a2':>8} {'a3':>8}")
        for row in result["warm_up"]:
            print(
                f"{row['minute']:6.0f} {row['temperature_c']:7.2f} {row['a1_change_pct']:+7.2f}% "
                f"{row['a2_change_pct']:+7.2f}% {row['a3_change_pct']:+7.2f}%"
            )
    return 0


def _warm_up(seconds: float, period: list[Setpoint]) -> list[dict[str, float]]:
    """The warm-up drive on ``period`` (2 s, repeated) for ``seconds``; the drift once a minute."""
    from ..acquisition.drives.plant import load_profile
    from ..acquisition.drives.sim_axis import SimulatedAxis
    from ..model import default_params

    nominal = default_params()
    plant = load_profile("warm-up", nominal)
    plant = dataclasses.replace(
        plant, simulation=dataclasses.replace(plant.simulation, initial_position_m=0.1)
    )
    drive = SimulatedAxis(plant, nominal, 1_700_000_000_000_000_000)
    cold = drive.true_params()
    rows = []
    ticks = round(seconds * 1000)
    for k in range(ticks + 1):
        if k % 60_000 == 0:
            now = drive.true_params()
            rows.append(
                {
                    "minute": k / 60_000,
                    "temperature_c": drive.temperature_c,
                    "a1_change_pct": (now.a1 / cold.a1 - 1) * 100,
                    "a2_change_pct": (now.a2 / cold.a2 - 1) * 100,
                    "a3_change_pct": (now.a3 / cold.a3 - 1) * 100,
                }
            )
        drive.read()
        drive.apply(period[k % len(period)])
    return rows
