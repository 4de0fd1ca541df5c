"""Command-line options and argument types shared by the commands (`axisflow.cli`) and the benchmarks
(`axisflow.benchmarks`): a layer below both, so neither imports the other for them."""

from __future__ import annotations

import argparse
import math
from typing import TYPE_CHECKING

from .acquisition.bus.options import MAX_TCP_PORT

if TYPE_CHECKING:
    from .model import AxisParams


def add_params_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--params",
        metavar="FILE",
        default=None,
        help="axis parameter file (TOML, SI units); default: the packaged estimate",
    )


def params_from_args(args: argparse.Namespace) -> AxisParams:
    from .model import load_params

    return load_params(args.params)


def finite_float(text: str) -> float:
    """argparse type: a finite float (rejects nan/inf with the value named)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"{text!r} is not a finite number")
    return value


def non_negative_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"{value} must be >= 0")
    return value


def positive_int(text: str) -> int:
    value = non_negative_int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value} must be >= 1")
    return value


def cpu_list(text: str) -> tuple[int, ...]:
    """argparse type: comma-separated CPU numbers, each >= 0 (``0,1``)."""
    try:
        cpus = tuple(int(c) for c in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a comma-separated list of CPU numbers") from None
    if min(cpus) < 0:
        raise argparse.ArgumentTypeError(f"CPU numbers {text!r} must be whole numbers >= 0")
    return cpus


def tcp_port(text: str) -> int:
    """argparse type: a TCP port to connect to or listen on, 1…65535."""
    value = positive_int(text)
    if value > MAX_TCP_PORT:
        raise argparse.ArgumentTypeError(f"{value} is not a TCP port (1…{MAX_TCP_PORT})")
    return value


def tcp_port_or_any(text: str) -> int:
    """argparse type: a TCP port to listen on, 0…65535 (0: any free port)."""
    value = non_negative_int(text)
    if value > MAX_TCP_PORT:
        raise argparse.ArgumentTypeError(f"{value} is not a TCP port (0…{MAX_TCP_PORT}; 0 = a free one)")
    return value


SOLVER_HELP = {
    "exact": "exact: the problem's structure solved to machine precision with a certificate",
    "ipopt": "ipopt: CasADi + IPOPT as published, capped at --max-iter iterations (docs/planner.md "
    "compares their times)",
}


def waypoint_count(text: str) -> int:
    """argparse type: a number of way points (at least 2: one move)."""
    value = non_negative_int(text)
    if value < 2:
        raise argparse.ArgumentTypeError(f"{value} way points make no move: at least 2 are needed")
    return value


def add_solver_options(parser: argparse.ArgumentParser, default: str = "exact") -> None:
    """``--solver exact|ipopt`` (default ``exact``, the online planner; the experiment passes
    ``ipopt`` to reproduce the paper) and IPOPT's ``--max-iter``."""
    from .planner import BACKENDS

    parser.add_argument(
        "--solver",
        choices=sorted(BACKENDS),
        default=default,
        help=f"planner back-end (default: {default}); " + "; ".join(SOLVER_HELP.values()),
    )
    parser.add_argument(
        "--max-iter",
        type=positive_int,
        default=10,
        metavar="N",
        help="IPOPT iteration cap (default: 10, as in the paper; ignored by the exact solver)",
    )


def backend_from_args(args: argparse.Namespace):  # noqa: ANN201 - PlannerBackend
    from .planner import make_backend

    if args.solver == "ipopt":
        return make_backend("ipopt", max_iter=args.max_iter)
    return make_backend(args.solver)


def add_waypoint_options(parser: argparse.ArgumentParser) -> None:
    """--seed and --waypoints of the experiment's random way points (uniform in [0, L])."""
    from .experiment.paper import PAPER_WAYPOINTS

    parser.add_argument("--seed", type=non_negative_int, default=0, help="way point seed (default 0)")
    parser.add_argument(
        "--waypoints",
        type=waypoint_count,
        default=PAPER_WAYPOINTS,
        help=f"number of way points (default {PAPER_WAYPOINTS})",
    )
