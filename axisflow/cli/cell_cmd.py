"""``axisflow cell up CELL.toml``: start what a machine of a cell runs, from the cell's launch file."""

from __future__ import annotations

import argparse
import signal
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..deploy.cell_file import Process
    from ..deploy.processes import Child, Exited, Launcher


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "cell",
        help="a cell of several axes from its launch file: start what a machine runs (docs/deployment.md)",
        description="A cell's launch file (CELL.toml) names its router and, per machine, what it runs: "
        "the router, a recorder, a bridge per axis (docs/deployment.md). `cell up` starts them.",
    )
    actions = p.add_subparsers(dest="action", metavar="ACTION", required=True)
    up = actions.add_parser(
        "up",
        help="start the processes of one machine of the cell (default: of every machine, on this host)",
        description="Start what the machine runs — the router first, then the recorder, then the bridges — "
        "each an axisflow command of its own whose output goes to --logs; wait until each is ready, and "
        "hold them until Ctrl-C or SIGTERM, which stops them in the reverse order (the recorder finishes "
        "its file). A process that ends on its own ends them all (exit 2, naming it). --print prints the "
        "commands instead.",
    )
    up.add_argument("file", metavar="CELL.toml", help="the cell's launch file")
    up.add_argument("--machine", default=None, metavar="NAME", help="the machine (default: every machine)")
    up.add_argument("--print", action="store_true", help="print the commands, one per line, and exit")
    up.add_argument(
        "--logs",
        default=None,
        metavar="DIR",
        help="the processes' output, NAME.out and NAME.err (default: a new folder under logs/)",
    )
    up.set_defaults(func=run_up)


def run_up(args: argparse.Namespace) -> int:
    from ..deploy.cell import CellError
    from ..deploy.cell_file import load_cell_file
    from ..deploy.processes import READY_TIMEOUT_S, Launcher, notify_ready, stop_on_signals
    from ..model.files import check_output_dir

    cell = load_cell_file(args.file)
    processes = cell.processes(args.machine)
    if args.print:
        for proc in processes:
            print(f"{proc.machine}: {proc.command}")
        return 0
    logs = Path(args.logs) if args.logs else Path("logs") / time.strftime("cell-%Y%m%d-%H%M%S")
    check_output_dir(logs)
    with stop_on_signals() as stop, Launcher(logs) as launcher:
        children: list[tuple[Process, Child]] = []
        for proc in processes:
            child = launcher.start(proc.name, *proc.args, ready=True)
            launcher.wait_ready(child, READY_TIMEOUT_S)
            children.append((proc, child))
            print(f"{proc.name} ({proc.machine}) ready: {proc.command}", file=sys.stderr, flush=True)
        notify_ready()
        print(
            f"cell up: {len(children)} processes; output in {logs}; Ctrl-C stops them",
            file=sys.stderr,
            flush=True,
        )
        while not stop.wait(0.2):
            ended = next((c for _p, c in children if c.poll() is not None), None)
            if ended is not None:
                _stop_in_order(launcher, children)
                raise CellError(
                    f"{ended.command} ended on its own with code {ended.returncode}; the others were stopped "
                    f"(its output: {ended.err_path})"
                )
        ends = _stop_in_order(launcher, children)
    failed = [e for e in ends if e.returncode != 0]
    for end in ends:
        print(f"{end.name}: exit code {end.returncode}", file=sys.stderr)
    return 2 if failed else 0


def _stop_in_order(launcher: Launcher, children: list[tuple[Process, Child]]) -> list[Exited]:
    """SIGINT to the bridges, then the recorders, then the router, each group waited for before the
    next: the recorder hears the bridges' last samples, the router goes last."""
    ends = []
    for command in ("bridge", "record", "router"):
        group = [c for p, c in children if p.args[0] == command]
        for child in group:
            if child.poll() is None:
                child.send_signal(signal.SIGINT)
        ends += [launcher.wait(child) for child in group]
    return ends
