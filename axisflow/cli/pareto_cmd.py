"""``axisflow pareto``: the time–energy trade-off curve per law (JSON and PNG)."""

from __future__ import annotations

import argparse
import io
import json
from pathlib import Path

from ..arguments import (
    add_params_option,
    add_solver_options,
    add_waypoint_options,
    backend_from_args,
    finite_float,
    params_from_args,
)
from ..experiment.paper import LAWS


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "pareto",
        help="sweep ω and write the total time vs total energy curve per law",
        description="Sweep the time weight ω of the min-time-energy case from 0 to 1 over the experiment's "
        "way points (same seed and count) and write DIR/pareto.json and DIR/pareto.png: total time [s] "
        "against total model energy [J] per law, with the time-optimal (bang–cruise–bang) limit.",
    )
    p.add_argument(
        "--law",
        action="append",
        choices=LAWS,
        default=None,
        help="law to sweep (repeatable; default: all three polynomial laws)",
    )
    p.add_argument("--out", metavar="DIR", default="out/pareto", help="output directory (default out/pareto)")
    add_waypoint_options(p)
    p.add_argument(
        "--omega",
        type=finite_float,
        action="append",
        default=None,
        metavar="W",
        help="an ω of the sweep (repeatable; default: 0, 0.05, …, 1)",
    )
    add_params_option(p)
    add_solver_options(p)
    p.set_defaults(func=run)


def _plot(data: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.0, 4.8), dpi=120)
    for curve in data["curves"]:
        ax.plot(curve["total_time_s"], curve["total_energy_j"], marker="o", ms=3, label=curve["law"])
    lim = data["time_optimal"]
    ax.plot([lim["total_time_s"]], [lim["total_energy_j"]], "k*", ms=10, label="time-optimal (bang)")
    ax.set_xscale("log")
    ax.set_xlabel("total time ΣT [s]")
    ax.set_ylabel(f"total model energy ΣE [J] ({data['params']['energy_accounting']})")
    ax.set_title(f"Time–energy trade-off, ω from 0 to 1 ({len(data['waypoints_m'])} way points)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    png = io.BytesIO()
    fig.savefig(png, format="png")
    plt.close(fig)
    from ..model.files import write_atomic

    write_atomic(path, png.getvalue())


def run(args: argparse.Namespace) -> int:
    from ..experiment.waypoints import random_waypoints
    from ..model.files import check_output_dir, ensure_dir, write_atomic
    from ..planner.pareto import DEFAULT_OMEGAS, check_omegas, sweep, time_optimal_point

    params = params_from_args(args)
    check_output_dir(args.out)  # a bad --out fails before the sweep, not after it
    laws = tuple(dict.fromkeys(args.law or LAWS))
    omegas = check_omegas(args.omega) if args.omega else DEFAULT_OMEGAS
    points = random_waypoints(args.waypoints, args.seed, params)
    backend = None if args.solver == "exact" else backend_from_args(args)
    curves = [sweep(points, law, params, omegas, backend=backend) for law in laws]
    bang = time_optimal_point(points, params)
    data = {
        "seed": args.seed,
        "waypoints_m": [float(w) for w in points],
        "params": params.to_dict(),
        "solver": args.solver,
        "curves": [c.to_json() for c in curves],
        "time_optimal": {"total_time_s": bang.total_time_s, "total_energy_j": bang.total_energy_j},
    }
    out = ensure_dir(args.out)
    write_atomic(out / "pareto.json", json.dumps(data, indent=1) + "\n")
    _plot(data, out / "pareto.png")
    for c in curves:
        print(f"{c.law}:")
        for pt in c.points:
            print(f"  ω = {pt.omega:5.3f}   ΣT = {pt.total_time_s:9.2f} s   ΣE = {pt.total_energy_j:9.1f} J")
    print(f"time-optimal limit: ΣT = {bang.total_time_s:.2f} s, ΣE = {bang.total_energy_j:.1f} J")
    print(f"wrote {out / 'pareto.json'} and {out / 'pareto.png'}")
    return 0
