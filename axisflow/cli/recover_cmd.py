"""``axisflow recover``: rebuild a complete MCAP file from one cut off by a crash."""

from __future__ import annotations

import argparse

from ..acquisition.logs.recover import recover


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "recover",
        help="rebuild a crashed recording into a complete MCAP file",
        description="Read FILE with a streaming reader up to its last complete chunk and write a "
        "complete copy (summary, index, footer) that every MCAP tool opens.",
    )
    p.add_argument("file", metavar="FILE.mcap", help="the recording, e.g. one whose recorder was killed")
    p.add_argument("-o", "--output", default=None, metavar="OUT.mcap", help="default: FILE.recovered.mcap")
    p.add_argument("--overwrite", action="store_true", help="replace OUT.mcap if it exists")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    print(recover(args.file, args.output, overwrite=args.overwrite).format())
    return 0
