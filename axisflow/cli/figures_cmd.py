"""``axisflow figures``: the paper's figures (2, 4a, 4b, 5a, 5b) as PNG files."""

from __future__ import annotations

import argparse
import json
import sys

from ..arguments import add_params_option, non_negative_int, params_from_args, waypoint_count
from ..experiment.paper import FIG5_WAYPOINTS

# the figures (matplotlib, the planners, the refit) and the log reader are imported when the command runs


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "figures",
        help="the paper's figures (2, 4a, 4b, 5a, 5b) as PNG files",
        description="Draw the paper's figures into DIR: fig2.png (identification, measured against model "
        "torque with the residual; only with --excitation), fig4a.png (energy of a poly5 move over distance "
        "and time with the minimum-time limit and the time-energy optimum), fig4b.png (IPOPT's optimal time "
        "and solve time against its iteration cap, against the exact optimum), fig5a.png and fig5b.png "
        "(position, velocity and torque through random way points per law, minimum time and minimum "
        "time-energy: the plans sampled at 1 kHz with the model, or a recording's measured samples with "
        "--recording). The files are written together and atomically, after all are drawn; existing ones "
        "are replaced only with --overwrite.",
    )
    p.add_argument("--out", required=True, metavar="DIR", help="output directory (created if missing)")
    p.add_argument("--overwrite", action="store_true", help="replace the figures of an earlier run in DIR")
    p.add_argument(
        "--excitation",
        default=None,
        metavar="LOG.mcap",
        help="excitation recording for Fig. 2 (refit from it)",
    )
    p.add_argument(
        "--recording",
        default=None,
        metavar="LOG.mcap",
        help="recording of planner runs: Fig. 5 from its measured samples instead of the plans",
    )
    p.add_argument(
        "--waypoints",
        type=waypoint_count,
        default=FIG5_WAYPOINTS,
        metavar="N",
        help=f"random way points of Fig. 5 (default {FIG5_WAYPOINTS})",
    )
    p.add_argument("--seed", type=non_negative_int, default=0, help="seed of the way points (default 0)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    add_params_option(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..acquisition.logs.reader import check_mcap
    from ..experiment.waypoints import random_waypoints
    from ..model.files import check_output_files
    from ..viz.figures import FIGURE_FILES, render_figures, save_figures

    params = params_from_args(args)
    logs = [check_mcap(log) for log in (args.excitation, args.recording) if log is not None]
    # a bad --out fails before the work, not after it
    out = check_output_files(args.out, FIGURE_FILES, inputs=logs, overwrite=args.overwrite)
    waypoints = random_waypoints(args.waypoints, args.seed, params)

    def progress(text: str) -> None:
        if not args.json:
            print(f"  {text}", file=sys.stderr, flush=True)

    figures = render_figures(params, waypoints, args.excitation, args.recording, progress)
    written = save_figures(figures, out)
    if args.json:
        data = {
            "written": [str(p) for p in written],
            "bytes": {p.name: len(figures.pngs[p.name]) for p in written},
            "skipped": figures.skipped,
            "seconds": figures.seconds,
        }
        print(json.dumps(data, indent=1))
    else:
        for path in written:
            print(f"wrote {path} ({len(figures.pngs[path.name]) / 1024:.0f} kB)")
        for name, why in figures.skipped.items():
            print(f"skipped {name}: {why}")
    return 0
