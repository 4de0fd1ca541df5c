"""Cell: N axes × 1 kHz into one recorder through one Zenoh router, against peer-to-peer in the same run.

For each axis count N of ``--axes`` (ascending), two steps in fresh processes on loopback, their order
alternating from one N to the next:

* **peer-to-peer** (the baseline, what ``axisflow bench pipeline`` measures): the recorder listens, one
  publisher process connects to it as a peer;
* **router**: ``axisflow router`` listens; the recorder and the publisher are its clients (the
  deployment of docs/deployment.md: every sample crosses the router).

The publisher plays N synthetic axes (:mod:`axisflow.benchmarks.toolkit.synthetic_publisher`: N
JointState streams at 1 kHz, pre-encoded, the stamp patched per tick), which loads the recorder and
the router as N drives would. A step passes when every published sample is in the file with no
sequence gap, the recorder keeps up (p99 stamp → write ≤ 100 ms) and the publisher held 1 kHz. Per
step: published, recorded, lost, gaps, the latency from each sample's header stamp (the drive's time)
to the recorder's write (MCAP ``log_time``) p50/p99, and the CPU time of the recorder and the router.
The search stops at the first N where both paths fail (or when ``--budget`` runs out); it reports the
largest N with zero loss for each path and their ratio, and the latencies at the smallest N side by
side.

Then (``--outage-axes``, default 4; 0 skips it) the outages of docs/deployment.md with real bridges
(:mod:`axisflow.benchmarks.cell_outage`): the router restarted, and the router frozen (SIGSTOP).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

from axisflow.arguments import finite_float
from axisflow.deploy.processes import Launcher, free_port

from .pipeline import KEEP_UP_P99_US, analyse_recording, axis_counts, failure
from .toolkit import synthetic_publisher
from .toolkit.proc_stats import cpu_seconds_or_zero

DEFAULT_AXES = "4,8,16,32,48,64,96,128"
PATHS = ("peer-to-peer", "router")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--axes",
        type=axis_counts,
        default=DEFAULT_AXES,
        help=f"axis counts to try, ascending (default {DEFAULT_AXES})",
    )
    parser.add_argument("--seconds", type=finite_float, default=3.0, help="run time per step [s] (default 3)")
    parser.add_argument(
        "--budget", type=finite_float, default=300.0, help="stop the capacity search after [s] (default 300)"
    )
    parser.add_argument(
        "--outage-axes",
        type=int,
        default=4,
        help="bridges of the outage measurements (router restarted, router frozen; default 4, 0 = skip)",
    )


# --------------------------------------------------------------------------- one step


def run_step(tmp: Path, n_axes: int, seconds: float, path: str) -> dict:
    """One recorder and one publisher process (and, on the router path, a router); the step's figures."""
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    out = tmp / f"cell_{path}_{n_axes}_{time.monotonic_ns()}.mcap"
    record = ("record", "-o", str(out), "--json")
    with Launcher(tmp / "logs") as launcher:
        router = None
        if path == "router":
            router = launcher.start("router", "router", "--listen", endpoint, ready=True)
            launcher.wait_ready(router, 60.0)
            rec = launcher.start("recorder", *record, "--mode", "client", "--connect", endpoint, ready=True)
            mode = "client"
        else:
            rec = launcher.start("recorder", *record, "--listen", endpoint, ready=True)
            mode = "peer"
        launcher.wait_ready(rec, 60.0)
        args = synthetic_publisher.arguments(endpoint, n_axes, seconds, mode=mode)
        pub = launcher.start("publisher", *args, entry=synthetic_publisher.ENTRY)
        published = launcher.wait(pub)
        cpu = {
            "recorder_cpu_s": cpu_seconds_or_zero(rec.pid),
            "router_cpu_s": cpu_seconds_or_zero(router.pid) if router else None,
        }
        recorded = launcher.stop(rec, 60.0)  # its stop proves the publisher's last samples arrived
    if published.returncode != 0 or not published.stdout.strip():
        raise RuntimeError(f"publisher ({path}, {n_axes} axes) failed: {published.stderr[-2000:]}")
    p = json.loads(published.stdout.strip().splitlines()[-1])
    if not p["matched"]:
        raise RuntimeError(f"the publisher found no recorder subscribed within 15 s ({path}, {n_axes} axes)")
    summary = json.loads(recorded.stdout) if recorded.stdout.strip() else {}
    a = analyse_recording(out)
    out.unlink(missing_ok=True)
    n_published = p["ticks"] * p["axes"]
    return {
        "axes": n_axes,
        "path": path,
        "published": n_published,
        "recorded": a["recorded"],
        "lost": n_published - a["recorded"],
        "gaps": a["gaps"],
        "recorder_missed": summary.get("missed"),
        "zero_loss": n_published == a["recorded"] and a["gaps"] == 0,
        "keeps_up": a["latency_p99_us"] <= KEEP_UP_P99_US,
        "on_pace": p["wall_s"] <= seconds * 1.05 + 0.05,
        "publisher_wall_s": p["wall_s"],
        "publisher_late_ticks": p["late_ticks"],
        "latency_p50_us": a["latency_p50_us"],
        "latency_p99_us": a["latency_p99_us"],
        **cpu,
    }


# --------------------------------------------------------------------------- the benchmark


def run(args: argparse.Namespace) -> int:
    result: dict[str, object] = {"seconds_per_step": args.seconds, "load_average_at_start": os.getloadavg()}
    steps: list[dict] = []
    failed: set[str] = set()
    result["stopped_by"] = "end of the axis list"
    t_start = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="axisflow-bench-cell-") as tmpdir:
        tmp = Path(tmpdir)
        for i, n in enumerate(args.axes):
            if time.monotonic() - t_start > args.budget:
                result["stopped_by"] = f"time budget ({args.budget:g} s)"
                break
            order = PATHS if i % 2 == 0 else PATHS[::-1]
            for path in order:
                if path in failed:
                    continue
                step = run_step(tmp, n, args.seconds, path)
                steps.append(step)
                why = failure(step)
                _progress(args, f"{n} axes, {path}: {why or 'zero loss'}")
                if why:
                    failed.add(path)
            if failed == set(PATHS):
                result["stopped_by"] = f"{n} axes: both paths failed"
                break
        result["steps"] = steps
        result["max_axes_zero_loss"] = {
            path: max((s["axes"] for s in steps if s["path"] == path and not failure(s)), default=0)
            for path in PATHS
        }
        if args.outage_axes > 0:
            from .cell_outage import measure_outages

            _progress(args, f"outages: {args.outage_axes} bridges, the router restarted, then frozen")
            result["outages"] = measure_outages(tmp, args.outage_axes)
    result["load_average_at_end"] = os.getloadavg()
    if args.json:
        print(json.dumps(result, indent=2))
    else:
        _print_table(result)
    return 0


def _progress(args: argparse.Namespace, text: str) -> None:
    if not args.json:
        print(f"  … {text}", file=sys.stderr, flush=True)


def _print_table(r: dict) -> None:
    load0, load1 = r["load_average_at_start"][0], r["load_average_at_end"][0]
    print(
        f"cell benchmark: N axes × 1 kHz into one recorder, through one router and peer-to-peer "
        f"({r['seconds_per_step']:g} s per step; load average {load0:.1f} at start, {load1:.1f} at end)"
    )
    print(
        f"{'axes':>5} {'path':>13} {'published':>10} {'recorded':>9} {'lost':>6} {'gaps':>5} "
        f"{'lat p50 µs':>10} {'lat p99 µs':>10} {'rec CPU s':>9} {'router CPU s':>12} {'pass':>5}"
    )
    for s in r["steps"]:
        router_cpu = "–" if s["router_cpu_s"] is None else f"{s['router_cpu_s']:.2f}"
        print(
            f"{s['axes']:>5} {s['path']:>13} {s['published']:>10} {s['recorded']:>9} {s['lost']:>6} "
            f"{s['gaps']:>5} {s['latency_p50_us']:>10.0f} {s['latency_p99_us']:>10.0f} "
            f"{s['recorder_cpu_s']:>9.2f} {router_cpu:>12} {'NO' if failure(s) else 'yes':>5}"
        )
    best = r["max_axes_zero_loss"]
    ratio = best["router"] / best["peer-to-peer"] if best["peer-to-peer"] else float("nan")
    print(
        f"largest axis count with zero loss, keeping up (p99 <= {KEEP_UP_P99_US / 1e3:.0f} ms): router "
        f"{best['router']}, peer-to-peer {best['peer-to-peer']} (ratio {ratio:.2f}); search stopped by: "
        f"{r['stopped_by']}"
    )
    both = {}
    for s in r["steps"]:
        both.setdefault(s["axes"], {})[s["path"]] = s
    for n, paths in both.items():
        if len(paths) == 2:
            a, b = paths["router"], paths["peer-to-peer"]
            print(
                f"latency stamp→write at {n} axes: router p50 {a['latency_p50_us']:.0f} µs, p99 "
                f"{a['latency_p99_us']:.0f} µs; peer-to-peer p50 {b['latency_p50_us']:.0f} µs, p99 "
                f"{b['latency_p99_us']:.0f} µs (ratio p50 {a['latency_p50_us'] / b['latency_p50_us']:.2f}, "
                f"p99 {a['latency_p99_us'] / b['latency_p99_us']:.2f})"
            )
            break
    if "outages" in r:
        from .cell_outage import format_outages

        print(format_outages(r["outages"]))
