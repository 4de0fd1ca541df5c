"""``axisflow bridge``: the 1 kHz drive bridge — the simulated axis, or CiA 402 drives over CANopen."""

from __future__ import annotations

import argparse
import json
import os
import sys
from typing import TYPE_CHECKING

from ..acquisition.bridge.continuity import DEFAULT_JUMP_TOLERANCE_M
from ..acquisition.bus.options import DEFAULT_ENDPOINT, ZenohOptions
from ..acquisition.drives.plant_profiles import DEFAULT_PROFILE, PROFILE_RESOURCES
from ..acquisition.wire.keys import DEFAULT_AXIS, DEFAULT_PREFIX
from ..arguments import add_params_option, finite_float, params_from_args
from ..deploy.processes import notify_ready, stop_on_signals
from ..model import EXECUTION_PERIOD_NS, AxisflowError
from ..nodes.drive_kinds import DRIVES
from .timing_options import add_timing_options, timing_from_args
from .zenoh_options import add_zenoh_options, zenoh_options_from_args

if TYPE_CHECKING:
    from ..acquisition.bridge.config import BridgeConfig
    from ..acquisition.bridge.report import BridgeReport
    from ..acquisition.drives.canopen.cycle import CycleReport


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "bridge",
        help="run the 1 kHz drive bridge (simulated axis, or CiA 402 drives over CANopen) over Zenoh",
        description="Publish 1 kHz samples and setpoints of an axis over Zenoh and execute the moves "
        "received on <prefix>/<axis>/trajectory. The drive is the built-in simulated axis (default), the "
        "CiA 402 drive(s) of --drive-config over CANopen (docs/drives.md), or simulated CiA 402 drives "
        "hosted in this process on an in-process CAN bus (--drive canopen-sim). Stops after --duration or "
        "on SIGINT/SIGTERM and prints the period jitter.",
    )
    p.add_argument("--sim", action="store_true", help="drive the built-in simulated axis (the default)")
    p.add_argument(
        "--drive",
        choices=DRIVES,
        default=None,
        help="sim: the built-in simulated axis; canopen: the drives of --drive-config; canopen-sim: "
        "simulated CiA 402 drives in this process on the bus of --drive-config (default: one on python-can's "
        "virtual bus). Default: canopen with --drive-config, else sim",
    )
    p.add_argument(
        "--drive-config",
        metavar="FILE",
        default=None,
        help="drive.toml: the CAN bus and the CiA 402 drives on it (docs/drives.md)",
    )
    p.add_argument(
        "--reset-fault",
        action="store_true",
        help="reset a CANopen drive found in fault at start-up (after removing its cause)",
    )
    p.add_argument("--axis", default=DEFAULT_AXIS, help=f"axis name (default: {DEFAULT_AXIS})")
    p.add_argument("--prefix", default=DEFAULT_PREFIX, help=f"key prefix (default: {DEFAULT_PREFIX})")
    add_params_option(p)
    plant = p.add_mutually_exclusive_group()
    plant.add_argument(
        "--plant",
        metavar="FILE",
        default=None,
        help="plant file of the simulated axis or simulated drives (docs/plant.md; default: the packaged "
        "ideal one)",
    )
    plant.add_argument(
        "--plant-profile",
        choices=list(PROFILE_RESOURCES),
        default=None,
        help=f"a packaged plant profile (default {DEFAULT_PROFILE}): ideal = eq. (1) with white noise; "
        "realistic = drive units, coloured current noise, cogging, belt elasticity, friction along the "
        "stroke, jittered stamps and lost samples; warm-up = realistic with friction that falls as the "
        "axis warms",
    )
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
    add_timing_options(p)
    p.add_argument("--json", action="store_true", help="print the report as one JSON object")
    add_zenoh_options(p)
    p.set_defaults(func=run)


def _drive_kind(args: argparse.Namespace) -> str:
    kind = args.drive or ("canopen" if args.drive_config else "sim")
    if args.sim and kind != "sim":
        raise AxisflowError(f"--sim (the built-in simulated axis) contradicts --drive {kind}")
    if kind == "canopen" and args.drive_config is None:
        raise AxisflowError("--drive canopen needs --drive-config FILE (the CAN bus and its drives)")
    if kind == "sim" and args.drive_config is not None:
        raise AxisflowError("--drive-config is for CANopen drives: drop --drive sim (or --sim)")
    if kind != "sim" and args.plant_state is not None:
        raise AxisflowError(
            "--plant-state keeps the built-in simulated axis's position; a drive keeps its own"
        )
    if kind == "canopen" and (args.plant is not None or args.plant_profile is not None):
        raise AxisflowError(
            "--plant and --plant-profile belong to a simulated drive: use --drive canopen-sim or "
            "axisflow drive-sim"
        )
    if kind == "sim" and args.reset_fault:
        raise AxisflowError("--reset-fault is for CANopen drives; the built-in simulated axis never faults")
    return kind


def run(args: argparse.Namespace) -> int:
    from ..nodes.bridge_stack import BridgeStackSettings, StackHooks, run_bridge_stack

    params = params_from_args(args)
    settings = BridgeStackSettings(
        drive=_drive_kind(args),
        drive_config=args.drive_config,
        reset_fault=args.reset_fault,
        axis=args.axis,
        prefix=args.prefix,
        plant=args.plant,
        plant_profile=args.plant_profile,
        plant_state=args.plant_state,
        speed=args.speed,
        duration_s=args.duration,
        wait_subscribers_s=args.wait_subscribers,
        jump_tolerance_m=args.jump_tolerance,
        timing=timing_from_args(args),
    )
    options = zenoh_options_from_args(args)

    def started(config: BridgeConfig) -> None:
        if not args.json:
            print(startup_line(config, options), file=sys.stderr, flush=True)

    hooks = StackHooks(started, notify_ready, lambda reports, bus: _print_reports(args, reports, bus))
    with stop_on_signals() as stop:
        run_bridge_stack(settings, params, options, stop, hooks)
    return 0


def _print_reports(
    args: argparse.Namespace, reports: dict[str, BridgeReport], bus: CycleReport | None = None
) -> None:
    """One bridge: its report (with ``bus``, the CAN cycle's); several: ``bridges`` by axis and ``bus``."""
    if args.json:
        if len(reports) == 1:
            out = next(iter(reports.values())).to_dict()
        else:
            out = {"bridges": {axis: r.to_dict() for axis, r in reports.items()}}
        if bus is not None:
            out["bus"] = bus.to_dict()
        print(json.dumps(out, indent=2), flush=True)
        return
    for axis, report in reports.items():
        prefix = "" if len(reports) == 1 else f"axis {axis}: "
        print(prefix + report.summary(), flush=True)
    if bus is not None:
        print(bus.summary(), flush=True)


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
        f"{config.drive.describe() if config.drive else 'a drive'}, {rate_hz / 1e3:g} kHz {pace}{duration}; "
        f"stop it with Ctrl-C or kill -TERM {os.getpid()}"
    )
