"""``axisflow drive-sim``: simulated CiA 402 drives on a CAN bus, as processes of their own."""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

from ..acquisition.drives.canopen.emergency import DEFAULT_FAULT_CODE, describe_code
from ..arguments import add_params_option, finite_float, params_from_args
from ..deploy.processes import stop_on_signals
from ..model import AxisflowError

if TYPE_CHECKING:
    from ..acquisition.drives.canopen.sim_drive import FaultPlan

IN_PROCESS_INTERFACES = ("virtual",)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "drive-sim",
        help="simulated CiA 402 drives on a CAN bus (for a bridge with --drive-config in another process)",
        description="Run a simulated CiA 402 servo drive for each drive of --drive-config (or the one at "
        "--node) on its CAN bus: SDO server, NMT, heartbeat, emergency messages, PDOs per the master's "
        "mapping, the 402 state machine, cyclic synchronous position around the simulated plant, in encoder "
        "counts and per mille of the rated torque. Until SIGINT/SIGTERM or --duration. Across processes use "
        "socketcan (vcan) or, inside a private network namespace only, udp_multicast (docs/drives.md).",
    )
    p.add_argument(
        "--drive-config", metavar="FILE", required=True, help="drive.toml (the bus and its drives)"
    )
    p.add_argument(
        "--node", type=int, default=None, metavar="ID", help="simulate only the drive at this node id"
    )
    add_params_option(p)
    p.add_argument("--plant", metavar="FILE", default=None, help="plant file (default: the packaged one)")
    p.add_argument(
        "--fault-at",
        metavar="S[:CODE]",
        default=None,
        help=f"raise a fault at S seconds of drive time (0: boot in fault), with the CiA 301 error CODE "
        f"(hex; default {describe_code(DEFAULT_FAULT_CODE)})",
    )
    p.add_argument(
        "--silent-at",
        metavar="S[:D]",
        default=None,
        help="fall silent (transmit nothing) at S seconds of drive time, for D seconds (default: for good)",
    )
    p.add_argument("--duration", type=finite_float, default=None, metavar="S", help="wall time to run [s]")
    p.set_defaults(func=run)


def _seconds(option: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise AxisflowError(f"{option} {text!r}: {text!r} is not a number of seconds") from None
    if not 0.0 <= value < 1e9:
        raise AxisflowError(f"{option} {text!r}: {value:g} s must be >= 0 s")
    return value


def fault_plan(fault_at: str | None, silent_at: str | None) -> FaultPlan:
    """The faults of ``--fault-at S[:CODE]`` and ``--silent-at S[:D]``."""
    from ..acquisition.drives.canopen.sim_drive import FaultPlan

    plan: dict = {}
    if fault_at is not None:
        at, _, code = fault_at.partition(":")
        plan["fault_at_s"] = _seconds("--fault-at", at)
        if code:
            try:
                plan["fault_code"] = int(code, 16)
            except ValueError:
                raise AxisflowError(
                    f"--fault-at {fault_at!r}: error code {code!r} is not hexadecimal"
                ) from None
            if not 0x1000 <= plan["fault_code"] <= 0xFFFF:
                raise AxisflowError(
                    f"--fault-at {fault_at!r}: error code 0x{plan['fault_code']:X} is not a CiA 301 error "
                    "code (0x1000…0xFFFF)"
                )
    if silent_at is not None:
        at, _, duration = silent_at.partition(":")
        plan["silent_at_s"] = _seconds("--silent-at", at)
        if duration:
            plan["silent_for_s"] = _seconds("--silent-at", duration)
    return FaultPlan(**plan)


def run(args: argparse.Namespace) -> int:
    from ..acquisition.drives.canopen.config import load_drive_config
    from ..acquisition.drives.canopen.sim_drive import SimulatedDrive
    from ..acquisition.drives.plant import load_plant

    params = params_from_args(args)
    config = load_drive_config(args.drive_config)
    if config.can.interface in IN_PROCESS_INTERFACES:
        raise AxisflowError(
            f"{config.source}: CAN interface {config.can.interface!r} reaches only its own process; a "
            "drive-sim process would be alone on it: use socketcan (vcan) or udp_multicast, or `axisflow "
            "bridge --drive canopen-sim`, which hosts the simulated drives beside the bridge"
        )
    drives = [d for d in config.drives if args.node is None or d.node_id == args.node]
    if not drives:
        listed = ", ".join(str(d.node_id) for d in config.drives)
        raise AxisflowError(
            f"--node {args.node}: {config.source} has no drive at that node id (it has {listed})"
        )
    plant = load_plant(args.plant, params)
    plan = fault_plan(args.fault_at, args.silent_at)
    sims = [SimulatedDrive(config.can, d, config.cycle_hz, plant, params, plan) for d in drives]
    with stop_on_signals() as stop:
        started = []
        try:
            for sim in sims:
                sim.start()
                started.append(sim)
                print(
                    f"axisflow drive-sim: node {sim.settings.node_id} on {config.can.interface} "
                    f"{config.can.channel}: booted (pre-operational)",
                    file=sys.stderr,
                    flush=True,
                )
            stop.wait(args.duration)
        finally:
            for sim in started:
                sim.close()
    for sim in sims:
        print(
            f"drive-sim node {sim.settings.node_id}: {sim.ticks} ticks run, state {sim.state.value}",
            flush=True,
        )
    return 0
