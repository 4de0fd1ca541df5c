"""``axisflow excite``: run the identification excitation on an axis through its bridge."""

from __future__ import annotations

import argparse
import json
import sys

from ..acquisition.wire.keys import DEFAULT_AXIS, DEFAULT_PREFIX, AxisKeys
from ..arguments import add_params_option, finite_float, params_from_args
from ..deploy.processes import stop_on_signals
from ..identification.excitation import DEFAULT_DURATION_S, DEFAULT_TORQUE_MARGIN
from .zenoh_options import add_zenoh_options, zenoh_options_from_args


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "excite",
        help="run the identification excitation on an axis (record it, then `axisflow identify`)",
        description="Send the excitation for friction identification to a running bridge: sinusoid "
        "bursts from 0.01 m/s up to most of v_max, slow and fast, each checked against the limits "
        "with a torque margin; waits until they have run. Record the session with `axisflow record` "
        "and refit with `axisflow identify`.",
    )
    p.add_argument("--axis", default=DEFAULT_AXIS, help=f"axis name (default: {DEFAULT_AXIS})")
    p.add_argument("--prefix", default=DEFAULT_PREFIX, help=f"key prefix (default: {DEFAULT_PREFIX})")
    p.add_argument(
        "--duration",
        type=finite_float,
        default=DEFAULT_DURATION_S,
        metavar="S",
        help=f"drive time to aim at [s] (default {DEFAULT_DURATION_S:g}); each burst holds whole periods, "
        "so the run lasts somewhat more or less: --plan-only prints the bursts and the exact time",
    )
    p.add_argument(
        "--center",
        type=finite_float,
        default=None,
        metavar="M",
        help="centre of the bursts [m] (default L/2)",
    )
    p.add_argument(
        "--torque-margin",
        type=finite_float,
        default=DEFAULT_TORQUE_MARGIN,
        metavar="F",
        help="largest nominal motor torque of a burst, as a fraction of tau_max "
        f"(default {DEFAULT_TORQUE_MARGIN:g})",
    )
    p.add_argument("--plan-only", action="store_true", help="print the bursts and exit (no bridge needed)")
    p.add_argument("--json", action="store_true", help="print one JSON object (no progress lines)")
    add_params_option(p)
    add_zenoh_options(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..acquisition.bus.session import open_session
    from ..identification.excitation import design_excitation
    from ..nodes.excite import run_excitation

    params = params_from_args(args)
    plan = design_excitation(params, args.duration, args.center, args.torque_margin)
    keys = AxisKeys(args.axis, args.prefix)
    if args.plan_only:
        if args.json:
            print(json.dumps(plan.to_json(), indent=2))
        else:
            print(f"{len(plan.bursts)} bursts, {plan.duration_s:.1f} s around {plan.center_m:.3f} m:")
            for b in plan.bursts:
                print(
                    f"  {b.speed_m_s:7.3f} m/s  {b.frequency_hz:5.2f} Hz  amplitude "
                    f"{b.amplitude_m * 1e3:7.2f} mm  {b.hold_periods:3d} periods  {b.duration_s:6.2f} s"
                )
        return 0

    def progress(line: str) -> None:
        print(line, file=sys.stderr, flush=True)

    if not args.json:
        print(
            f"excitation: {len(plan.bursts)} bursts, {plan.duration_s:.1f} s of drive time, axis {keys.axis}",
            file=sys.stderr,
            flush=True,
        )
    with stop_on_signals() as stop, open_session(zenoh_options_from_args(args)) as session:
        report = run_excitation(session, keys, params, plan, None if args.json else progress, stop)
    print(
        json.dumps({**report.to_dict(), "plan": plan.to_json()}, indent=2) if args.json else report.format()
    )
    return 0
