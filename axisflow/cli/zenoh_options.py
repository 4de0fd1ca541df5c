"""The Zenoh connection flags every networked command takes."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..acquisition.bus.options import DEFAULT_ENDPOINT, MODES, ZenohOptions


def add_zenoh_options(parser: argparse.ArgumentParser) -> None:
    g = parser.add_argument_group(
        "zenoh",
        f"default: peer on loopback, multicast scouting off, listen on or connect to {DEFAULT_ENDPOINT}",
    )
    g.add_argument("--mode", choices=MODES, default=None, help="zenoh mode (default: peer)")
    g.add_argument(
        "--connect", action="append", default=[], metavar="EP", help="endpoint to connect to (repeatable)"
    )
    g.add_argument(
        "--listen", action="append", default=[], metavar="EP", help="endpoint to listen on (repeatable)"
    )
    g.add_argument(
        "--zenoh-config",
        metavar="FILE",
        default=None,
        help="zenoh JSON5 configuration (TLS, authentication, access control); flags override it",
    )


def zenoh_options_from_args(args: argparse.Namespace) -> ZenohOptions:
    return ZenohOptions(
        mode=args.mode,
        connect=tuple(args.connect),
        listen=tuple(args.listen),
        config_file=Path(args.zenoh_config) if args.zenoh_config else None,
    )
