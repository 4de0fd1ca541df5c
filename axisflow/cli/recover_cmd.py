"""``axisflow recover``: rebuild a complete MCAP file from one cut off by a crash or damaged."""

from __future__ import annotations

import argparse
import sys


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "recover",
        help="rebuild a crashed or damaged recording into a complete MCAP file",
        description="Read FILE up to its last complete chunk, skipping (and naming) every chunk that "
        "cannot be read, and write a complete copy (summary, index, footer) that every MCAP tool "
        "opens. The copy is written beside OUT under a temporary name and renamed when complete: a "
        "failure or a signal leaves nothing. OUT is never FILE (nor a link to it).",
    )
    p.add_argument("file", metavar="FILE.mcap", help="the recording, e.g. one whose recorder was killed")
    p.add_argument("-o", "--output", default=None, metavar="OUT.mcap", help="default: FILE.recovered.mcap")
    p.add_argument("--overwrite", action="store_true", help="replace OUT.mcap if it exists")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..acquisition.logs.recover import recover

    report = recover(args.file, args.output, overwrite=args.overwrite, progress=_show_progress)
    print(report.format())
    return 0


def _show_progress(messages: int) -> None:
    print(f"  {messages} messages copied", file=sys.stderr, flush=True)
