"""What ``axisflow fleet index|identify|trend|simulate`` run once parsed: one library call each, its
progress on stderr and its summary on stdout (the parser is :mod:`.fleet_cmd`)."""

from __future__ import annotations

import argparse
import json
import logging
import sys
import time

from ..arguments import params_from_args

DASK_LOGGERS = ("distributed", "bokeh", "tornado")
"""Dask's loggers: a cluster's start and stop say a dozen lines at INFO; shown only with -v"""


def _quiet_dask(args: argparse.Namespace) -> None:
    import distributed  # noqa: F401 - its import configures its loggers: quieten them after it

    if not args.verbose:
        for name in DASK_LOGGERS:
            logging.getLogger(name).setLevel(logging.ERROR)


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
