"""``axisflow router``: hold a Zenoh router session (e.g. the secure router of ``security init``).

zenohd is not on PyPI; a Python session in router mode routes, authenticates (TLS, mTLS) and applies
the access-control list of its configuration just as well. Runs until SIGINT/SIGTERM (or --duration).
"""

from __future__ import annotations

import argparse
import time
from typing import TYPE_CHECKING

from ..acquisition.errors import ZenohConfigError
from ..arguments import finite_float
from ..deploy.processes import notify_ready, stop_on_signals
from .zenoh_options import add_zenoh_options, zenoh_options_from_args

if TYPE_CHECKING:
    from ..acquisition.bus.session import ZenohOptions


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "router",
        help="run a Zenoh router (the secure one: --zenoh-config DIR/router.json5)",
        description="Hold a Zenoh session in router mode until SIGINT/SIGTERM or --duration. With the "
        "router.json5 of `axisflow security init` it is the only listener of a secure deployment: it "
        "admits TLS links of its CA's certificates and applies the access-control list.",
    )
    p.add_argument("--duration", type=finite_float, default=None, metavar="S", help="stop after S seconds")
    add_zenoh_options(p)
    p.set_defaults(func=run)


def _router_options(args: argparse.Namespace) -> ZenohOptions:
    from ..acquisition.bus.session import ZenohOptions, build_config

    options = zenoh_options_from_args(args)
    if options.mode not in (None, "router"):
        raise ZenohConfigError(f"axisflow router runs in mode router, not --mode {options.mode}")
    if options.config_file is None and not options.listen:
        raise ZenohConfigError(
            "axisflow router needs --zenoh-config FILE (e.g. DIR/router.json5) or --listen EP"
        )
    if options.config_file is not None and options.mode is None:
        mode = build_config(options).get_json("mode").strip('"')
        if mode != "router":
            raise ZenohConfigError(
                f"zenoh config file {options.config_file} is for mode {mode}, not a router "
                "(the router's file of `axisflow security init` is DIR/router.json5)"
            )
    return ZenohOptions(
        mode="router",
        connect=options.connect,
        listen=options.listen,
        config_file=options.config_file,
        connect_wait_s=options.connect_wait_s,
    )


def run(args: argparse.Namespace) -> int:
    from ..acquisition.bus.session import build_config, open_session

    if args.duration is not None and not args.duration > 0:
        raise ZenohConfigError(f"router duration = {args.duration} s must be > 0 s")
    options = _router_options(args)
    start = time.monotonic()
    config = build_config(options)
    listening = config.get_json("listen/endpoints")
    acl = (
        "on"
        if config.get_json("access_control/enabled") == "true"
        else "OFF (anyone who connects may do anything)"
    )
    with stop_on_signals() as stop, open_session(options) as session:
        print(
            f"router {session.info.zid()} listening on {listening}, access control {acl}; "
            "Ctrl-C or SIGTERM stops it",
            flush=True,
        )
        notify_ready()  # to a launcher (a cell): the router listens
        stop.wait(args.duration)
        links = len(list(session.info.transports()))
    print(
        f"router stopped after {time.monotonic() - start:.1f} s ({links} clients/peers connected at the end)"
    )
    return 0
