"""The options of a command that runs a 1 kHz loop: the ticking thread's real-time priority and cores
(acquisition/bridge/tick_clock.py; docs/acquisition.md)."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ..arguments import cpu_list, positive_int

if TYPE_CHECKING:
    from ..acquisition.bridge.tick_clock import TickTiming


def add_timing_options(p: argparse.ArgumentParser) -> None:
    """``--rt-priority P`` and ``--cpus LIST``."""
    p.add_argument(
        "--rt-priority",
        type=positive_int,
        default=None,
        metavar="P",
        help="run the ticking thread as SCHED_FIFO at priority P (1-99): it preempts ordinary processes "
        "at each deadline; needs CAP_SYS_NICE or ulimit -r >= P (docs/acquisition.md)",
    )
    p.add_argument(
        "--cpus",
        type=cpu_list,
        default=None,
        metavar="LIST",
        help="hold the ticking thread to these cores, e.g. 1 or 0,1 (default: any)",
    )


def timing_from_args(args: argparse.Namespace) -> TickTiming:
    """The :class:`~axisflow.acquisition.bridge.tick_clock.TickTiming` of the options."""
    from ..acquisition.bridge.tick_clock import TickTiming

    return TickTiming(args.rt_priority, args.cpus)
