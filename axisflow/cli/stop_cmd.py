"""``axisflow stop``: a quick stop of an axis (abandon its queue, brake to rest, hold)."""

from __future__ import annotations

import argparse
import json
import time
from typing import TYPE_CHECKING

from ..acquisition.wire.keys import DEFAULT_AXIS, DEFAULT_PREFIX, AxisKeys
from ..arguments import finite_float
from ..model import AxisflowError
from .zenoh_options import add_zenoh_options, zenoh_options_from_args

if TYPE_CHECKING:
    from ..acquisition.bus.move_sender import MoveSender
    from ..acquisition.wire.move_status import MoveStatus


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "stop",
        help="quick stop: the bridge abandons its queue and brakes the axis to rest",
        description="Send a quick stop to an axis's bridge (CiA 402 quick-stop semantics): it drops the "
        "moves that have not started and brings the running one to rest as fast as the torque limit "
        "allows, then holds. Prints where the axis stopped, after what distance and time, and the axis's "
        "physical minimum from the same speed. With --reset-fault it also resets the fault of a drive "
        "that stopped following setpoints, so that the bridge accepts moves again. Not a safety function: "
        "see docs/drives.md.",
    )
    p.add_argument("--axis", default=DEFAULT_AXIS, help=f"axis name (default: {DEFAULT_AXIS})")
    p.add_argument("--prefix", default=DEFAULT_PREFIX, help=f"key prefix (default: {DEFAULT_PREFIX})")
    p.add_argument("--reason", default="axisflow stop", help="why (logged by the bridge)")
    p.add_argument(
        "--reset-fault",
        action="store_true",
        help="also reset the drive's fault (CiA 402 fault reset) and enable it again; waits for the drive to "
        "follow setpoints, and fails naming the fault if it does not",
    )
    p.add_argument(
        "--timeout",
        type=finite_float,
        default=10.0,
        metavar="S",
        help="wait for the bridge up to S s (default 10)",
    )
    p.add_argument("--json", action="store_true", help="print the bridge's answer as one JSON object")
    add_zenoh_options(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..acquisition.bus.move_sender import MoveSender
    from ..acquisition.bus.session import open_session
    from ..acquisition.wire.move_status import MoveState
    from ..acquisition.wire.quick_stop import STOP_MOVE_ID

    if not args.timeout > 0:
        raise AxisflowError(f"--timeout {args.timeout:g} s must be > 0 s")
    keys = AxisKeys(args.axis, args.prefix)
    with open_session(zenoh_options_from_args(args)) as session, MoveSender(session, keys) as sender:
        if not sender.wait_for_bridge(args.timeout):
            raise AxisflowError(
                f"no bridge for axis {keys.axis!r} answered within {args.timeout:g} s ({keys.alive})"
            )
        sender.stop(args.reason, reset_fault=args.reset_fault)
        status = sender.wait_status(STOP_MOVE_ID, {MoveState.STOPPED}, args.timeout)
        if status is None:
            raise AxisflowError(
                f"the bridge of axis {keys.axis!r} did not confirm the stop within {args.timeout:g} s"
            )
        reset = _wait_reset(sender, status, args.timeout) if args.reset_fault else None
    if reset is not None and reset.state is not MoveState.ENABLED:
        raise AxisflowError(f"the fault reset of axis {keys.axis!r} failed: {reset.text}")
    if args.json:
        answer = {"tick": status.tick, "start_tick": status.start_tick, "end_tick": status.end_tick}
        answer["text"] = status.text
        if reset is not None:
            answer["reset"] = {"tick": reset.tick, "text": reset.text}
        print(json.dumps(answer))
    else:
        print(status.text)
        if reset is not None:
            print(reset.text)
    return 0


def _wait_reset(sender: MoveSender, stopped: MoveStatus, timeout_s: float) -> MoveStatus:
    """The bridge's answer to the fault reset: the first ENABLED or FAULT status of move 0 for this
    sender after its stop's STOPPED."""
    from ..acquisition.wire.move_status import MoveState
    from ..acquisition.wire.quick_stop import STOP_MOVE_ID

    answers = frozenset({MoveState.ENABLED, MoveState.FAULT, MoveState.COMM_LOST})
    deadline = time.monotonic() + timeout_s
    seen = sender.statuses.index(stopped) + 1
    while True:
        for status in sender.statuses[seen:]:
            if status.move_id == STOP_MOVE_ID and status.state in answers:
                return status
        seen = len(sender.statuses)
        if time.monotonic() > deadline:
            raise AxisflowError(f"the bridge did not answer the fault reset within {timeout_s:g} s")
        if not sender.poll_status():
            time.sleep(0.005)
