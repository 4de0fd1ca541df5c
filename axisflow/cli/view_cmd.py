"""``axisflow view``: rerun views of the axes, from MCAP logs or live from Zenoh."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import TYPE_CHECKING

from ..acquisition.wire.keys import AxisKeys, all_keys
from ..arguments import add_params_option, finite_float, params_from_args, tcp_port_or_any
from ..deploy.processes import notify_ready, stop_on_signals
from .zenoh_options import add_zenoh_options, zenoh_options_from_args

if TYPE_CHECKING:
    from ..model import AxisParams
    from ..viz.outputs import RerunOutput

# the views (and rerun) are imported when the command runs: other commands start without them


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "view",
        help="rerun view of the axes (position, velocity, torque, tracking error, power, energy per move, "
        "move statuses), from MCAP logs or live",
        description="Show the axes of MCAP logs (every /<prefix>/<axis>/state, setpoint, event and plan "
        "topic) or, with --live, of the Zenoh keys as they arrive, in rerun, laid out like the paper's "
        "Fig. 5: position with the stroke and the way points, velocity with ±v_max, motor torque against "
        "the feed-forward with ±tau_max, tracking error, mechanical power and energy per move, and the "
        "bridge's move statuses; one column per axis. -o saves a .rrd (atomically; no viewer needed), "
        "--spawn opens the rerun viewer, --serve serves a web viewer on 127.0.0.1. Without any of them a "
        "log view is saved beside the first log as LOG.rrd. An existing .rrd is replaced only with "
        "--overwrite, an input never. A chunk of a log that cannot be read is skipped and named.",
    )
    p.add_argument("logs", nargs="*", metavar="LOG.mcap", help="recordings to view (not with --live)")
    p.add_argument("--live", action="store_true", help="view the Zenoh keys live instead of logs")
    p.add_argument(
        "--axis",
        action="append",
        default=[],
        metavar="A",
        help="view only this axis of a recording of several (a cell's: a0, a1, …; repeatable); default: "
        "every axis. With --live: one axis, its keys <prefix>/A/**",
    )
    p.add_argument(
        "--keys", default=None, metavar="EXPR", help=f"with --live: key expression (default {all_keys()})"
    )
    p.add_argument(
        "--duration", type=finite_float, default=None, metavar="S", help="with --live: stop after S seconds"
    )
    p.add_argument("-o", "--output", default=None, metavar="FILE.rrd", help="save the view to FILE.rrd")
    p.add_argument("--overwrite", action="store_true", help="replace FILE.rrd if it exists")
    viewer = p.add_mutually_exclusive_group()
    viewer.add_argument("--spawn", action="store_true", help="open the rerun viewer (stays open)")
    viewer.add_argument(
        "--serve",
        action="store_true",
        help="serve a web viewer on 127.0.0.1 until Ctrl-C (or the end of --duration)",
    )
    p.add_argument(
        "--web-port",
        type=tcp_port_or_any,
        default=0,
        metavar="N",
        help="with --serve: the web viewer's port (default: a free one)",
    )
    p.add_argument("--json", action="store_true", help="print the summary as one JSON object")
    add_params_option(p)
    add_zenoh_options(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..acquisition.logs.reader import check_mcap
    from ..model.files import check_distinct_inputs
    from ..viz.errors import VizError
    from ..viz.outputs import RerunOutput, ViewOutput, view_size_estimate
    from ..viz.session import SessionLogs, log_session

    params = params_from_args(args)
    if args.live:
        return _run_live(args, params)
    if args.keys is not None or args.duration is not None:
        raise VizError("--keys and --duration apply to --live only")
    if not args.logs:
        raise VizError("nothing to view: give LOG.mcap files, or --live")
    logs = tuple(check_mcap(log) for log in args.logs)
    check_distinct_inputs(logs, "log")
    rrd = args.output
    if rrd is None and not (args.spawn or args.serve):
        rrd = logs[0].with_suffix(".rrd")
    output = ViewOutput(
        rrd=Path(rrd) if rrd else None,
        spawn=args.spawn,
        serve=args.serve,
        web_port=args.web_port,
        expected_bytes=view_size_estimate(logs),
        inputs=logs,
        overwrite=args.overwrite,
    )
    session = SessionLogs.open(logs, only=args.axis)
    with RerunOutput(output, session.blueprint()) as out:
        summary = log_session(out.rec, session, params)  # Ctrl-C here: nothing is written
        data = {
            "logs": [str(p) for p in summary.logs],
            "axes": [vars(a) for a in summary.axes.values()],
            "rrd": str(output.rrd) if output.rrd else None,
        }
        _print(args, data, summary.format())
        _hold(out)
    if output.rrd is not None and not args.json:
        print(f"wrote {output.rrd} (open it with: rerun {output.rrd})", flush=True)
    return 0


def _run_live(args: argparse.Namespace, params: AxisParams) -> int:
    from ..acquisition.bus.session import open_session
    from ..viz.errors import VizError
    from ..viz.live_view import LiveView, check_keys
    from ..viz.outputs import RerunOutput, ViewOutput

    if args.logs:
        raise VizError("--live views the network: give no LOG.mcap with it")
    if args.keys is not None and args.axis:
        raise VizError(f"--keys {args.keys} and --axis {args.axis[0]} both choose the keys: give one")
    keys = check_keys(args.keys or _live_keys(args.axis))
    if args.duration is not None and not args.duration > 0:
        raise VizError(f"--duration {args.duration} s must be > 0 s")
    output = ViewOutput(
        rrd=Path(args.output) if args.output else None,
        spawn=args.spawn,
        serve=args.serve,
        web_port=args.web_port,
        overwrite=args.overwrite,
    )
    with (
        stop_on_signals() as stop,
        open_session(zenoh_options_from_args(args)) as session,
        RerunOutput(output) as out,
    ):
        view = LiveView(out, params, keys)
        if out.web_url:
            print(f"serving the view at {out.web_url}", flush=True)
        report = view.run(session, stop, args.duration, on_ready=notify_ready)
    _print(args, {**report.to_dict(), "rrd": str(output.rrd) if output.rrd else None}, report.format())
    if output.rrd is not None and not args.json:
        print(f"wrote {output.rrd}", flush=True)
    return 0


def _live_keys(axes: list[str]) -> str:
    """The keys of ``--live``: every axis, or the keys of the one ``--axis`` (its label: the axis name
    under the default prefix, or ``<prefix>/<axis>``)."""
    from ..viz.errors import VizError

    if not axes:
        return all_keys()
    if len(axes) > 1:
        raise VizError(f"--live views one --axis or all (--axis {' --axis '.join(axes)}): drop all but one")
    label = axes[0]
    return f"{label}/**" if "/" in label else f"{AxisKeys(label).prefix}/{label}/**"


def _hold(out: RerunOutput) -> None:
    """With a web viewer: keep serving until Ctrl-C (SIGINT/SIGTERM)."""
    if out.web_url:
        print(f"serving the view at {out.web_url} (Ctrl-C to stop)", flush=True)
        with stop_on_signals() as stop:
            while not stop.wait(0.2):
                pass


def _print(args: argparse.Namespace, data: dict, text: str) -> None:
    print(json.dumps(data, indent=1) if args.json else text, flush=True)
