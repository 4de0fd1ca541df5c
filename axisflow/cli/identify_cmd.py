"""``axisflow identify``: refit the friction (and inertia) from recorded logs by SQP."""

from __future__ import annotations

import argparse
import json
from typing import TYPE_CHECKING

from ..acquisition.wire.keys import DEFAULT_PREFIX
from ..arguments import add_params_option, finite_float, non_negative_int, params_from_args
from ..identification.extra_terms import DEFAULT_STROKE_TERMS
from ..identification.fit import PARAMETERS
from ..identification.preparation import PreparationSettings
from ..identification.signals import DEFAULT_JOINT, DEFAULT_TOPIC
from ..model.terms import EXTRA_TERMS, LAW_TERMS, parse_terms
from .column_options import (
    add_column_options,
    column_map_from_args,
    column_options_given,
    csv_options_from_args,
)

if TYPE_CHECKING:
    pass


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "identify",
        help="refit friction (and inertia) from JointState MCAP logs (or CSV, Parquet, MATLAB) by SQP",
        description="Read sensor_msgs/msg/JointState samples of one joint from MCAP logs (ours or any "
        "ROS 2 recording; a log of one JointState topic of one joint needs neither --topic nor --joint), "
        "or from .csv, .tsv, .parquet and .mat files through the importer of `axisflow import` with "
        "the same column options, estimate velocity and acceleration by zero-phase filtering, fit M_eq and "
        "a1…a4 of eq. (1) by CasADi's SQP so that model effort matches the measured one (the terms the "
        "data support: --terms), and write DIR/params.toml (a complete parameter file), DIR/report.json, "
        "DIR/report.md, DIR/fit.png and DIR/effort.parquet (the fit per sample) (together, atomically; "
        "existing ones only with --overwrite). A chunk of a log that cannot be "
        "read is skipped and named; its samples count as missing, never fitted across.",
    )
    p.add_argument(
        "logs",
        nargs="+",
        metavar="LOG",
        help="recordings to fit (e.g. of `axisflow excite`): MCAP, or .csv/.tsv/.parquet/.mat with the "
        "column options below",
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
        f"{DEFAULT_TOPIC} for ours; in others, their only JointState topic)",
    )
    p.add_argument(
        "--prefix", default=None, help=f"key prefix of --axis (default: any; ours is {DEFAULT_PREFIX})"
    )
    p.add_argument(
        "--joint",
        default=None,
        help=f"joint name (default: the topic's only joint, else {DEFAULT_JOINT}: rad, rad/s, N·m; "
        "'carriage': m, m/s, N)",
    )
    p.add_argument(
        "--joint-kind",
        choices=("motor", "carriage"),
        default=None,
        help="what a joint of another name measures: the motor (rad, rad/s, N·m) or the carriage (m, m/s, N)",
    )
    p.add_argument(
        "--terms",
        default="auto",
        metavar="auto|NAMES",
        help="auto (default): choose the terms the data support: candidate structures (the friction "
        "law's offset, asymmetry and atan terms, then the stroke terms) compared on held-out blocks of "
        "the logs and on --validate logs, the simplest within one standard error of the best; cogging "
        "orders (given or found) join the chosen one; a term whose σ exceeds its value is dropped "
        f"(docs/identification.md). Or comma-separated terms to fit, of {', '.join(LAW_TERMS)}, and "
        f"{', '.join(EXTRA_TERMS)} (stroke and cogging as --stroke-terms and --cogging say); f0 (offset) "
        "and da1 (asymmetry) cannot both be fitted: give one of them in --params",
    )
    p.add_argument(
        "--fit",
        default=None,
        metavar="NAMES",
        help=f"comma-separated parameters to fit instead of choosing terms, of {','.join(PARAMETERS)}; a "
        "parameter not fitted keeps the value your --params file gives it, and one your file does not "
        "give is refused (never another axis's nominal)",
    )
    group = p.add_mutually_exclusive_group()
    group.add_argument(
        "--validate", action="append", default=[], metavar="LOG", help="a separate log to validate on"
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
    add_column_options(p, joint=False)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..acquisition.foreign import ForeignLogError, format_of
    from ..acquisition.logs.reader import check_mcap
    from ..experiment.refit_folder import REFIT_FILES
    from ..experiment.refit_logs import ForeignColumns, LogChoice, refit_logs
    from ..identification.extra_terms import extra_terms_from_text
    from ..identification.refit import IdentifySettings
    from ..identification.signals import TimeWindow
    from ..model.files import check_distinct_inputs, check_output_files
    from ..model.params import given_keys

    nominal = params_from_args(args)
    chosen = parse_terms(args.terms, keywords=("auto",))
    terms = None if chosen == "auto" else chosen
    assert not isinstance(terms, str)
    logs = [*args.logs, *args.validate]
    foreign = None
    if any(format_of(log) is not None for log in logs):
        foreign = ForeignColumns(column_map_from_args(args, args.joint), csv_options_from_args(args))
    elif column_options_given(args):
        raise ForeignLogError(
            f"{', '.join(column_options_given(args))} map the columns of .csv, .tsv, .parquet and .mat "
            "logs; these logs are MCAP"
        )
    for log in logs:
        if format_of(log) is None:
            check_mcap(log)
    settings = IdentifySettings(  # the topic and joint once the logs are read
        joint_kind=args.joint_kind,
        fit=None if args.fit is None else tuple(name.strip() for name in args.fit.split(",") if name.strip()),
        terms=terms,
        select=terms is None,
        given=given_keys(args.params),
        preparation=PreparationSettings(cutoff_hz=args.cutoff),
        torque_delay_s=args.torque_delay,
        holdout=args.holdout,
        window=TimeWindow(args.start, args.end),
        extra=extra_terms_from_text(args.stroke_terms, args.cogging, terms),
    )
    check_distinct_inputs(logs, "log")  # the same samples twice would shrink the uncertainty
    # a bad --out fails before the work, not after it
    out = check_output_files(args.out, REFIT_FILES, inputs=logs, overwrite=args.overwrite)
    choice = LogChoice(args.topic, args.axis, args.prefix, args.joint)
    report = refit_logs(out, args.logs, args.validate, nominal, settings, choice, foreign)
    if args.json:
        print(json.dumps(report, indent=1))
    else:
        from ..identification.report import report_markdown

        print(report_markdown(report), end="")
        written = ", ".join(str(out / name) for name in REFIT_FILES[:-1])
        print(f"\nwrote {written} and {out / REFIT_FILES[-1]}")
    return 0
