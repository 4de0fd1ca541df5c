"""Identify: a one-hour 1 kHz log refit end to end (read + prepare + solve), time and peak memory,
against reading the same log with per-message decoding.

Steps:

1. a synthetic one-hour log (``--hours``) of one axis, ``/axisflow/a0/state`` and ``setpoint``
   interleaved at 1 kHz, 7.2 M messages, measured torque from a "true" axis that differs from the
   nominal one — the true axis of the default (``ideal``) plant file, its ``[scale]`` factors on the
   nominal parameters (acquisition/logs/synthetic_log.py; writing it is not timed; ``--log FILE`` keeps it
   between runs);
2. ``axisflow identify`` on it in a fresh process: its own stage timings (read, prepare, solve,
   total), the process's peak RSS, and how far the refit lands from the true parameters;
3. the baselines, each in another fresh process: reading the same topic with the ``mcap`` library
   alone (``make_reader(f).iter_messages(topics=[topic])``, every message's bytes, no decoding: the
   floor of a per-message reader in Python), and with per-message CDR decoding
   (``read_joint_states(..., per_message=True)``, each payload through :meth:`JointState.decode`), the
   read the refit would need without the vectorised path.

Goals (issue "Identification"): total ≤ 10 s and peak RSS ≤ 1 GB for an hour on the 2-core machine.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from ..arguments import finite_float

GOAL_TOTAL_S = 10.0
GOAL_RSS_MB = 1024.0

_IDENTIFY = """
import json, resource, sys
from axisflow.cli import main
rc = main(["identify", sys.argv[1], "--out", sys.argv[2], "--json"])
peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
sys.stderr.write(json.dumps({"rc": rc, "peak_rss_mb": peak_mb}))
"""
_MCAP_ALONE = """
import json, resource, sys, time
from mcap.reader import make_reader
t0 = time.perf_counter()
n = 0
with open(sys.argv[1], "rb") as fh:
    for _schema, _channel, message in make_reader(fh).iter_messages(topics=[sys.argv[2]]):
        n += len(message.data) > 0
print(json.dumps({"read_s": time.perf_counter() - t0, "rows": n,
                  "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""
_PER_MESSAGE = """
import json, resource, sys, time
from axisflow.acquisition import read_joint_states
t0 = time.perf_counter()
columns = read_joint_states(sys.argv[1], sys.argv[2], per_message=True)
print(json.dumps({"read_s": time.perf_counter() - t0, "rows": len(columns),
                  "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--hours", type=finite_float, default=1.0, help="log length [h] (default 1)")
    parser.add_argument(
        "--log", default=None, metavar="FILE", help="keep the synthetic log here (reused if it exists)"
    )
    parser.add_argument(
        "--no-baseline", action="store_true", help="skip the per-message baseline (the slow part of the run)"
    )


def _say(args: argparse.Namespace, text: str) -> None:
    if not args.json:
        print(f"  … {text}", file=sys.stderr, flush=True)


def _child(code: str, *argv: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code, *argv], capture_output=True, text=True, check=False)


def run(args: argparse.Namespace) -> int:
    from ..acquisition.drives.plant import load_plant
    from ..acquisition.logs.synthetic_log import SyntheticLogSpec, write_synthetic_log
    from ..model import default_params

    nominal = default_params()
    plant = load_plant(None, nominal)  # the default plant file: the one home of its [scale] factors
    true = plant.axis
    spec = SyntheticLogSpec(duration_s=args.hours * 3600.0, params=nominal, true_params=true)
    result: dict[str, object] = {
        "hours": args.hours,
        "goal_total_s": GOAL_TOTAL_S,
        "goal_rss_mb": GOAL_RSS_MB,
        "plant": plant.describe(),
    }
    with tempfile.TemporaryDirectory(prefix="axisflow-bench-identify-") as tmpdir:
        tmp = Path(tmpdir)
        log = Path(args.log) if args.log else tmp / "hour.mcap"
        if not log.exists():
            _say(args, f"writing a synthetic {args.hours:g} h log to {log}")
            t0 = time.perf_counter()
            write_synthetic_log(log, spec)
            result["write_s"] = time.perf_counter() - t0
        result["log_mb"] = log.stat().st_size / 1e6
        _say(args, "identify (fresh process)")
        t0 = time.perf_counter()
        proc = _child(_IDENTIFY, str(log), str(tmp / "refit"))
        process_s = time.perf_counter() - t0
        tail = proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else "{}"
        child = json.loads(tail[tail.index("{") :]) if "{" in tail else {}
        if proc.returncode != 0 or child.get("rc") != 0:
            raise RuntimeError(f"identify failed: {proc.stderr.strip()[-2000:]}")
        report = json.loads(proc.stdout)
        values = {name: p["value"] for name, p in report["parameters"].items()}
        truth = {"M_eq": true.M_eq, "a1": true.a1, "a2": true.a2, "a3": true.a3, "a4": true.a4}
        result["identify"] = {
            **report["timing_s"],
            "process_s": process_s,
            "peak_rss_mb": child["peak_rss_mb"],
            "samples": report["log"]["samples"],
            "fitted_samples": report["samples"]["fitted"],
            "relative_error": {n: values[n] / truth[n] - 1.0 for n in values},
            "fit_rms_nm": report["fit"]["rms_nm"],
        }
        _say(args, "baseline: the mcap library alone, every message of the topic (fresh process)")
        alone = _child(_MCAP_ALONE, str(log), spec.topic("state"))
        if alone.returncode != 0:
            raise RuntimeError(f"mcap baseline failed: {alone.stderr.strip()[-2000:]}")
        result["mcap_alone"] = json.loads(alone.stdout)
        if not args.no_baseline:
            _say(args, "baseline: per-message decoding of the same topic (fresh process)")
            base = _child(_PER_MESSAGE, str(log), spec.topic("state"))
            if base.returncode != 0:
                raise RuntimeError(f"baseline failed: {base.stderr.strip()[-2000:]}")
            result["per_message"] = json.loads(base.stdout)
    ident = result["identify"]
    assert isinstance(ident, dict)
    result["goals_met"] = ident["total"] <= GOAL_TOTAL_S and ident["peak_rss_mb"] <= GOAL_RSS_MB
    if args.json:
        print(json.dumps(result, indent=2))
    else:
        _print_table(result)
    return 0


def _print_table(r: dict) -> None:
    i = r["identify"]
    print(
        f"identify benchmark: a {r['hours']:g} h synthetic 1 kHz log ({i['samples']} samples, "
        f"{r['log_mb']:.0f} MB); true parameters: the plant {r['plant']}"
    )
    alone = r["mcap_alone"]
    print(
        f"baseline, the mcap library alone: every message of the topic read in {alone['read_s']:.2f} s "
        f"(peak RSS {alone['peak_rss_mb']:.0f} MB); identify's read {i['read']:.2f} s: ratio "
        f"{i['read'] / alone['read_s']:.2f}, the whole refit {i['total']:.2f} s: ratio "
        f"{i['total'] / alone['read_s']:.2f}"
    )
    print(f"{'':28} {'seconds':>8} {'per-message':>12} {'ratio':>7}")
    base = r.get("per_message")
    read_base = f"{base['read_s']:>12.2f}" if base else f"{'–':>12}"
    ratio = f"{base['read_s'] / i['read']:>6.1f}×" if base else f"{'':>7}"
    print(f"{'read (one topic)':28} {i['read']:>8.2f} {read_base} {ratio}")
    print(f"{'prepare (filter, masks)':28} {i['prepare']:>8.2f}")
    print(f"{'select (the terms, --terms)':28} {i.get('select', 0.0):>8.2f}")
    print(f"{'solve (offset + SQP)':28} {i['solve']:>8.2f}")
    print(f"{'judge (errors, residuals)':28} {i.get('judge', 0.0):>8.2f}")
    rest = i["prepare"] + i.get("select", 0.0) + i["solve"] + i.get("judge", 0.0)
    total_base = f"{base['read_s'] + rest:>12.2f}" if base else f"{'–':>12}"
    ratio = f"{(base['read_s'] + rest) / i['total']:>6.1f}×" if base else ""
    print(f"{'total':28} {i['total']:>8.2f} {total_base} {ratio}")
    print(
        f"{'the whole command':28} {i['process_s']:>8.2f}   (Python start-up, imports and writing the report "
        "and the per-sample table)"
    )
    rss_base = f"{base['peak_rss_mb']:.0f} MB" if base else "–"
    print(f"peak RSS: identify {i['peak_rss_mb']:.0f} MB (per-message read alone: {rss_base})")
    errors = ", ".join(f"{n} {e * 100:+.2f} %" for n, e in i["relative_error"].items())
    print(f"refit against the true parameters: {errors}; fit RMS {i['fit_rms_nm']:.4f} N·m")
    print(
        f"goals (total <= {r['goal_total_s']:g} s, peak RSS <= {r['goal_rss_mb']:.0f} MB): "
        f"{'met' if r['goals_met'] else 'NOT met'}"
    )
