"""``axisflow adapt``: refit an axis's friction from its live samples while it works (docs/adaptation.md)."""

from __future__ import annotations

import argparse
import json
import sys
import threading

from ..acquisition.wire.keys import DEFAULT_AXIS, DEFAULT_PREFIX
from ..arguments import add_params_option, finite_float
from .zenoh_options import add_zenoh_options, zenoh_options_from_args

DEFAULTS = {"window": 30.0, "holdout": 5.0, "every": 5.0}
"""the command's defaults (the same as AdaptSettings', checked by tests/cli)"""
DEFAULT_TERMS = "M_eq,a2,coulomb"
"""what the paper's axis fits; an axis with an offset or an asymmetry adds them (default_terms)"""


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "adapt",
        help="refit the friction (and M_eq) over a sliding window of live samples; publish accepted sets",
        description="Subscribe to <prefix>/<axis>/state, refit eq. (1)'s friction (and M_eq, when the "
        "motion excites it) over the newest --window seconds of samples every --every seconds of drive "
        "time, and publish each decision on <prefix>/<axis>/params: accepted (a new version, which "
        "`axisflow planner --adapt` plans with) or not, with the reason. An estimate is accepted only "
        "from an informative window, with σ below its bounds, a plausible change, and a lower torque error "
        "than the accepted set on the newest --holdout seconds, which the fit leaves out "
        "(docs/adaptation.md). Prints one line per decision; stops on SIGINT/SIGTERM or after --duration.",
    )
    p.add_argument("--axis", default=DEFAULT_AXIS, help=f"axis name (default: {DEFAULT_AXIS})")
    p.add_argument("--prefix", default=DEFAULT_PREFIX, help=f"key prefix (default: {DEFAULT_PREFIX})")
    p.add_argument(
        "--window",
        type=finite_float,
        default=DEFAULTS["window"],
        metavar="S",
        help=f"drive time of each window, the held-out part included (default {DEFAULTS['window']:g} s)",
    )
    p.add_argument(
        "--holdout",
        type=finite_float,
        default=DEFAULTS["holdout"],
        metavar="S",
        help=f"the newest part of each window, judged and not fitted (default {DEFAULTS['holdout']:g} s)",
    )
    p.add_argument(
        "--every",
        type=finite_float,
        default=DEFAULTS["every"],
        metavar="S",
        help=f"drive time between two fits (default {DEFAULTS['every']:g} s)",
    )
    p.add_argument(
        "--terms",
        default=None,
        metavar="NAMES",
        help=f"what to fit: of M_eq, a1, a2, a3, a4, f0, da1, da2 and coulomb (a1 and a3 scaled together; "
        f"not f0 with da1); default {DEFAULT_TERMS}, and da1,da2 when --params has an asymmetry, else f0 "
        "when it has an offset (the others are carried at their accepted values)",
    )
    p.add_argument(
        "--torque-delay",
        type=finite_float,
        default=None,
        metavar="S",
        help="the torque/position offset [s] (default: estimated on the first windows, then held)",
    )
    p.add_argument("--duration", type=finite_float, default=None, metavar="S", help="stop after S s (wall)")
    p.add_argument("--json", action="store_true", help="print one JSON object at the end (no progress lines)")
    add_params_option(p)
    add_zenoh_options(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    # the fit (scipy, CasADi) and the bus (zenoh): loaded when the command runs
    from ..acquisition.bus.session import open_session
    from ..acquisition.wire.keys import AxisKeys
    from ..acquisition.wire.params_estimate import ParamsEstimate
    from ..arguments import params_from_args
    from ..deploy.processes import notify_ready, stop_on_signals
    from ..identification.errors import IdentificationError
    from ..identification.online import Adapter, AdaptSettings, load_fit_libraries
    from ..nodes.adapt_node import AdaptNode

    if args.duration is not None and not args.duration > 0.0:
        raise IdentificationError(f"--duration {args.duration:g} s must be > 0 s")
    keys = AxisKeys(args.axis, args.prefix)
    params = params_from_args(args)
    settings = AdaptSettings(
        window_s=args.window,
        holdout_s=args.holdout,
        every_s=args.every,
        terms=None if args.terms is None else tuple(args.terms.split(",")),
        torque_delay_s=args.torque_delay,
    )
    adapter = Adapter(keys.axis, params, settings)
    # scipy and CasADi load while the node joins and fills its first window: left to the first step,
    # their import would hold the sample intake for a second or more
    threading.Thread(target=load_fit_libraries, name="load-fit-libraries", daemon=True).start()

    def progress(record: ParamsEstimate) -> None:
        print(f"{args.axis} version {record.version}: {record.reason}", file=sys.stdout, flush=True)

    with stop_on_signals() as stop, open_session(zenoh_options_from_args(args)) as session:
        node = AdaptNode(session, keys, adapter, None if args.json else progress, stop)
        report = node.run(args.duration, on_ready=notify_ready)
    print(json.dumps(report.to_dict(), indent=1) if args.json else report.summary(), flush=True)
    return 0
