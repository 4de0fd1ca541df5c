"""``axisflow bridge --sim``: the 1 kHz drive bridge with the simulated axis."""

from __future__ import annotations

import argparse
import gc
import json
import os
import sys

from ..acquisition.bridge.bridge import Bridge, BridgeConfig
from ..acquisition.bridge.move_queue import DEFAULT_JUMP_TOLERANCE_M
from ..acquisition.bus.session import DEFAULT_ENDPOINT, ZenohOptions, open_session
from ..acquisition.drives.sim_axis import SimulatedAxis, load_plant
from ..acquisition.wire.keys import DEFAULT_AXIS, DEFAULT_PREFIX, AxisKeys
from ..arguments import add_params_option, finite_float, params_from_args
from ..model import EXECUTION_PERIOD_NS
from ..processes import notify_ready, stop_on_signals
from .zenoh_options import add_zenoh_options, zenoh_options_from_args


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "bridge",
        help="run the 1 kHz drive bridge (simulated axis) over Zenoh",
        description="Publish 1 kHz samples and setpoints of an axis over Zenoh and execute the moves "
        "received on <prefix>/<axis>/trajectory. Stops after --duration or on SIGINT/SIGTERM and "
        "prints the period jitter.",
    )
    p.add_argument("--sim", action="store_true", required=True, help="drive the simulated axis (required)")
    p.add_argument("--axis", default=DEFAULT_AXIS, help=f"axis name (default: {DEFAULT_AXIS})")
    p.add_argument("--prefix", default=DEFAULT_PREFIX, help=f"key prefix (default: {DEFAULT_PREFIX})")
    add_params_option(p)
    p.add_argument("--plant", metavar="FILE", default=None, help="plant file (default: the packaged one)")
    p.add_argument(
        "--plant-state",
        metavar="FILE",
        default=None,
        help="keep the simulated axis's position here between runs: a bridge restarted on the same file "
        "starts where the axis came to rest (default: start at the plant's initial position)",
    )
    p.add_argument(
        "--speed",
        type=finite_float,
        default=1.0,
        metavar="X",
        help="X times real time; 0 = as fast as the consumers allow (default: 1)",
    )
    p.add_argument("--duration", type=finite_float, default=None, metavar="S", help="drive time to run [s]")
    p.add_argument(
        "--wait-subscribers",
        type=finite_float,
        default=0.0,
        metavar="S",
        help="wait up to S seconds for a subscriber to the state key before the first tick",
    )
    p.add_argument(
        "--jump-tolerance",
        type=finite_float,
        default=DEFAULT_JUMP_TOLERANCE_M,
        metavar="M",
        help=f"largest accepted start-position mismatch of a move [m] (default {DEFAULT_JUMP_TOLERANCE_M})",
    )
    p.add_argument("--json", action="store_true", help="print the report as one JSON object")
    add_zenoh_options(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    params = params_from_args(args)
    plant = load_plant(args.plant, params)
    config = BridgeConfig(
        keys=AxisKeys(args.axis, args.prefix),
        speed=args.speed,
        duration_s=args.duration,
        wait_subscribers_s=args.wait_subscribers,
        jump_tolerance_m=args.jump_tolerance,
    )
    options = zenoh_options_from_args(args)
    # its clock starts at the first sample
    drive = SimulatedAxis(plant, params, axis=args.axis, state_path=args.plant_state)
    with stop_on_signals() as stop, open_session(options) as session:
        try:
            with Bridge(session, drive, params, config) as bridge:
                if not args.json:
                    print(startup_line(config, options), file=sys.stderr, flush=True)
                notify_ready()
                # what is allocated by now lives as long as the process: out of the collector's way,
                # so a full collection on the 1 kHz loop costs ~0 ms instead of 40–55 ms (measured)
                gc.freeze()
                bridge.run(stop)
        finally:
            drive.close()
        report = bridge.report
        # the report is out before the session closes (a close that hangs must not take it along)
        if args.json:
            print(json.dumps(report.to_dict(), indent=2), flush=True)
        else:
            print(report.summary(), flush=True)
    return 0


def startup_line(config: BridgeConfig, options: ZenohOptions) -> str:
    """What a starting bridge says: the axis, where Zenoh reaches it, the drive, the rate, how to stop."""
    rate_hz = 1e9 / EXECUTION_PERIOD_NS
    pace = (
        "as fast as its consumers allow (none: it waits)"
        if config.speed == 0
        else f"at {config.speed:g}× real time"
    )
    if options.listen:
        where = f"listening on {', '.join(options.listen)}"
    elif options.config_file is not None:
        where = f"Zenoh as configured in {options.config_file}"
    elif options.connect:
        where = f"connected to {', '.join(options.connect)}"
    else:
        where = f"on {DEFAULT_ENDPOINT} (or a port of its own if taken)"
    duration = f" for {config.duration_s:g} s of drive time" if config.duration_s is not None else ""
    return (
        f"axisflow bridge: axis {config.keys.axis} ({config.keys.prefix}/{config.keys.axis}/…) {where}; "
        f"simulated drive, {rate_hz / 1e3:g} kHz {pace}{duration}; "
        f"stop it with Ctrl-C or kill -TERM {os.getpid()}"
    )
