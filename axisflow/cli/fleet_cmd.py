"""``axisflow fleet index|identify|trend|simulate``: a fleet's logs over months (docs/fleet.md)."""

from __future__ import annotations

import argparse

from ..arguments import add_params_option, finite_float, non_negative_int, positive_int
from ..fleet.cluster import CONNECT_TIMEOUT_S, DEFAULT_WORKERS
from .fleet_runs import run_identify, run_index, run_simulate, run_trend


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
        "Every window fits the same terms (those of --params); each axis is first calibrated on its "
        "first 5 windows (torque/position offset, cogging orders: DIR/calibrations.parquet), which all "
        "its windows then hold. Windows already there (same content and settings) are not done again. "
        "A window that fails is a row with its reason; the command fails only when no window could be "
        "identified.",
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
    p.add_argument("--redo", action="store_true", help="calibrate every axis and identify every window again")
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
