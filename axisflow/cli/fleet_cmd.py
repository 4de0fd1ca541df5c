"""``axisflow fleet index|identify|trend|simulate``: a fleet's logs over months (docs/fleet.md)."""

from __future__ import annotations

import argparse
import json
import logging
import sys
import time

from ..arguments import add_params_option, finite_float, non_negative_int, params_from_args, positive_int
from ..fleet.cluster import CONNECT_TIMEOUT_S, DEFAULT_WORKERS

DASK_LOGGERS = ("distributed", "bokeh", "tornado")
"""Dask's loggers: a cluster's start and stop say a dozen lines at INFO; shown only with -v"""


def _quiet_dask(args: argparse.Namespace) -> None:
    import distributed  # noqa: F401 - its import configures its loggers: quieten them after it

    if not args.verbose:
        for name in DASK_LOGGERS:
            logging.getLogger(name).setLevel(logging.ERROR)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "fleet",
        help="a fleet of axes over months: catalog, identification on Dask, trends, wear alarms",
        description="Index a fleet's MCAP logs into a Parquet catalog, identify every axis per window on "
        "Dask distributed (a LocalCluster on 127.0.0.1, or a running scheduler), trend friction and energy "
        "and raise wear alarms, or simulate a fleet (docs/fleet.md).",
    )
    steps = p.add_subparsers(dest="step", metavar="STEP", required=True)
    _index(steps)
    _identify(steps)
    _trend(steps)
    _simulate(steps)


def _catalog_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--catalog", required=True, metavar="DIR", help="the catalog folder (of `fleet index`)")


def _cluster_options(p: argparse.ArgumentParser) -> None:
    where = p.add_mutually_exclusive_group()
    where.add_argument(
        "--workers",
        type=positive_int,
        default=DEFAULT_WORKERS,
        metavar="N",
        help=f"worker processes of a LocalCluster on 127.0.0.1 (default {DEFAULT_WORKERS})",
    )
    where.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDR",
        help="a running Dask scheduler instead (tcp://host:8786); its workers must see the logs' paths",
    )
    p.add_argument(
        "--connect-timeout",
        type=finite_float,
        default=CONNECT_TIMEOUT_S,
        metavar="S",
        help=f"how long a --scheduler has to answer [s] (default {CONNECT_TIMEOUT_S:g})",
    )
    p.add_argument("--json", action="store_true", help="print the summary as JSON (no progress)")


def _index(steps: argparse._SubParsersAction) -> None:
    p = steps.add_parser(
        "index",
        help="scan MCAP logs into the catalog (incremental)",
        description="Scan MCAP logs (files, or folders searched for *.mcap) and record per file and axis "
        "its time span, samples, holes, the motion that excites friction and a content hash in "
        "DIR/catalog.parquet. A second run reads only new or changed files. A log that cannot be read "
        "is a row with its reason (and a warning); the command fails only when no log could be read.",
    )
    p.add_argument("paths", nargs="+", metavar="PATH", help="MCAP files or folders")
    _catalog_option(p)
    p.add_argument(
        "--axis-pattern",
        default=None,
        metavar="REGEX",
        help="a foreign log's axis from its path: the group 'axis' (else the first group) of REGEX "
        "(default: the name of the folder holding it)",
    )
    p.add_argument(
        "--topic", default=None, help="the JointState topic of foreign logs (default: their first)"
    )
    p.add_argument("--joint", default="motor", help="the joint to read (default motor)")
    p.add_argument(
        "--joint-kind", choices=("motor", "carriage"), default=None, help="what another joint measures"
    )
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    add_params_option(p)
    p.set_defaults(func=run_index)


def _identify(steps: argparse._SubParsersAction) -> None:
    from ..fleet.fits import DEFAULT_HOLDOUT

    p = steps.add_parser(
        "identify",
        help="identify every axis per window on Dask distributed",
        description="Identify every axis of the catalog per window with the code of `axisflow identify`, "
        "a task per window on Dask distributed, into DIR/fits.parquet (one row per axis and window). "
        "Windows already there (same content and settings) are not done again. A window that fails "
        "is a row with its reason; the command fails only when no window could be identified.",
    )
    _catalog_option(p)
    p.add_argument(
        "--window",
        default="day",
        metavar="day|session|SECONDS",
        help="what one identification covers (default day, UTC)",
    )
    p.add_argument(
        "--holdout",
        type=finite_float,
        default=DEFAULT_HOLDOUT,
        metavar="FRACTION",
        help="the last FRACTION of each log kept out of the fit for the held-out error "
        f"(default {DEFAULT_HOLDOUT:g})",
    )
    p.add_argument("--redo", action="store_true", help="identify every window again")
    _cluster_options(p)
    add_params_option(p)
    p.set_defaults(func=run_identify)


def _trend(steps: argparse._SubParsersAction) -> None:
    from ..fleet.trend import DetectorSettings

    d = DetectorSettings()
    p = steps.add_parser(
        "trend",
        help="trends per axis, wear alarms (alarms.json), trend.md with figures and a rerun recording",
        description="Per axis, each parameter over its windows with its σ band; a CUSUM in units of σ "
        "against each axis's first windows on the friction, with the false alarm rate held over the "
        "whole period; DIR/alarms.json, DIR/trend.md with PNG figures and DIR/trend.rrd.",
    )
    _catalog_option(p)
    p.add_argument(
        "--baseline",
        type=positive_int,
        default=d.baseline_windows,
        metavar="N",
        help=f"windows of each axis's baseline (default {d.baseline_windows})",
    )
    p.add_argument(
        "--min-change",
        type=finite_float,
        default=d.min_change_pct,
        metavar="PCT",
        help=f"the smallest change worth an alarm [%%] (default {d.min_change_pct:g})",
    )
    p.add_argument(
        "--false-alarm",
        type=finite_float,
        default=d.false_alarm,
        metavar="P",
        help=f"false alarms expected over the whole period and fleet (default {d.false_alarm:g})",
    )
    p.add_argument("--json", action="store_true", help="print the alarms as JSON")
    p.set_defaults(func=run_trend)


def _simulate(steps: argparse._SubParsersAction) -> None:
    p = steps.add_parser(
        "simulate",
        help="write a simulated fleet's daily logs (not at real time) and truth.json",
        description="Simulate N axes for D days, each axis the realistic plant with its own parameters "
        "drawn around nominal, one log a day; --wear raises an axis's Coulomb friction from a day on. "
        "The logs go to OUT/<axis>/<axis>_<date>.mcap, the truth to OUT/truth.json.",
    )
    p.add_argument("--axes", type=positive_int, default=12, metavar="N", help="axes (default 12)")
    p.add_argument("--days", type=positive_int, default=30, metavar="D", help="days (default 30)")
    p.add_argument("--out", required=True, metavar="DIR", help="output folder")
    p.add_argument(
        "--wear",
        action="append",
        default=[],
        metavar="AXIS:DAY:PERCENT[:RAMP_DAYS]",
        help="Coulomb friction (a1, a3) of AXIS up by PERCENT from DAY (0-based) on, at once or over "
        "RAMP_DAYS (repeatable)",
    )
    p.add_argument(
        "--idle",
        action="append",
        default=[],
        metavar="AXIS:DAY",
        help="AXIS stands still on DAY (repeatable)",
    )
    p.add_argument("--seed", type=non_negative_int, default=0, help="seed of every draw (default 0)")
    p.add_argument("--first-day", default=None, metavar="YYYY-MM-DD", help="the first day (UTC)")
    p.add_argument("--overwrite", action="store_true", help="replace a simulated fleet in DIR")
    _cluster_options(p)
    add_params_option(p)
    p.set_defaults(func=run_simulate)


class _Progress:
    """One progress line on stderr at most once a second (and the last), nothing with --json."""

    def __init__(self, quiet: bool, what: str) -> None:
        self.quiet, self.what = quiet, what
        self._last = 0.0

    def __call__(self, text: str, final: bool) -> None:
        now = time.monotonic()
        if self.quiet or not (final or now - self._last >= 1.0):
            return
        self._last = now
        print(f"axisflow fleet {self.what}: {text}", file=sys.stderr, flush=True)


def run_index(args: argparse.Namespace) -> int:
    from ..fleet.catalog import IndexSettings, index_logs
    from ..fleet.errors import FleetError

    nominal = params_from_args(args)
    settings = IndexSettings(args.axis_pattern, args.topic, args.joint, args.joint_kind)
    show = _Progress(args.json, "index")
    result = index_logs(
        args.paths, args.catalog, nominal, settings, lambda d, n: show(f"{d}/{n} logs read", d == n)
    )
    summary = {
        "catalog": str(result.path),
        "rows": len(result.entries),
        "read": result.read,
        "unchanged": result.unchanged,
        "removed": result.removed,
        "unreadable": result.unreadable,
        "axes": len({e.axis for e in result.entries if e.ok}),
        "wall_s": result.wall_s,
    }
    if args.json:
        print(json.dumps(summary, indent=1))
    else:
        print(
            f"{summary['rows']} rows ({summary['axes']} axes) in {result.path}: {result.read} logs read, "
            f"{result.unchanged} unchanged, {result.removed} removed, {result.unreadable} unreadable, "
            f"in {result.wall_s:.1f} s"
        )
    if not any(e.ok for e in result.entries):
        raise FleetError(f"none of the {len(result.entries)} logs could be indexed (each is named above)")
    return 0


def run_identify(args: argparse.Namespace) -> int:
    _quiet_dask(args)
    from ..fleet.errors import FleetError
    from ..fleet.fits import OK
    from ..fleet.job import identify_fleet
    from ..fleet.window_fit import FitSettings
    from ..fleet.windows import WindowSpec

    windows = WindowSpec.parse(args.window)
    if not (0.0 <= args.holdout < 0.9):
        raise FleetError(f"--holdout {args.holdout} must be a fraction within [0, 0.9)")
    settings = FitSettings(params_from_args(args), holdout=args.holdout)
    show = _Progress(args.json, "identify")
    result = identify_fleet(
        args.catalog,
        windows,
        settings,
        args.workers,
        args.scheduler,
        lambda p: show(p.line(), p.done == p.total),
        args.redo,
        args.connect_timeout,
    )
    counts: dict[str, int] = {}
    for row in result.new:
        counts[row.status] = counts.get(row.status, 0) + 1
    summary = {
        "fits": str(result.path),
        "windows": result.windows,
        "identified_now": len(result.new),
        "kept": result.kept,
        "by_status": counts,
        "wall_s": result.wall_s,
        "peak_rss_mb_per_worker": result.peak_rss_mb,
        "where": args.scheduler or f"LocalCluster of {args.workers} workers on 127.0.0.1",
    }
    if args.json:
        print(json.dumps(summary, indent=1))
    else:
        done = ", ".join(f"{n} {s.replace('_', ' ')}" for s, n in sorted(counts.items())) or "nothing new"
        where = f" on {summary['where']}" if result.new else ""
        rss = max(result.peak_rss_mb.values(), default=0.0)
        memory = f"; peak RSS per worker {rss:.0f} MB" if result.new else ""
        print(
            f"{result.windows} windows: {len(result.new)} identified now ({done}), {result.kept} already in "
            f"{result.path}; {result.wall_s:.1f} s{where}{memory}"
        )
        for row in result.new:
            if row.status == "failed":
                print(f"  failed: {row.axis} window from {row.window_start_ns} ns: {row.reason}")
    if result.new and not any(r.status == OK for r in result.new) and result.kept == 0:
        raise FleetError(f"no window could be identified ({len(result.new)} tried; the reasons are above)")
    return 0


def run_trend(args: argparse.Namespace) -> int:
    from ..fleet.trend import DetectorSettings
    from ..fleet.trend_job import trend_fleet

    settings = DetectorSettings(args.baseline, args.min_change, false_alarm=args.false_alarm)
    result = trend_fleet(args.catalog, settings)
    if args.json:
        print(json.dumps([a.to_json() for a in result.alarms], indent=1))
        return 0
    print(f"{result.axes} axes, {result.windows} windows, {result.watched} watched by the detector")
    for a in result.alarms:
        print(f"ALARM {a.axis} {a.parameter}: {a.change_pct:+.2f} % ± {a.sigma_pct:.2f} % from {a.onset}")
    if not result.alarms:
        print("no alarm")
    print("wrote " + ", ".join(str(p) for p in result.files))
    return 0


def run_simulate(args: argparse.Namespace) -> int:
    _quiet_dask(args)
    from ..fleet.cluster import fleet_client
    from ..fleet.simulate import (
        DEFAULT_FIRST_DAY,
        FleetSpec,
        IdleSpec,
        WearSpec,
        check_simulation_dir,
        simulate_fleet,
    )

    nominal = params_from_args(args)
    spec = FleetSpec(
        axes=args.axes,
        days=args.days,
        seed=args.seed,
        first_day=args.first_day or DEFAULT_FIRST_DAY,
        wear=tuple(WearSpec.parse(w) for w in args.wear),
        idle=tuple(IdleSpec.parse(i) for i in args.idle),
    )
    out = check_simulation_dir(args.out, args.overwrite)
    show = _Progress(args.json, "simulate")
    with fleet_client(args.workers, args.scheduler, args.connect_timeout) as client:
        result = simulate_fleet(
            spec, out, client, nominal, lambda d, n: show(f"{d}/{n} logs written", d == n)
        )
    summary = {
        "out": str(out),
        "logs": len(result.days),
        "axes": spec.axes,
        "days": spec.days,
        "wear": [vars(w) for w in spec.wear],
        "wall_s": result.wall_s,
    }
    if args.json:
        print(json.dumps(summary, indent=1))
    else:
        print(
            f"{len(result.days)} logs of {spec.axes} axes × {spec.days} days in {out} ({result.wall_s:.1f} s)"
        )
    return 0
