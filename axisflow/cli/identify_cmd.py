"""``axisflow identify``: refit the friction (and inertia) from recorded logs by SQP."""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, cast

from ..acquisition.wire.keys import DEFAULT_PREFIX
from ..arguments import add_params_option, finite_float, non_negative_int, params_from_args
from ..identification.errors import IdentificationError
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
    from ..identification.refit import IdentifySettings
    from ..model import AxisParams


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


def _state_topic(args: argparse.Namespace, logs: Sequence[str | Path]) -> str:
    """The JointState topic to fit: ``--topic``, else the state topic of ``--axis`` (or of the logs'
    only axis) in every log; in logs without any axis of ours, their only JointState topic (several
    are refused with their list); logs without any keep the default topic, whose reading then says
    what is wrong with them."""
    from ..acquisition.logs.joint_topics import only_joint_state_topic
    from ..acquisition.logs.recorded_axes import choose_axis_of_logs, recorded_axes

    if args.topic is not None:
        if args.prefix is not None:
            raise IdentificationError(
                "--prefix goes with --axis, not with --topic (a topic names it already)"
            )
        return args.topic
    if args.axis is None and args.prefix is None and not any(recorded_axes(log) for log in logs):
        return only_joint_state_topic(logs) or DEFAULT_TOPIC
    state = choose_axis_of_logs(logs, args.axis, args.prefix).state
    assert state is not None  # chosen for its state topic
    return state


def run(args: argparse.Namespace) -> int:
    from ..acquisition.foreign import ForeignLogError, format_of, import_for_reading
    from ..acquisition.logs.reader import check_mcap
    from ..experiment.refit_folder import REFIT_FILES
    from ..identification.extra_terms import ExtraTerms
    from ..identification.refit import IdentifySettings
    from ..identification.signals import TimeWindow
    from ..model.files import check_distinct_inputs, check_output_files
    from ..model.params import given_keys

    nominal = params_from_args(args)
    chosen = parse_terms(args.terms, keywords=("auto",))
    terms = None if chosen == "auto" else chosen
    assert not isinstance(terms, str)
    if terms is not None:
        if "stroke" not in terms:
            args.stroke_terms = 0
        if "cogging" not in terms:
            args.cogging = "none"
    logs = [*args.logs, *args.validate]
    foreign = [log for log in logs if format_of(log) is not None]
    for log in logs:
        if log not in foreign:
            check_mcap(log)
    if foreign:
        cmap = column_map_from_args(args, args.joint)
    elif column_options_given(args):
        raise ForeignLogError(
            f"{', '.join(column_options_given(args))} map the columns of .csv, .tsv, .parquet and .mat "
            "logs; these logs are MCAP"
        )
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
        extra=ExtraTerms(
            args.stroke_terms, _orders(args.cogging), auto_cogging=args.cogging.strip() == "auto"
        ),
    )
    check_distinct_inputs(logs, "log")  # the same samples twice would shrink the uncertainty
    # a bad --out fails before the work, not after it
    out = check_output_files(args.out, REFIT_FILES, inputs=logs, overwrite=args.overwrite)
    with tempfile.TemporaryDirectory(prefix="axisflow-identify-") as folder:
        imported = {}
        if foreign:
            read = import_for_reading(foreign, cmap, folder, csv=csv_options_from_args(args))
            imported = dict(zip(foreign, read, strict=True))
        fit = [imported.get(log, log) for log in args.logs]
        validate = [imported.get(log, log) for log in args.validate]
        sides = {log.side for log in imported.values()}
        report = _refit(args, settings, nominal, out, fit, validate, sides.pop() if len(sides) == 1 else None)
    if args.json:
        print(json.dumps(report, indent=1))
    else:
        from ..identification.report import report_markdown

        print(report_markdown(report), end="")
        written = ", ".join(str(out / name) for name in REFIT_FILES[:-1])
        print(f"\nwrote {written} and {out / REFIT_FILES[-1]}")
    return 0


def _refit(
    args: argparse.Namespace,
    settings: IdentifySettings,
    nominal: AxisParams,
    out: Path,
    fit: list[str | os.PathLike],
    validate: list[str | os.PathLike],
    imported_side: str | None,
) -> dict:
    """The refit of ``fit`` (validated on ``validate``) written to ``out``; report.json's content. The
    topic and joint are chosen here, from the logs; ``imported_side``: the side of the foreign logs
    among them (the kind of a joint they name otherwise)."""
    from ..acquisition.logs.joint_topics import choose_joint
    from ..experiment.refit_folder import identify_to

    # an ImportedLog is a path-like, not a Path: everything below opens its logs through os.fspath
    # (the temporary MCAP) and names them through str (the file the user gave)
    fit_paths, validate_paths = cast("list[str | Path]", fit), cast("list[str | Path]", validate)
    logs = [*fit_paths, *validate_paths]
    topic = _state_topic(args, logs)
    joint = args.joint if args.joint is not None else choose_joint(logs, topic, DEFAULT_JOINT)
    kind = settings.joint_kind if settings.joint_kind is not None else imported_side
    chosen = dataclasses.replace(settings, topic=topic, joint=joint, joint_kind=kind)
    _ident, report = identify_to(out, fit_paths, nominal, chosen, validate=validate_paths)
    return report
