"""Fleet: windows identified per second on a LocalCluster of 1 and of 2 workers, memory per worker,
and an unchanged catalog's index + identify against the first run.

Steps:

1. a simulated fleet (``--axes`` × ``--days``, one axis wearing; written on a 2-worker cluster, not
   timed) or ``--fleet DIR`` (a folder of ``axisflow fleet simulate``, reused);
2. ``fleet index`` into a new catalog (timed: the first index);
3. the baseline: the first ``--baseline-windows`` windows identified one after the other in this
   process, no Dask, with their axis's calibration held (seconds per window on one core: the
   machine's reference for the rates below); the calibration of their axis timed beside it (once per
   axis, over its first windows; the rates below include the calibrations);
4. for 1 and then 2 workers: a new LocalCluster on 127.0.0.1, every worker warmed up (one window
   identified on each, so that imports and first calls are not counted), then every window of the
   catalog identified into a fits table of its own: windows per second from the first submit to the
   last row, and each worker's peak RSS before the job (warmed up) and after it;
5. the incremental re-run, as a user runs it: ``fleet index`` again and ``fleet identify`` again on the
   unchanged catalog (the 2-worker fits), each a fresh process, against the first index plus the
   2-worker identify with its cluster's start.

The machine's load (1-minute average) is read before and after.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path

GOAL_RATIO = 1.7
GOAL_INCREMENTAL = 0.05


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--axes", type=int, default=4, help="axes of the simulated fleet (default 4)")
    parser.add_argument("--days", type=int, default=10, help="days of the simulated fleet (default 10)")
    parser.add_argument("--fleet", default=None, metavar="DIR", help="a simulated fleet to use instead")
    parser.add_argument(
        "--baseline-windows", type=int, default=4, metavar="N", help="windows of the serial baseline"
    )
    parser.add_argument(
        "--judge",
        default=None,
        metavar="CATALOG",
        help="instead: judge a catalog's fits and alarms (of `fleet identify` and `fleet trend` on the "
        "fleet of --fleet) against the fleet's truth.json, and time nothing",
    )


def _say(args: argparse.Namespace, text: str) -> None:
    if not args.json:
        print(f"  … {text}", file=sys.stderr, flush=True)


def _peak_rss_mb() -> float:
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _cli(*argv: str) -> tuple[float, dict]:
    """``axisflow ARGV --json`` in a fresh process: (wall time [s], its JSON)."""
    code = "import sys; from axisflow.cli import main; sys.exit(main(sys.argv[1:]))"
    t0 = time.perf_counter()
    proc = subprocess.run(
        [sys.executable, "-c", code, *argv, "--json"], capture_output=True, text=True, check=False
    )
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise RuntimeError(f"axisflow {' '.join(argv)} failed: {proc.stderr.strip()[-2000:]}")
    return wall, json.loads(proc.stdout)


def judge(catalog: Path, fleet: Path) -> dict:
    """The alarms against the truth (the worn axes, onsets within 2 days) and every ok fit's Coulomb
    friction at 0.2 m/s of an axis without wear against the truth of its day over its stretch, in
    units of its σ against the truth (the window's and the axis's systematic σ together); also in
    units of the window's σ alone."""
    from datetime import datetime

    import numpy as np

    from ..fleet.alarms import read_alarms
    from ..fleet.fits import read_fits
    from ..fleet.simulate import read_truth
    from ..fleet.window_fit import COULOMB_SPEED_M_S
    from ..fleet.windows import NS_PER_DAY
    from ..model import forward_friction

    truth = read_truth(fleet / "truth.json")
    alarms = read_alarms(catalog / "alarms.json")
    worn = {a.axis: truth.onset_iso(a) for a in truth.axes if a.wear is not None}
    found = []
    for alarm in alarms:
        onset = datetime.fromisoformat(alarm.onset.replace("Z", "+00:00"))
        true = worn.get(alarm.axis)
        late = (
            (onset - datetime.fromisoformat(true.replace("Z", "+00:00"))).total_seconds() / 86400
            if true
            else None
        )
        found.append(
            {
                "axis": alarm.axis,
                "parameter": alarm.parameter,
                "onset": alarm.onset,
                "true_onset": true,
                "days_off": late,
                "change_pct": alarm.change_pct,
                "sigma_pct": alarm.sigma_pct,
            }
        )
    z, z_window, errors_pct = [], [], []
    for row in read_fits(catalog):
        if not row.ok or truth.axis(row.axis).wear is not None:
            continue
        day = (row.window_start_ns - truth.spec.first_day_ns) // NS_PER_DAY
        params = truth.params_on(row.axis, int(day), (row.stretch_low_m, row.stretch_high_m))
        true_f = float(forward_friction(COULOMB_SPEED_M_S, params))
        z.append((row.coulomb_n - true_f) / row.coulomb_truth_std_n)
        z_window.append((row.coulomb_n - true_f) / row.coulomb_std_n)
        errors_pct.append(100.0 * (row.coulomb_n / true_f - 1.0))
    return {
        "alarms": found,
        "alarm_axes_exactly_the_worn": sorted({a["axis"] for a in found}) == sorted(worn),
        "onsets_within_2_days": all(a["days_off"] is not None and abs(a["days_off"]) <= 2 for a in found),
        "unworn_fits": len(z),
        **coverage(z),
        "window_sigma_only": coverage(z_window),
        "median_error_pct": float(np.median(errors_pct)) if z else math.nan,
        "max_abs_error_pct": max((abs(p) for p in errors_pct), default=math.nan),
    }


def coverage(z: Sequence[float]) -> dict[str, float]:
    """The fractions of errors (in σ units) within 1, 2 and 3 σ, and their median and spread."""
    import numpy as np

    a = np.abs(np.asarray(z, dtype=float))
    n = max(a.size, 1)
    return {
        "within_1_sigma": float(np.sum(a <= 1) / n),
        "within_2_sigma": float(np.sum(a <= 2) / n),
        "within_3_sigma": float(np.sum(a <= 3) / n),
        "median_error_sigma": float(np.median(z)) if a.size else math.nan,
        "sd_error_sigma": float(np.std(z)) if a.size else math.nan,
    }


def _quiet_dask(args: argparse.Namespace) -> None:
    """Dask's loggers say a dozen lines at INFO for each cluster: shown only with -v (as ``fleet``)."""
    import logging

    import distributed  # noqa: F401 - its import configures its loggers: quieten them after it

    if not getattr(args, "verbose", 0):
        for name in ("distributed", "bokeh", "tornado"):
            logging.getLogger(name).setLevel(logging.ERROR)


def run(args: argparse.Namespace) -> int:
    _quiet_dask(args)
    if args.judge is not None:
        if args.fleet is None:
            from ..fleet.errors import FleetValueError

            raise FleetValueError("--judge needs --fleet DIR (the simulated fleet with its truth.json)")
        print(json.dumps(judge(Path(args.judge), Path(args.fleet)), indent=2))
        return 0
    from ..fleet.axis_calibration import calibrate_axis, calibrated_windows
    from ..fleet.catalog import index_logs
    from ..fleet.cluster import fleet_client
    from ..fleet.job import identify_windows
    from ..fleet.simulate import FleetSpec, WearSpec, axis_names, default_nominal, simulate_fleet
    from ..fleet.window_fit import FitSettings, fit_window_row
    from ..fleet.windows import WindowSpec, plan_windows

    nominal = default_nominal()
    settings = FitSettings(nominal)
    result: dict[str, object] = {"load_before": os.getloadavg()[0], "cpus": os.cpu_count()}
    with tempfile.TemporaryDirectory(prefix="axisflow-bench-fleet-") as tmpdir:
        tmp = Path(tmpdir)
        if args.fleet is None:
            logs = tmp / "logs"
            wear = (WearSpec(axis_names(args.axes)[1], args.days // 2, 25),) if args.axes > 1 else ()
            spec = FleetSpec(axes=args.axes, days=args.days, wear=wear)
            _say(args, f"simulating {args.axes} axes × {args.days} days on 2 workers")
            with fleet_client(2) as client:
                fleet = simulate_fleet(spec, logs, client, nominal)
            result["simulate_s"] = fleet.wall_s
        else:
            logs = Path(args.fleet)
        _say(args, "fleet index (first run)")
        t0 = time.perf_counter()
        indexed = index_logs([logs], tmp / "catalog", nominal)
        result["index_s"] = time.perf_counter() - t0
        windows = plan_windows(indexed.entries, WindowSpec.parse("day"), settings.method())
        result["windows"] = len(windows)
        result["logs"] = sum(e.ok for e in indexed.entries)
        _say(args, f"baseline: {args.baseline_windows} windows one after the other in this process")
        fit_window_row(windows[0], settings)  # imports and first calls, not timed
        keyed, plans = calibrated_windows(windows, settings)
        base = keyed[: args.baseline_windows]
        t0 = time.perf_counter()
        axes = sorted({w.axis for w in base} & plans.keys())
        held = {axis: calibrate_axis(plans[axis], settings) for axis in axes}
        result["calibration_s_per_axis"] = (time.perf_counter() - t0) / max(len(axes), 1)
        t0 = time.perf_counter()
        for w in base:
            fit_window_row(w, settings, held.get(w.axis))
        result["serial_s_per_window"] = (time.perf_counter() - t0) / len(base)
        runs = {}
        for workers in (1, 2):
            folder = tmp / f"run{workers}"
            folder.mkdir()
            shutil.copy(tmp / "catalog" / "catalog.parquet", folder / "catalog.parquet")
            _say(args, f"identify on {workers} worker(s): {len(windows)} windows")
            t0 = time.perf_counter()
            with fleet_client(workers) as client:
                started = time.perf_counter() - t0
                warm = client.run(fit_window_row, windows[0], settings)  # every worker, once
                idle = {w: r.peak_rss_mb for w, r in warm.items()}
                job = identify_windows(client, windows, settings, folder)
            statuses: dict[str, int] = {}
            for row in job.new:
                statuses[row.status] = statuses.get(row.status, 0) + 1
            runs[workers] = {
                "cluster_start_s": started,
                "job_s": job.wall_s,
                "windows_per_s": len(job.new) / job.wall_s,
                "peak_rss_mb_warm": sorted(idle.values()),
                "peak_rss_mb_after": sorted(job.peak_rss_mb.values()),
                "statuses": statuses,
            }
        result["runs"] = runs
        result["ratio_2_over_1"] = runs[2]["windows_per_s"] / runs[1]["windows_per_s"]
        _say(
            args,
            "incremental: fleet index and fleet identify again on the unchanged catalog (fresh processes)",
        )
        first_cli_s, _first = _cli("fleet", "identify", "--catalog", str(tmp / "run2"), "--redo")
        index_again_s, index_again = _cli("fleet", "index", str(logs), "--catalog", str(tmp / "run2"))
        identify_again_s, identify_again = _cli("fleet", "identify", "--catalog", str(tmp / "run2"))
        result["incremental"] = {
            "first_index_s": result["index_s"],
            "first_identify_process_s": first_cli_s,
            "index_again_process_s": index_again_s,
            "index_again_read": index_again["read"],
            "identify_again_process_s": identify_again_s,
            "identify_again_new": identify_again["identified_now"],
        }
        first_total = float(result["index_s"]) + first_cli_s  # type: ignore[arg-type]
        result["incremental_ratio"] = (index_again_s + identify_again_s) / first_total
    result["load_after"] = os.getloadavg()[0]
    result["client_peak_rss_mb"] = _peak_rss_mb()
    result["goals_met"] = (
        float(result["ratio_2_over_1"]) >= GOAL_RATIO  # type: ignore[arg-type]
        and float(result["incremental_ratio"]) < GOAL_INCREMENTAL  # type: ignore[arg-type]
    )
    if args.json:
        print(json.dumps(result, indent=2))
    else:
        _print_table(result)
    return 0


def _print_table(r: dict) -> None:
    runs = r["runs"]
    print(
        f"fleet benchmark: {r['logs']} logs, {r['windows']} windows (a day each); {r['cpus']} CPUs, load "
        f"{r['load_before']:.1f} before, {r['load_after']:.1f} after"
    )
    base = r["serial_s_per_window"]
    print(
        f"baseline, one window after the other in one process (no Dask): {base:.2f} s per window, its "
        f"axis's calibration held; the calibration {r['calibration_s_per_axis']:.2f} s per axis"
    )
    print(
        f"{'workers':>8} {'windows/s':>10} {'× serial':>9} {'cluster start':>14} {'job':>8}  "
        "peak RSS per worker"
    )
    for n, run in runs.items():
        rss = ", ".join(
            f"{a:.0f}→{b:.0f}"
            for a, b in zip(run["peak_rss_mb_warm"], run["peak_rss_mb_after"], strict=False)
        )
        print(
            f"{n:>8} {run['windows_per_s']:>10.2f} {run['windows_per_s'] * base:>8.2f}× "
            f"{run['cluster_start_s']:>13.1f}s {run['job_s']:>7.1f}s  {rss} MB (warm → after)"
        )
    print(f"2 workers over 1: {r['ratio_2_over_1']:.2f}× (goal ≥ {GOAL_RATIO})")
    inc = r["incremental"]
    print(
        f"first run: index {inc['first_index_s']:.1f} s + identify {inc['first_identify_process_s']:.1f} s "
        f"(a process); again on the unchanged catalog: index {inc['index_again_process_s']:.1f} s "
        f"({inc['index_again_read']} read) + "
        f"identify {inc['identify_again_process_s']:.1f} s ({inc['identify_again_new']} new): "
        f"{100 * r['incremental_ratio']:.1f} % of the first (goal < {100 * GOAL_INCREMENTAL:.0f} %)"
    )
    print(f"goals: {'met' if r['goals_met'] else 'NOT met'}")
