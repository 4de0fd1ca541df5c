"""View: a one-hour 1 kHz log to a rerun .rrd, and the live view's latency and loss at 8 axes,
against ``rerun mcap convert`` of the same log in the same run.

Steps (each command in a fresh process, on this machine's two cores):

1. a synthetic one-hour log of one axis (``/axisflow/a0/state`` and ``setpoint`` interleaved at 1 kHz,
   7.2 M messages; acquisition/logs/synthetic_log.py; writing it is not timed; ``--log FILE`` keeps it);
2. ``axisflow view LOG -o FILE.rrd``: wall time of the whole command (interpreter start-up and imports
   included), peak RSS, .rrd size, rows written (read back with rerun's RrdReader, ``--verify``);
3. the baseline, ``CI=1 rerun mcap convert LOG -o FILE.rrd`` (rerun's own importer, Rust): wall time,
   peak RSS, size; the ratios view / convert;
4. live: ``axisflow view --live -o FILE.rrd`` fed over loopback Zenoh by one publisher process that
   plays N simulated axes (``--axes``, default 8) at 1 kHz in real time, each a state and a setpoint
   JointState per tick (2·N messages per ms); stopped with SIGINT after the publisher: messages
   published, received and missed (sequence gaps), the view's latency from sample stamp to rerun
   (p50/p99/max), and the rows of every axis in the .rrd.

Goals (issue "rerun views"): the hour in ≤ 10 s; live at 8 axes with no loss and p99 latency ≤ 100 ms.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from ..arguments import finite_float
from ..deploy.processes import Launcher, free_port
from .pipeline import axis_counts
from .toolkit import synthetic_publisher
from .toolkit.proc_stats import cpu_seconds

GOAL_HOUR_S = 10.0
GOAL_LIVE_P99_MS = 100.0
GOAL_LIVE_AXES = 8
"""the live goal holds at this many axes; other counts in ``--axes`` are measured, not judged"""
CLI = [sys.executable, "-c", "import sys; from axisflow.cli import main; sys.exit(main())"]


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--hours", type=finite_float, default=1.0, help="log length [h] (default 1)")
    parser.add_argument(
        "--log", default=None, metavar="FILE", help="keep the synthetic log here (reused if it exists)"
    )
    parser.add_argument(
        "--axes",
        type=axis_counts,
        default=[GOAL_LIVE_AXES],
        help=f"axis counts of the live step, comma-separated (default {GOAL_LIVE_AXES})",
    )
    parser.add_argument(
        "--seconds", type=finite_float, default=10.0, help="length of each live step [s] (default 10)"
    )
    parser.add_argument("--no-live", action="store_true", help="skip the live step")
    parser.add_argument("--no-log", action="store_true", help="skip the log steps (1 to 3)")
    parser.add_argument("--no-verify", action="store_true", help="do not read the .rrd files back")


# --------------------------------------------------------------------------- helpers


def _wait4(cmd: list[str], env: dict[str, str] | None = None) -> dict:
    """Run ``cmd``: wall time, its own peak RSS, exit code, output (stdout/stderr to temporary files)."""
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        t0 = time.perf_counter()
        proc = subprocess.Popen(cmd, stdout=out, stderr=err, text=True, env=env)
        _pid, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - t0
        proc.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        return {
            "wall_s": wall,
            "peak_rss_mb": usage.ru_maxrss / 1024,
            "rc": proc.returncode,
            "stdout": out.read(),
            "stderr": err.read(),
        }


def _rrd_rows(path: Path) -> dict[str, int]:
    """Temporal rows per entity of an .rrd (rerun's RrdReader)."""
    from rerun.chunk import RrdReader

    rows: dict[str, int] = {}
    for chunk in RrdReader(path).store().stream():
        if not chunk.is_static:
            rows[chunk.entity_path] = rows.get(chunk.entity_path, 0) + chunk.num_rows
    return rows


def _say(args: argparse.Namespace, text: str) -> None:
    if not args.json:
        print(f"  … {text}", file=sys.stderr, flush=True)


# --------------------------------------------------------------------------- steps


def _log_steps(args: argparse.Namespace, tmp: Path, result: dict) -> None:
    from ..acquisition.logs.synthetic_log import SyntheticLogSpec, write_synthetic_log

    spec = SyntheticLogSpec(duration_s=args.hours * 3600.0)
    log = Path(args.log) if args.log else tmp / "hour.mcap"
    if not log.exists():
        _say(args, f"writing a synthetic {args.hours:g} h log to {log} (not timed)")
        write_synthetic_log(log, spec)
    result["log"] = {"path": str(log), "mb": log.stat().st_size / 1e6, "messages": 2 * spec.ticks}
    _say(args, "axisflow view LOG -o FILE.rrd (fresh process)")
    view_rrd = tmp / "view.rrd"
    view = _wait4([*CLI, "view", str(log), "-o", str(view_rrd), "--json"], {**os.environ, "CI": "1"})
    if view["rc"] != 0:
        raise RuntimeError(f"axisflow view failed: {view['stderr'][-2000:]}")
    _say(args, "baseline: rerun mcap convert LOG -o FILE.rrd (fresh process)")
    base_rrd = tmp / "convert.rrd"
    base = _wait4(
        [sys.executable, "-m", "rerun", "mcap", "convert", str(log), "-o", str(base_rrd)],
        {**os.environ, "CI": "1"},
    )
    if base["rc"] != 0:
        raise RuntimeError(f"rerun mcap convert failed: {base['stderr'][-2000:]}")
    result["view"] = {
        "wall_s": view["wall_s"],
        "peak_rss_mb": view["peak_rss_mb"],
        "rrd_mb": view_rrd.stat().st_size / 1e6,
    }
    result["convert"] = {
        "wall_s": base["wall_s"],
        "peak_rss_mb": base["peak_rss_mb"],
        "rrd_mb": base_rrd.stat().st_size / 1e6,
    }
    result["ratio_view_over_convert"] = {
        "wall": view["wall_s"] / base["wall_s"],
        "peak_rss": view["peak_rss_mb"] / base["peak_rss_mb"],
        "rrd_size": result["view"]["rrd_mb"] / result["convert"]["rrd_mb"],
    }
    if not args.no_verify:
        _say(args, "reading both .rrd files back (RrdReader)")
        rows = _rrd_rows(view_rrd)
        result["view"]["rows_per_signal"] = rows.get("/axes/a0/position/measured", 0)
        result["view"]["signals"] = sum(1 for n in rows.values() if n == spec.ticks)
        base_rows = _rrd_rows(base_rrd)
        result["convert"]["rows_per_signal"] = max(base_rows.values(), default=0)
        result["convert"]["signals"] = sum(1 for n in base_rows.values() if n == spec.ticks)
    view_rrd.unlink(missing_ok=True)
    base_rrd.unlink(missing_ok=True)


def _live_step(args: argparse.Namespace, tmp: Path, n_axes: int) -> dict:
    port = free_port()
    rrd = tmp / f"live_{n_axes}.rrd"
    with Launcher(tmp / "logs") as launcher:
        view = launcher.start(
            "view",
            "view",
            "--live",
            "-o",
            str(rrd),
            "--listen",
            f"tcp/127.0.0.1:{port}",
            "--json",
            ready=True,
        )
        launcher.wait_ready(view, 60.0)  # its subscriber has joined
        pub = launcher.wait(
            launcher.start(
                "publisher",
                *synthetic_publisher.arguments(f"tcp/127.0.0.1:{port}", n_axes, args.seconds, setpoints=True),
                entry=synthetic_publisher.ENTRY,
            ),
            args.seconds + 60,
        )
        if pub.returncode != 0:
            raise RuntimeError(f"the publisher failed: {pub.stderr[-2000:]}")
        cpu_s = cpu_seconds(view.pid)
        viewed = launcher.stop(view, 60.0)  # its stop proves the publisher's last samples arrived
    out, err = viewed.stdout, viewed.stderr
    if viewed.returncode != 0:
        raise RuntimeError(f"the live view failed: {err[-2000:]}")
    published = json.loads(pub.stdout.strip().splitlines()[-1])
    report = json.loads(out)
    step = {
        "axes": n_axes,
        "seconds": args.seconds,
        "published": published["published"],
        "received": report["received"],
        "missed": report["missed"],
        "late_ticks": published["late_ticks"],
        "view_cpu_s": cpu_s,
        "latency_ms": {k: report["latency"][f"{k}_us"] / 1e3 for k in ("p50", "p99", "max")}
        if report["latency"]
        else None,
    }
    if not args.no_verify:
        rows = _rrd_rows(rrd)
        expected = published["ticks"]
        state = [rows.get(f"/axes/bench{i}/position/measured", 0) for i in range(n_axes)]
        setpoint = [rows.get(f"/axes/bench{i}/position/setpoint", 0) for i in range(n_axes)]
        step["rrd_rows_missing"] = int(sum(expected - n for n in state) + sum(expected - n for n in setpoint))
    rrd.unlink(missing_ok=True)
    return step


def run(args: argparse.Namespace) -> int:
    result: dict[str, object] = {
        "hours": args.hours,
        "goal_hour_s": GOAL_HOUR_S,
        "goal_live_p99_ms": GOAL_LIVE_P99_MS,
    }
    with tempfile.TemporaryDirectory(prefix="axisflow-bench-view-") as tmpdir:
        tmp = Path(tmpdir)
        if not args.no_log:
            _log_steps(args, tmp, result)
        if not args.no_live:
            steps = []
            for n in args.axes:
                _say(args, f"live view of {n} axes for {args.seconds:g} s")
                steps.append(_live_step(args, tmp, n))
            result["live"] = steps
    live = result.get("live", [])
    assert isinstance(live, list)
    view = result.get("view")
    hour_ok = view is None or view["wall_s"] / args.hours <= GOAL_HOUR_S  # type: ignore[index]
    result["goals_met"] = hour_ok and all(
        s["missed"] == 0
        and s["received"] == s["published"]
        and s["latency_ms"]
        and s["latency_ms"]["p99"] <= GOAL_LIVE_P99_MS
        and not s.get("rrd_rows_missing")
        for s in live
        if s["axes"] == GOAL_LIVE_AXES
    )
    if args.json:
        print(json.dumps(result, indent=2))
    else:
        _print_table(result)
    return 0


def _print_table(r: dict) -> None:
    if "view" in r:
        _print_log_table(r)
    for step in r.get("live", []):
        _print_live_step(step)
    print(
        f"goals (hour <= {r['goal_hour_s']:g} s; live at {GOAL_LIVE_AXES} axes: no loss, "
        f"p99 <= {r['goal_live_p99_ms']:g} ms): "
        f"{'met' if r['goals_met'] else 'NOT met'}"
    )


def _print_log_table(r: dict) -> None:
    v, c, q = r["view"], r["convert"], r["ratio_view_over_convert"]
    log = r["log"]
    print(
        f"view benchmark: a {r['hours']:g} h synthetic 1 kHz log, 2 topics, {log['messages']} messages, "
        f"{log['mb']:.0f} MB"
    )
    print(f"{'':34} {'axisflow view':>14} {'rerun mcap convert':>19} {'ratio':>7}")
    print(f"{'wall time, whole command [s]':34} {v['wall_s']:>14.2f} {c['wall_s']:>19.2f} {q['wall']:>6.2f}×")
    print(f"{'peak RSS [MB]':34} {v['peak_rss_mb']:>14.0f} {c['peak_rss_mb']:>19.0f} {q['peak_rss']:>6.2f}×")
    print(f"{'.rrd size [MB]':34} {v['rrd_mb']:>14.0f} {c['rrd_mb']:>19.0f} {q['rrd_size']:>6.2f}×")
    if "signals" in v:
        print(f"{'signals with every sample':34} {v['signals']:>14} {c['signals']:>19}")


def _print_live_step(s: dict) -> None:
    lat = s["latency_ms"] or {"p50": float("nan"), "p99": float("nan"), "max": float("nan")}
    print(
        f"live, {s['axes']} axes × 2 topics × 1 kHz for {s['seconds']:g} s: published {s['published']}, "
        f"received {s['received']}, missed {s['missed']}, rows missing in the .rrd "
        f"{s.get('rrd_rows_missing', '–')}; stamp→rerun latency p50 {lat['p50']:.1f} ms, "
        f"p99 {lat['p99']:.1f} ms, max {lat['max']:.1f} ms; the view used {s['view_cpu_s']:.1f} s of CPU "
        f"(publisher late ticks: {s['late_ticks']})"
    )
