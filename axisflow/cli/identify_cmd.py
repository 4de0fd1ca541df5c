"""``axisflow identify``: refit the friction (and inertia) from recorded logs by SQP."""

from __future__ import annotations

import argparse
import json

from ..acquisition.wire.keys import DEFAULT_PREFIX
from ..arguments import add_params_option, finite_float, non_negative_int, params_from_args
from ..identification.errors import IdentificationError
from ..identification.extra_terms import DEFAULT_STROKE_TERMS
from ..identification.fit import PARAMETERS
from ..identification.preparation import PreparationSettings
from ..identification.signals import DEFAULT_JOINT, DEFAULT_TOPIC
from ..model.terms import EXTRA_TERMS, LAW_TERMS, parse_terms


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "identify",
        help="refit friction (and inertia) from JointState MCAP logs by SQP",
        description="Read sensor_msgs/msg/JointState samples of one joint from MCAP logs (ours or any "
        "ROS 2 recording), estimate velocity and acceleration by zero-phase filtering, fit M_eq and "
        "a1…a4 of eq. (1) by CasADi's SQP so that model effort matches the measured one, and write "
        "DIR/params.toml (a complete parameter file), DIR/report.json, DIR/report.md and DIR/fit.png "
        "(together, atomically; existing ones only with --overwrite). A chunk of a log that cannot be "
        "read is skipped and named; its samples count as missing, never fitted across.",
    )
    p.add_argument(
        "logs", nargs="+", metavar="LOG.mcap", help="recordings to fit (e.g. of `axisflow excite`)"
    )
    p.add_argument("--out", required=True, metavar="DIR", help="output directory (created if missing)")
    p.add_argument("--overwrite", action="store_true", help="replace the files of an earlier refit in DIR")
    which = p.add_mutually_exclusive_group()
    which.add_argument(
        "--axis",
        default=None,
        help="the axis to fit, in a recording of several (a cell's: a0, a1, …); default: the logs' only "
        "axis (logs of several without --axis are refused with the list of their axes)",
    )
    which.add_argument(
        "--topic",
        default=None,
        help=f"a JointState topic by name, for other recordings (default: the axis's state topic, "
        f"{DEFAULT_TOPIC} for ours)",
    )
    p.add_argument(
        "--prefix", default=None, help=f"key prefix of --axis (default: any; ours is {DEFAULT_PREFIX})"
    )
    p.add_argument(
        "--joint",
        default=DEFAULT_JOINT,
        help=f"joint name (default {DEFAULT_JOINT}: rad, rad/s, N·m; 'carriage': m, m/s, N)",
    )
    p.add_argument(
        "--joint-kind",
        choices=("motor", "carriage"),
        default=None,
        help="what a joint of another name measures: the motor (rad, rad/s, N·m) or the carriage (m, m/s, N)",
    )
    p.add_argument(
        "--fit",
        default=None,
        metavar="NAMES",
        help=f"comma-separated parameters to fit, of {','.join(PARAMETERS)} (default: every parameter of "
        "the terms that are on, and M_eq); a parameter not fitted keeps the value your --params file gives "
        "it, and one your file does not give is refused (never another axis's nominal)",
    )
    p.add_argument(
        "--terms",
        default=None,
        metavar="NAMES",
        help=f"comma-separated terms of the friction law to fit, of {', '.join(LAW_TERMS)}, and "
        f"{', '.join(EXTRA_TERMS)} (default: the terms your parameter file gives, with stroke and cogging "
        "as --stroke-terms and --cogging say); f0 (offset) and da1 (asymmetry) cannot both be fitted: "
        "give one of them in --params",
    )
    group = p.add_mutually_exclusive_group()
    group.add_argument(
        "--validate", action="append", default=[], metavar="LOG.mcap", help="a separate log to validate on"
    )
    group.add_argument(
        "--holdout",
        type=finite_float,
        default=0.0,
        metavar="FRACTION",
        help="validate on the last FRACTION of each log, left out of the fit (e.g. 0.2)",
    )
    p.add_argument(
        "--torque-delay",
        type=finite_float,
        default=None,
        metavar="S",
        help="torque/position time offset [s] (default: estimated from the logs)",
    )
    p.add_argument(
        "--start",
        type=finite_float,
        default=None,
        metavar="S",
        help="fit each log from S seconds after its first sample (default: its start)",
    )
    p.add_argument(
        "--end",
        type=finite_float,
        default=None,
        metavar="S",
        help="fit each log up to S seconds after its first sample (default: its end)",
    )
    p.add_argument(
        "--stroke-terms",
        type=non_negative_int,
        default=DEFAULT_STROKE_TERMS,
        metavar="K",
        help="Legendre terms of the Coulomb friction along the stroke, fitted beside a1…a4 (a1 is then "
        f"their average over the covered stretch; 0: none; default {DEFAULT_STROKE_TERMS})",
    )
    p.add_argument(
        "--cogging",
        default="auto",
        metavar="ORDERS",
        help="cogging orders [cycles per motor revolution] fitted beside a1…a4: comma-separated (e.g. "
        "24,48), 'auto' (default: the orders whose residual peak stands out, found by a first fit) or 'none'",
    )
    p.add_argument(
        "--cutoff",
        type=finite_float,
        default=PreparationSettings.cutoff_hz,
        metavar="HZ",
        help=f"cut-off of the zero-phase low-pass [Hz] (default {PreparationSettings.cutoff_hz:g})",
    )
    p.add_argument("--json", action="store_true", help="print report.json instead of the summary")
    add_params_option(p)
    p.set_defaults(func=run)


def _orders(text: str) -> tuple[int, ...]:
    if text.strip() in ("auto", "none"):
        return ()
    orders = []
    for part in (p.strip() for p in text.split(",")):
        if not part:
            continue
        try:
            orders.append(int(part))
        except ValueError:
            raise IdentificationError(
                f"--cogging {text}: {part!r} is not a whole number of cycles per motor revolution"
            ) from None
    return tuple(orders)


def _state_topic(args: argparse.Namespace, logs: list[str]) -> str:
    """The JointState topic to fit: ``--topic``, else the state topic of ``--axis`` (or of the logs'
    only axis) in every log; logs without any axis of ours keep the default topic, whose reading then
    says what is wrong with them."""
    from ..acquisition.logs.recorded_axes import choose_axis_of_logs, recorded_axes

    if args.topic is not None:
        if args.prefix is not None:
            raise IdentificationError(
                "--prefix goes with --axis, not with --topic (a topic names it already)"
            )
        return args.topic
    if args.axis is None and args.prefix is None and not any(recorded_axes(log) for log in logs):
        return DEFAULT_TOPIC
    state = choose_axis_of_logs(logs, args.axis, args.prefix).state
    assert state is not None  # chosen for its state topic
    return state


def run(args: argparse.Namespace) -> int:
    from ..acquisition.logs.reader import check_mcap
    from ..identification.extra_terms import ExtraTerms
    from ..identification.refit import IdentifySettings
    from ..identification.report import report_markdown
    from ..identification.signals import TimeWindow
    from ..identify import REFIT_FILES, identify_to
    from ..model.files import check_distinct_inputs, check_output_files
    from ..model.params import given_keys

    nominal = params_from_args(args)
    terms = None if args.terms is None else parse_terms(args.terms)
    assert not isinstance(terms, str)  # no keyword is accepted here
    if terms is not None:
        if "stroke" not in terms:
            args.stroke_terms = 0
        if "cogging" not in terms:
            args.cogging = "none"
    logs = [*args.logs, *args.validate]
    for log in logs:
        check_mcap(log)
    settings = IdentifySettings(
        topic=_state_topic(args, logs),
        joint=args.joint,
        joint_kind=args.joint_kind,
        fit=None if args.fit is None else tuple(name.strip() for name in args.fit.split(",") if name.strip()),
        terms=terms,
        given=given_keys(args.params),
        preparation=PreparationSettings(cutoff_hz=args.cutoff),
        torque_delay_s=args.torque_delay,
        holdout=args.holdout,
        window=TimeWindow(args.start, args.end),
        extra=ExtraTerms(
            args.stroke_terms, _orders(args.cogging), auto_cogging=args.cogging.strip() == "auto"
        ),
    )
    check_distinct_inputs(logs, "log")  # the same samples twice would shrink the uncertainty
    # a bad --out fails before the work, not after it
    out = check_output_files(args.out, REFIT_FILES, inputs=logs, overwrite=args.overwrite)
    _ident, report = identify_to(out, args.logs, nominal, settings, validate=args.validate)
    if args.json:
        print(json.dumps(report, indent=1))
    else:
        print(report_markdown(report), end="")
        print(
            f"\nwrote {out / 'params.toml'}, {out / 'report.json'}, {out / 'report.md'} and {out / 'fit.png'}"
        )
    return 0
