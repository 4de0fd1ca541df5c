"""All: the speed benchmarks of issue 23 in one go, one table (Markdown and JSON) with the machine, the
date, the load average around each benchmark, each figure, its baseline measured in the same run and
their ratio (with its spread over rounds where the benchmark runs rounds), and the machine reference
(benchmarks/machine.py): measured here at the start and in each benchmark's own run, every time is
also given as a multiple of the reference of its run.

Each benchmark runs as ``axisflow bench NAME --json`` (or ``axisflow demo``) in a fresh process, one
after the other: ``startup``, ``moves``, ``pipeline`` (the recorder), ``identify`` and the demo.
``--short`` runs smaller versions (fewer way points, a quarter-hour log, shorter recorder steps, no
demo); ``--out DIR`` writes ``performance.md`` and ``performance.json`` there.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from axisflow.benchmarks.machine import machine_reference

_CLI = "import sys; from axisflow.cli import main; sys.exit(main())"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--short", action="store_true", help="smaller runs, no demo (a few minutes)")
    parser.add_argument("--no-demo", action="store_true", help="leave the demo out")
    parser.add_argument("--out", metavar="DIR", default=None, help="write performance.md and .json here")


def _machine() -> dict[str, Any]:
    model = ""
    with contextlib.suppress(OSError, StopIteration):
        model = next(
            line.split(":", 1)[1].strip()
            for line in Path("/proc/cpuinfo").read_text().splitlines()
            if line.startswith("model name")
        )
    return {
        "host": platform.node(),
        "cpus": os.cpu_count(),
        "cpu": model,
        "python": platform.python_version(),
        "system": f"{platform.system()} {platform.release()}",
    }


def _bench(name: str, *args: str) -> dict[str, Any]:
    """``axisflow bench NAME --json ARGS`` in a fresh process: its JSON, with the load around it."""
    load0, t0 = os.getloadavg()[0], time.monotonic()
    proc = subprocess.run(
        [sys.executable, "-c", _CLI, "bench", name, "--json", *args],
        capture_output=True,
        text=True,
        check=False,
    )
    if proc.returncode not in (0, 1):
        raise RuntimeError(f"axisflow bench {name} failed: {proc.stderr[-2000:]}")
    out = json.loads(proc.stdout)
    out["_load"] = (load0, os.getloadavg()[0])
    out["_seconds"] = time.monotonic() - t0
    return out


def _demo(tmp: Path) -> dict[str, Any]:
    load0, t0 = os.getloadavg()[0], time.monotonic()
    out = tmp / "demo"
    proc = subprocess.run(
        [sys.executable, "-c", _CLI, "demo", "--out", str(out)], capture_output=True, text=True, check=False
    )
    wall = time.monotonic() - t0
    if proc.returncode != 0:
        raise RuntimeError(f"axisflow demo failed: {proc.stderr[-2000:]}")
    summary = json.loads((out / "demo.json").read_text())
    summary["_command_s"] = wall
    summary["_load"] = (load0, os.getloadavg()[0])
    return summary


def run(args: argparse.Namespace) -> int:
    from ..model.files import check_output_files, ensure_dir, write_atomic_files

    short = args.short
    if args.out:  # before minutes of benchmarks, not after
        check_output_files(args.out, ("performance.md", "performance.json"), overwrite=True)
    say = (lambda _t: None) if args.json else (lambda t: print(f"  … {t}", file=sys.stderr, flush=True))
    results: dict[str, Any] = {
        "machine": _machine(),
        "date": time.strftime("%Y-%m-%d %H:%M %Z"),
        "short": short,
        "machine_reference": machine_reference().to_dict(),
    }
    say("startup")
    results["startup"] = _bench("startup", "--repeat", "3" if short else "5")
    say("moves (bridge + recorder + planner at --speed 0)")
    results["moves"] = _bench(
        "moves", *(["--waypoints", "20", "--rest-seconds", "20", "--raw-ticks", "30000"] if short else [])
    )
    say("pipeline (the recorder)")
    results["pipeline"] = _bench(
        "pipeline", "--axes", "32", "--seconds", "2" if short else "5", "--memory-seconds",
        "10" if short else "30", "--flood", "100000" if short else "300000",
    )  # fmt: skip
    say("identify")
    results["identify"] = _bench(
        "identify", "--hours", "0.25" if short else "1", *(["--no-baseline"] if short else [])
    )
    if not (short or args.no_demo):
        say("demo")
        with tempfile.TemporaryDirectory(prefix="axisflow-bench-all-") as tmp:
            results["demo"] = _demo(Path(tmp))
    results["rows"] = rows(results)
    markdown = table(results)
    if args.out:
        files = {"performance.md": markdown + "\n", "performance.json": json.dumps(results, indent=1) + "\n"}
        write_atomic_files(ensure_dir(args.out), files)
    if args.json:
        print(json.dumps(results, indent=1))
    else:
        print(markdown)
    return 0


_SECONDS_PER_UNIT = {"s": 1.0, "ms": 1e-3, "µs": 1e-6}
"""the units of the figures that are times"""


def _row(goal: str, figure: str, value: float, unit: str, baseline: str, base: float, **kw: Any) -> dict:
    """One row: ``met`` (True/False, None: no goal), ``load`` (start, end), ``reference`` (the machine
    reference of the run that measured it [s]; a time is then also given as a multiple of it) and
    ``spread`` ((min, max) of the ratio over rounds) as keywords."""
    ratio = value / base if base else None
    reference = kw.get("reference")
    scale = _SECONDS_PER_UNIT.get(unit)
    in_references = value * scale / reference if reference and scale is not None else None
    return {"goal": goal, "figure": figure, "value": value, "unit": unit, "baseline": baseline,
            "baseline_value": base, "ratio": ratio, "ratio_spread": kw.get("spread"), "met": kw.get("met"),
            "load": kw["load"], "reference_s": reference, "in_references": in_references}  # fmt: skip


def _reference_s(result: dict[str, Any]) -> float | None:
    """The machine reference a benchmark measured in its run [s] (None: it has none)."""
    ref = result.get("machine_reference")
    return float(ref["seconds"]) if ref else None


def rows(r: dict[str, Any]) -> list[dict[str, Any]]:
    out = []
    m = r["moves"]
    raw, rest, moves = m["raw_zenoh"], m["bridge_at_rest"], m["during_moves"]
    raw_speed, raw_cpu = "raw zenoh put loop, × real time", "raw zenoh put loop, CPU per tick"
    load, ref = m["_load"], _reference_s(m)
    out.append(_row("1", "pipeline during moves, × real time (≥ 40)", moves["speed"], "×", raw_speed,
                    raw["speed"], met=moves["speed"] >= 40, load=load, reference=ref))  # fmt: skip
    cpu = moves["cpu_us_per_tick"]
    out.append(_row("1", "CPU per tick during moves, all processes (≤ 50)", cpu, "µs", raw_cpu,
                    raw["cpu_us_per_tick"], met=cpu <= 50, load=load, reference=ref))  # fmt: skip
    out.append(_row("1", "bridge at rest + recorder, × real time", rest["speed"], "×", raw_speed,
                    raw["speed"], load=load, reference=ref))  # fmt: skip
    if "demo" in r:
        d = r["demo"]
        wall = d["wall_time_s"]
        ref = r["machine_reference"]["seconds"]  # (the demo's process measures none: this one's)
        out.append(_row("2", "demo wall time (≤ 45)", wall, "s", "goal", 45.0, met=wall <= 45,
                        load=d["_load"], reference=ref))  # fmt: skip
    s = r["startup"]
    out.append(_row("3", "slowest `--help` (≤ 0.3)", s["worst_s"], "s", "python -c 'import numpy'",
                    s["numpy_only_s"], met=s["goal_met"], load=s["_load"],
                    reference=_reference_s(s)))  # fmt: skip
    p = r["pipeline"]
    f = p["recorder_flood"]
    pref = _reference_s(p)
    out.append(_row("4", "recorder flood, msg/s (≥ 0.8 of the baseline)", f["msgs_per_s"], "msg/s",
                    "plain mcap Writer, msg/s", p["baseline_writer_msgs_per_s"],
                    met=f["ratio_to_baseline"] >= 0.8, load=p["_load"], reference=pref,
                    spread=(f["ratio_min"], f["ratio_max"]) if "ratio_min" in f else None))  # fmt: skip
    step = next((st for st in p["steps"] if st["axes"] == 32), None)
    if step is not None:
        p99 = step["latency_p99_us"]
        out.append(_row("4", "stamp→write p99 at 32 axes (≤ 2000)", p99, "µs", "goal", 2000.0,
                        met=p99 <= 2000 and step["zero_loss"], load=p["_load"], reference=pref))  # fmt: skip
    if "memory" in p:
        mem = p["memory"]
        out.append(_row("4", f"recorder RSS trend, {mem['axes']} axes", mem["slope_second_half_mb_per_min"],
                        "MB/min", "peak RSS MB", mem["peak_rss_mb"], load=p["_load"],
                        reference=pref))  # fmt: skip
    i = r["identify"]
    ident, alone = i["identify"], i["mcap_alone"]
    fast = ident["total"] <= 10.0 * i["hours"]
    iref = _reference_s(i)
    out.append(_row("6", f"identify a {i['hours']:g} h log end to end (≤ 10 s/h)", ident["total"], "s",
                    "the mcap library alone reading it, s", alone["read_s"], met=fast,
                    load=i["_load"], reference=iref))  # fmt: skip
    rss = ident["peak_rss_mb"]
    out.append(_row("6", "identify peak RSS (≤ 1024)", rss, "MB", "the mcap library alone, peak RSS MB",
                    alone["peak_rss_mb"], met=rss <= 1024, load=i["_load"], reference=iref))  # fmt: skip
    return out


def table(r: dict[str, Any]) -> str:
    m = r["machine"]
    ref = r["machine_reference"]
    lines = [
        f"Measured {r['date']} on {m['host']} ({m['cpus']} CPUs, {m['cpu']}; Python {m['python']}; "
        f"{m['system']}){' — short version' if r['short'] else ''}.",
        "",
        f"Machine reference (benchmarks/machine.py, a fixed Python and numpy workload, fastest of 3 rounds): "
        f"{ref['seconds'] * 1e3:.0f} ms here at the start (Python {ref['python_s'] * 1e3:.0f} ms + numpy "
        f"{ref['numpy_s'] * 1e3:.0f} ms); each benchmark measures its own, and a time is also given as a "
        "multiple of the reference of its run (× ref).",
        "",
        "| goal | figure | value | × ref | baseline (same run) | baseline value | ratio (rounds) | met | "
        "load (start → end) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for row in r["rows"]:
        ratio = "–" if row["ratio"] is None else f"{row['ratio']:.2f}"
        if row.get("ratio_spread"):
            ratio += f" ({row['ratio_spread'][0]:.2f}–{row['ratio_spread'][1]:.2f})"
        times = "–" if row.get("in_references") is None else f"{row['in_references']:.3g}"
        met = {True: "yes", False: "**no**", None: "–"}[row["met"]]
        lines.append(
            f"| {row['goal']} | {row['figure']} | {row['value']:.3g} {row['unit']} | {times} | "
            f"{row['baseline']} | {row['baseline_value']:.3g} | {ratio} | {met} | "
            f"{row['load'][0]:.1f} → {row['load'][1]:.1f} |"
        )
    if "demo" in r:
        phases = ", ".join(f"{k} {v:.1f} s" for k, v in r["demo"]["phases_s"].items())
        lines += ["", f"Demo phases: {phases}."]
    return "\n".join(lines)
