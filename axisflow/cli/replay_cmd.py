"""``axisflow replay``: publish a recording back over Zenoh at its recorded pace."""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

from ..arguments import finite_float
from ..deploy.processes import stop_on_signals
from .zenoh_options import add_zenoh_options, zenoh_options_from_args

if TYPE_CHECKING:
    from ..acquisition.logs.replay import ReplayProgress


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "replay",
        help="publish an MCAP recording back over Zenoh",
        description="Publish the messages of FILE on key = topic without the leading '/', at the "
        "recorded pace (the senders' publish times) times --speed. Moves (commands to a drive) are "
        "never replayed. A chunk of FILE that cannot be read is skipped and named; the replay goes on. "
        "Progress goes to stderr.",
    )
    p.add_argument("file", metavar="FILE.mcap", help="recording (complete or truncated)")
    p.add_argument(
        "--speed",
        type=finite_float,
        default=1.0,
        metavar="X",
        help="X times the recorded pace; 0 = as fast as the consumers allow (default: 1)",
    )
    p.add_argument(
        "--wait-subscribers",
        type=finite_float,
        default=5.0,
        metavar="S",
        help="wait up to S seconds for a subscriber before the first message (default 5; messages "
        "published before anyone subscribes are lost)",
    )
    p.add_argument(
        "--no-wait",
        dest="wait_subscribers",
        action="store_const",
        const=0.0,
        help="publish at once, without waiting for a subscriber",
    )
    p.add_argument(
        "--keys",
        default="**",
        metavar="EXPR",
        help="replay only the keys matching this Zenoh key expression (default: all)",
    )
    add_zenoh_options(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..acquisition.bus.session import open_session
    from ..acquisition.logs.replay import replay

    with stop_on_signals() as stop, open_session(zenoh_options_from_args(args)) as session:
        report = replay(
            session, args.file, args.speed, stop, args.wait_subscribers, args.keys, _show_progress
        )
    print(report.format())
    return 0


def _show_progress(progress: ReplayProgress) -> None:
    print(f"  {progress.format()}", file=sys.stderr, flush=True)
