"""Pipeline: the most simulated 1 kHz axes whose samples all reach the MCAP file, latency, throughput.

Steps (each in fresh processes on loopback: one recorder ``axisflow record`` and one publisher
process that plays N simulated axes, i.e. N telemetry publishers at 1 kHz with real-time pacing,
JointState payloads pre-encoded and only the stamp patched per tick):

1. baseline: a plain ``mcap.writer.Writer`` (zstd) writing pre-encoded JointState messages as fast as
   it can, in this process (measured in each round of step 3);
2. capacity: N = 8, 16, 32, 48, 64, … axes for ``--seconds`` each, stopping at the first N with a loss
   (or when ``--budget`` runs out): per step, published vs recorded messages, sequence gaps,
   end-to-end latency p50/p99 from sample stamp (header.stamp) to write (MCAP log_time), and the
   recorder's peak RSS;
3. throughput: a flood of messages published as fast as the recorder accepts them (blocking
   congestion control); recorder messages/s next to the baseline's, with their ratio. Beside them, the
   same flood into a bare Python Zenoh subscriber that only takes each sample and its fields: what
   Zenoh delivers to Python on this machine at all, the ceiling of any recorder written in Python.
   ``--flood-rounds`` rounds, each the baseline, the bare subscriber's flood, then the recorder's, so
   all three see the same state of a shared machine; the medians and the ratios' spread are reported;
4. memory: the recorder's RSS sampled over a longer run (``--memory-seconds``, ``--memory-axes``):
   its growth over the second half (after warm-up) and its trend there (MB/min, least squares);
5. idle: the CPU a ready recorder uses while nothing comes (``--idle-seconds``), as a share of a core.
"""

from __future__ import annotations

import argparse
import json
import struct
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from axisflow.model import EXECUTION_RATE_HZ

from axisflow.arguments import finite_float, positive_int
from axisflow.processes import Child, Launcher, cpu_seconds, free_port, thread_cpu_seconds

PUBLISHER_ENTRY = "axisflow.benchmarks.pipeline:publisher_main"
"""the publisher process: ``PORT AXES SECONDS SPEED``"""
PUBLISHER_CONFIRM_S = 30.0
"""how long the publisher waits for its receipts before it closes its session [s]: a recorder that
was starved may need a while to take its backlog, and the tail it has not taken is lost at the close"""
RAW_SUBSCRIBER_ENTRY = "axisflow.benchmarks.pipeline:raw_subscriber_main"
"""the reference subscriber process of the flood: ``PORT MESSAGES``"""
DEFAULT_AXES = "8,16,32,48,64,96,128,192,256"
KEEP_UP_P99_US = 100_000.0
"""a step passes if nothing is lost *and* the recorder keeps up in real time: p99 stamp→write ≤ 100 ms
(a recorder that falls behind still loses nothing while its queue absorbs the backlog, but only for a
while)"""
_STAMP = struct.Struct("<iI")


def axis_counts(text: str) -> list[int]:
    """argparse type: comma-separated axis counts, each ≥ 1."""
    try:
        counts = [int(a) for a in text.split(",") if a.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a comma-separated list of axis counts") from None
    if not counts or min(counts) < 1:
        raise argparse.ArgumentTypeError(f"axis counts {text!r} must be whole numbers >= 1")
    return counts


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--axes",
        type=axis_counts,
        default=DEFAULT_AXES,
        help=f"axis counts to try, ascending (default {DEFAULT_AXES})",
    )
    parser.add_argument(
        "--seconds", type=finite_float, default=3.0, help="run time per axis count [s] (default 3)"
    )
    parser.add_argument(
        "--budget", type=finite_float, default=60.0, help="stop the capacity search after [s] (default 60)"
    )
    parser.add_argument(
        "--flood",
        type=positive_int,
        default=200_000,
        help="messages in the throughput flood (default 200000)",
    )
    parser.add_argument(
        "--flood-rounds",
        type=positive_int,
        default=5,
        help="rounds of baseline + flood; their medians are reported (default 5)",
    )
    parser.add_argument(
        "--memory-seconds",
        type=finite_float,
        default=30.0,
        help="length of the memory run [s] (default 30; 0 = skip)",
    )
    parser.add_argument("--memory-axes", type=int, default=16, help="axes in the memory run (default 16)")
    parser.add_argument(
        "--idle-seconds",
        type=finite_float,
        default=10.0,
        help="how long to watch an idle recorder's CPU [s] (default 10; 0 = skip)",
    )


# --------------------------------------------------------------------------- publisher process


def payload_template(axis: str) -> bytearray:
    from axisflow.acquisition import AxisSample

    return bytearray(AxisSample(0, axis, 0.4, 0.1, 12.0, 133.0, 33.0, 0.05).encode())


def play(pubs: list, templates: list[bytearray], n_ticks: int, paced: bool) -> tuple[float, int]:
    """Publish ``templates[i]`` on ``pubs[i]`` every tick, each stamped with the wall clock (only the
    stamp patched into the pre-encoded JointState); at 1 kHz if ``paced``, else as fast as possible.
    Returns the wall time [s] and the ticks started more than 2 ms late."""
    late = 0
    t0 = time.monotonic_ns()
    for k in range(n_ticks):
        if paced:
            deadline = t0 + k * 1_000_000
            now = time.monotonic_ns()
            if deadline > now:
                time.sleep((deadline - now) * 1e-9)
            elif now - deadline > 2_000_000:
                late += 1
        stamp = time.time_ns()
        sec_ns = divmod(stamp, 1_000_000_000)
        for pub, buf in zip(pubs, templates, strict=True):
            _STAMP.pack_into(buf, 4, *sec_ns)
            pub.put(bytes(buf), stamp)
    return (time.monotonic_ns() - t0) * 1e-9, late


def publisher_main() -> None:
    """Entry of the publisher process: ``PORT AXES SECONDS SPEED``; prints one JSON line. Says it is done
    putting (the launcher's ready byte, when started with ``ready=True``), then waits for the receipts
    of the joined subscribers, which learn its last sequence numbers from them."""
    from axisflow.acquisition import AxisKeys, ZenohOptions, open_session
    from axisflow.acquisition.bus.publisher import (
        SequencedPublisher,
        Traffic,
        confirm_delivered,
        wait_for_subscribers,
    )

    from axisflow.processes import notify_ready

    port, n_axes, seconds, speed = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
    traffic = Traffic.TELEMETRY if speed > 0 else Traffic.BULK
    with open_session(ZenohOptions.loopback(connect_port=port)) as session:
        pubs = [
            SequencedPublisher(session, AxisKeys(f"bench{i}").state, "sensor_msgs/msg/JointState", traffic)
            for i in range(n_axes)
        ]
        templates = [payload_template(f"bench{i}") for i in range(n_axes)]
        matched = wait_for_subscribers(pubs, 15.0)
        n_ticks = round(seconds * EXECUTION_RATE_HZ)
        cpu0 = time.process_time()
        wall, late = play(pubs, templates, n_ticks, paced=speed > 0)
        cpu_s = time.process_time() - cpu0
        notify_ready()
        confirmed = confirm_delivered(session, pubs, PUBLISHER_CONFIRM_S)
        for pub in pubs:
            pub.undeclare()
    print(
        json.dumps(
            {
                "matched": matched,
                "ticks": n_ticks,
                "axes": n_axes,
                "wall_s": wall,
                "late_ticks": late,
                "cpu_s": cpu_s,
                "confirmed": confirmed,
            }
        )
    )


def raw_subscriber_main() -> None:
    """Entry of the reference subscriber: ``PORT MESSAGES``. Listens on PORT, takes samples (key,
    attachment and payload bytes of each, nothing written) until MESSAGES have come or none has for
    2 s, prints one JSON line: how many, their rate from the first to the last, and how many each
    key's first sample says it missed before it (it starts at once, without the recorder's join)."""
    import zenoh
    from axisflow.acquisition import ZenohOptions, open_session
    from axisflow.acquisition.logs.recorder_config import DEFAULT_QUEUE_CAPACITY
    from axisflow.acquisition.wire.attachment import unpack_attachment
    from axisflow.acquisition.wire.keys import all_keys

    from axisflow.processes import notify_ready

    port, n = int(sys.argv[1]), int(sys.argv[2])
    with open_session(ZenohOptions.loopback(listen_port=port)) as session:
        sub = session.declare_subscriber(all_keys(), zenoh.handlers.FifoChannel(DEFAULT_QUEUE_CAPACITY))
        notify_ready()
        recv, taken, first, last = sub.try_recv, 0, 0, time.perf_counter_ns()
        first_sequence: dict[str, int] = {}
        while taken < n:
            sample = recv()
            if sample is None:
                if taken and time.perf_counter_ns() - last > 2_000_000_000:
                    break  # the publisher is done: some were lost
                time.sleep(0.0005)  # (a flood seldom leaves the channel empty)
                continue
            last = time.perf_counter_ns()
            if not taken:
                first = last
            key, attachment = str(sample.key_expr), sample.attachment.to_bytes()
            sample.payload.to_bytes()
            if key not in first_sequence:
                first_sequence[key] = (unpack_attachment(attachment) or (1,))[0]
            taken += 1
        span_s = (last - first) * 1e-9
        sub.undeclare()
    missed_at_start = sum(seq - 1 for seq in first_sequence.values())
    print(json.dumps({"messages": taken, "msgs_per_s": taken / span_s if span_s > 0 else 0.0,
                      "missed_at_start": missed_at_start}))  # fmt: skip


def _raw_flood(tmp: Path, n_keys: int, n: int) -> tuple[float, int, int]:
    """The bare subscriber taking a flood of ``n`` messages on ``n_keys`` keys: messages/s, how many it
    did not get, and how many of those before its first sample of each key."""
    port = free_port()
    with Launcher(tmp / "logs") as launcher:
        sub = launcher.start("bare-subscriber", str(port), str(n), entry=RAW_SUBSCRIBER_ENTRY, ready=True)
        launcher.wait_ready(sub, 60.0)
        pub = launcher.start("publisher", str(port), str(n_keys), str(n / n_keys / EXECUTION_RATE_HZ), "0",
                             entry=PUBLISHER_ENTRY)  # fmt: skip
        published = launcher.wait(pub, 60.0)
        taken = launcher.wait(sub, 60.0)
    if published.returncode != 0 or taken.returncode != 0 or not taken.stdout.strip():
        raise RuntimeError(
            f"bare-subscriber flood failed (publisher exit {published.returncode}, subscriber exit "
            f"{taken.returncode}): {published.stderr[-1000:]} {taken.stderr[-1000:]}"
        )
    result = json.loads(taken.stdout.strip().splitlines()[-1])
    return float(result["msgs_per_s"]), n - int(result["messages"]), int(result["missed_at_start"])


# --------------------------------------------------------------------------- helpers


def rss_kb(pid: int, field: str = "VmRSS") -> int:
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith(field + ":"):
                return int(line.split()[1])
    except OSError:
        pass
    return 0


def analyse_recording(path: Path, cut_ns: int | None = None) -> dict[str, object]:
    """Counts, gaps and stamp→write latency of a benchmark recording; with ``cut_ns``, also how many
    were written by then (log time ≤ ``cut_ns``)."""
    from axisflow.acquisition import iter_recording
    from axisflow.acquisition.wire.sequence import SequenceTracker

    counts: dict[str, int] = {}
    sequences: dict[str, SequenceTracker] = {}
    lat: list[int] = []
    first_log, last_log = None, 0
    by_cut = 0
    for rec in iter_recording(path):
        topic, m = rec.channel.topic, rec.message
        by_cut += cut_ns is not None and m.log_time <= cut_ns
        first_log = m.log_time if first_log is None else min(first_log, m.log_time)
        last_log = max(last_log, m.log_time)
        counts[topic] = counts.get(topic, 0) + 1
        # one publisher per topic here; MCAP keeps its sequence numbers but not its id
        sequences.setdefault(topic, SequenceTracker()).add(b"", m.sequence)
        sec, nsec = _STAMP.unpack_from(m.data, 4)
        lat.append(m.log_time - (sec * 1_000_000_000 + nsec))
    arr = np.array(lat, dtype=np.int64) if lat else np.zeros(1, dtype=np.int64)
    return {
        "recorded": sum(counts.values()),
        "topics": len(counts),
        "gaps": sum(t.missed for t in sequences.values()),
        "write_span_s": (last_log - first_log) * 1e-9 if first_log is not None else 0.0,
        "latency_p50_us": float(np.percentile(arr, 50)) / 1e3,
        "latency_p99_us": float(np.percentile(arr, 99)) / 1e3,
        "recorded_by_cut": by_cut,
    }


def _run_step(tmp: Path, n_axes: int, seconds: float, speed: float = 1.0, sample_rss: bool = False) -> dict:
    """One recorder + one publisher process; returns the step's figures."""
    port = free_port()
    out = tmp / f"bench_{n_axes}_{speed:g}_{time.monotonic_ns()}.mcap"
    rss_trace: list[tuple[float, int]] = []
    with Launcher(tmp / "logs") as launcher:
        rec = _start_recorder(launcher, out, port)
        pub = launcher.start(
            "publisher", str(port), str(n_axes), str(seconds), str(speed), entry=PUBLISHER_ENTRY
        )
        t0 = time.monotonic()
        cpu_before = thread_cpu_seconds(rec.pid)
        while pub.poll() is None:
            if sample_rss:
                rss_trace.append((time.monotonic() - t0, rss_kb(rec.pid)))
            time.sleep(0.25)  # the sampling period of the RSS trace
        # the recorder's CPU up to now, against the messages it wrote up to now
        cpu_after, cut_ns = thread_cpu_seconds(rec.pid), time.time_ns()
        published = launcher.wait(pub)
        peak_kb = rss_kb(rec.pid, "VmHWM")
        recorded = launcher.stop(rec, 60.0)  # its stop proves the publisher's last samples arrived
    pub_out, pub_err, rec_out = published.stdout, published.stderr, recorded.stdout
    if published.returncode != 0 or not pub_out.strip():
        raise RuntimeError(f"publisher failed: {pub_err[-2000:]}")
    p = json.loads(pub_out.strip().splitlines()[-1])
    if not p["matched"]:
        raise RuntimeError(f"the publisher found no recorder subscribed within 15 s ({n_axes} axes)")
    summary = json.loads(rec_out) if rec_out.strip() else {}
    a = analyse_recording(out, cut_ns)
    published = p["ticks"] * p["axes"]
    out.unlink(missing_ok=True)
    return {
        "axes": n_axes,
        "published": published,
        "recorded": a["recorded"],
        "lost": published - a["recorded"],
        "gaps": a["gaps"],
        "recorder_missed": summary.get("missed"),
        "zero_loss": published == a["recorded"] and a["gaps"] == 0,
        "keeps_up": a["latency_p99_us"] <= KEEP_UP_P99_US,
        "on_pace": speed == 0 or p["wall_s"] <= seconds * 1.05 + 0.05,
        "publisher_wall_s": p["wall_s"],
        "publisher_late_ticks": p["late_ticks"],
        "latency_p50_us": a["latency_p50_us"],
        "latency_p99_us": a["latency_p99_us"],
        "recorder_peak_rss_mb": peak_kb / 1024,
        "rss_trace": rss_trace,
        "recorder_wall_s": summary.get("wall_time_s"),
        "write_span_s": a["write_span_s"],
        "cpu_us_per_message": _cpu_per_message(rec.pid, cpu_before, cpu_after, a["recorded_by_cut"], p),
    }


def _start_recorder(launcher: Launcher, out: Path, port: int) -> Child:
    """``axisflow record`` of everything into ``out``, listening on ``port``; returned once its subscriber
    has joined."""
    rec = launcher.start(
        "recorder", "record", "-o", str(out), "--listen", f"tcp/127.0.0.1:{port}", "--json", ready=True
    )
    launcher.wait_ready(rec, 60.0)
    return rec


def _idle_cpu_percent(tmp: Path, seconds: float) -> float:
    """The CPU a ready recorder uses over ``seconds`` with no publisher, in % of one core."""
    with Launcher(tmp / "logs") as launcher:
        rec = _start_recorder(launcher, tmp / "idle.mcap", free_port())
        cpu0, t0 = cpu_seconds(rec.pid), time.monotonic()
        time.sleep(seconds)  # the window watched
        cpu1, t1 = cpu_seconds(rec.pid), time.monotonic()
        launcher.stop(rec, 60.0)
    (tmp / "idle.mcap").unlink(missing_ok=True)
    return (cpu1 - cpu0) / (t1 - t0) * 100.0


def _cpu_per_message(
    rec_pid: int,
    before: dict[int, tuple[str, float]],
    after: dict[int, tuple[str, float]],
    written: int,
    pub: dict,
) -> dict[str, float]:
    """CPU µs per message: the recorder's main thread, its Zenoh receive threads and its other threads
    (the chunk writer, Zenoh's others) up to the cut, and the publisher process while it published."""
    spent = {"recorder_main": 0.0, "recorder_zenoh_rx": 0.0, "recorder_other": 0.0}
    for tid, (name, seconds) in after.items():
        group = (
            "recorder_main"
            if tid == rec_pid
            else "recorder_zenoh_rx"
            if name.startswith("rx-")
            else "recorder_other"
        )
        spent[group] += seconds - before.get(tid, (name, 0.0))[1]
    per = {k: v / written * 1e6 if written else float("nan") for k, v in spent.items()}
    messages = pub["ticks"] * pub["axes"]
    per["publisher"] = pub["cpu_s"] / messages * 1e6 if messages else float("nan")
    return per


def _baseline_writer(n: int, tmp: Path) -> float:
    """Messages/s of a plain mcap Writer (zstd, its default chunk size) with pre-encoded JointState."""
    from axisflow.acquisition.wire.keys import AxisKeys, topic_for_key
    from axisflow.acquisition.wire.messages import JOINT_STATE_SCHEMA
    from mcap.writer import CompressionType, Writer

    payload = bytes(payload_template("bench0"))
    path = tmp / "baseline.mcap"
    with open(path, "wb") as fh:
        w = Writer(fh, compression=CompressionType.ZSTD)
        w.start(profile="ros2")
        sid = w.register_schema("sensor_msgs/msg/JointState", "ros2msg", JOINT_STATE_SCHEMA.encode())
        cid = w.register_channel(topic_for_key(AxisKeys("bench0").state), "cdr", sid)
        t0 = time.perf_counter()
        for i in range(n):
            w.add_message(cid, i, payload, i, i)
        w.finish()
        dt = time.perf_counter() - t0
    path.unlink()
    return n / dt


# --------------------------------------------------------------------------- the benchmark


def run(args: argparse.Namespace) -> int:
    axes_list = list(args.axes)
    result: dict[str, object] = {"seconds_per_step": args.seconds}
    with tempfile.TemporaryDirectory(prefix="axisflow-bench-") as tmpdir:
        tmp = Path(tmpdir)
        steps = []
        t_start = time.monotonic()
        result["stopped_by"] = "end of the axis list"
        for n in axes_list:
            if time.monotonic() - t_start > args.budget:
                result["stopped_by"] = f"time budget ({args.budget:g} s)"
                break
            step = _run_step(tmp, n, args.seconds)
            step.pop("rss_trace")
            steps.append(step)
            _progress(args, f"{n} axes: lost {step['lost']}, gaps {step['gaps']}")
            reason = failure(step)
            if reason:
                result["stopped_by"] = f"{n} axes: {reason}"
                break
        result["steps"] = steps
        ok = [s["axes"] for s in steps if not failure(s)]
        result["max_axes_zero_loss"] = max(ok) if ok else 0

        # flood: 8 keys, as fast as the recorder takes them, each round beside its own baseline
        n_keys = 8
        rounds = []
        for k in range(args.flood_rounds):
            baseline = _baseline_writer(args.flood, tmp)
            bare, bare_lost, bare_missed_at_start = _raw_flood(tmp, n_keys, args.flood)
            flood = _run_step(tmp, n_keys, args.flood / n_keys / EXECUTION_RATE_HZ, speed=0.0)
            # the recorder's rate: messages over the span of their write times (first to last log_time)
            rate = flood["recorded"] / flood["write_span_s"] if flood["write_span_s"] else 0.0
            rounds.append({
                "baseline_msgs_per_s": baseline, "msgs_per_s": rate, "ratio": rate / baseline,
                "lost": flood["lost"], "messages": flood["recorded"],
                "bare_subscriber_msgs_per_s": bare, "bare_subscriber_lost": bare_lost,
                "bare_subscriber_missed_at_start": bare_missed_at_start,
                "cpu_us_per_message": flood["cpu_us_per_message"],
            })  # fmt: skip
            _progress(args, f"flood {k + 1}/{args.flood_rounds}: recorder {rate:.0f} msg/s, baseline "
                            f"{baseline:.0f} msg/s, bare subscriber {bare:.0f} msg/s")  # fmt: skip
        flood_rate = float(np.median([r["msgs_per_s"] for r in rounds]))
        baseline = float(np.median([r["baseline_msgs_per_s"] for r in rounds]))
        ratios = [r["ratio"] for r in rounds]
        bare = float(np.median([r["bare_subscriber_msgs_per_s"] for r in rounds]))
        result["baseline_writer_msgs_per_s"] = baseline
        result["bare_subscriber_msgs_per_s"] = bare
        result["recorder_flood"] = {
            "messages": sum(r["messages"] for r in rounds),
            "lost": sum(r["lost"] for r in rounds),
            "msgs_per_s": flood_rate,
            "ratio_to_baseline": flood_rate / baseline,
            "ratio_to_bare_subscriber": flood_rate / bare,
            "cpu_us_per_message": {
                k: float(np.median([r["cpu_us_per_message"][k] for r in rounds]))
                for k in rounds[0]["cpu_us_per_message"]
            },
            "ratio_min": min(ratios),
            "ratio_max": max(ratios),
            "rounds": rounds,
        }

        if args.idle_seconds > 0:
            result["idle_recorder_cpu_percent"] = _idle_cpu_percent(tmp, args.idle_seconds)

        if args.memory_seconds > 0:
            mem = _run_step(tmp, args.memory_axes, args.memory_seconds, sample_rss=True)
            trace = [(t, kb / 1024) for t, kb in mem["rss_trace"] if kb > 0]
            # after warm-up (allocator arenas, Zenoh buffers): the second half of the run
            late = [(t, mb) for t, mb in trace if t >= args.memory_seconds / 2]
            slope = float(np.polyfit(*zip(*late, strict=True), 1)[0]) * 60 if len(late) > 2 else float("nan")
            half = late[0][1] if late else float("nan")
            last = trace[-1][1] if trace else float("nan")
            result["memory"] = {
                "axes": args.memory_axes,
                "seconds": args.memory_seconds,
                "zero_loss": mem["zero_loss"],
                "rss_mb_at_half": half,
                "rss_mb_at_end": last,
                "growth_second_half_mb": last - half,
                "slope_second_half_mb_per_min": slope,
                "peak_rss_mb": mem["recorder_peak_rss_mb"],
                "rss_mb_at_tenths": [
                    round(next((mb for t, mb in trace if t >= args.memory_seconds * i / 10), trace[-1][1]), 1)
                    for i in range(1, 11)
                ]
                if trace
                else [],
            }
    if args.json:
        print(json.dumps(result, indent=2))
    else:
        _print_table(result)
    return 0


def failure(step: dict) -> str:
    """Why a capacity step does not count ('' if it passes)."""
    if not step["zero_loss"]:
        return f"{step['lost']} lost, {step['gaps']} sequence gaps"
    if not step["keeps_up"]:
        return f"recorder falls behind (p99 stamp→write {step['latency_p99_us'] / 1e3:.0f} ms)"
    if not step["on_pace"]:
        return f"the publisher process could not keep 1 kHz ({step['publisher_wall_s']:.2f} s wall)"
    return ""


def _progress(args: argparse.Namespace, text: str) -> None:
    if not args.json:
        print(f"  … {text}", file=sys.stderr, flush=True)


def _print_table(r: dict) -> None:
    print(f"pipeline benchmark ({r['seconds_per_step']:g} s per step, 1 kHz per axis, loopback Zenoh)")
    print(
        f"{'axes':>5} {'msg/s':>7} {'published':>10} {'recorded':>9} {'lost':>5} {'gaps':>5} "
        f"{'lat p50 µs':>10} {'lat p99 µs':>10} {'rec RSS MB':>10} {'late ticks':>10} {'pass':>5}"
    )
    for s in r["steps"]:
        print(
            f"{s['axes']:>5} {s['axes'] * 1000:>7} {s['published']:>10} {s['recorded']:>9} {s['lost']:>5} "
            f"{s['gaps']:>5} {s['latency_p50_us']:>10.0f} {s['latency_p99_us']:>10.0f} "
            f"{s['recorder_peak_rss_mb']:>10.1f} {s['publisher_late_ticks']:>10} "
            f"{'NO' if failure(s) else 'yes':>5}"
        )
    print(
        f"largest axis count with zero loss, keeping up (p99 <= {KEEP_UP_P99_US / 1e3:.0f} ms): "
        f"{r['max_axes_zero_loss']} (goal >= 32); search stopped by: {r['stopped_by']}"
    )
    f = r["recorder_flood"]
    spread = f"rounds {f['ratio_min']:.2f} to {f['ratio_max']:.2f}; goal >= 0.8"
    print(
        f"throughput, median of {len(f['rounds'])} rounds: recorder {f['msgs_per_s']:.0f} msg/s over Zenoh "
        f"({f['messages']} msgs, lost {f['lost']}) vs plain mcap Writer "
        f"{r['baseline_writer_msgs_per_s']:.0f} msg/s in-process: "
        f"ratio {f['ratio_to_baseline']:.2f} ({spread})"
    )
    bare_lost = sum(x["bare_subscriber_lost"] for x in f["rounds"])
    at_start = sum(x["bare_subscriber_missed_at_start"] for x in f["rounds"])
    lost = f"lost {bare_lost}, {at_start} at the start"
    bare = f"{r['bare_subscriber_msgs_per_s']:.0f} msg/s of the same flood ({lost})"
    print(
        f"            a bare Python Zenoh subscriber (no recording) takes {bare}: "
        f"the recorder reaches {f['ratio_to_bare_subscriber']:.2f} of it"
    )
    cpu = f["cpu_us_per_message"]
    print(
        f"            CPU per message (medians): recorder main thread {cpu['recorder_main']:.2f} µs, "
        f"its Zenoh receive {cpu['recorder_zenoh_rx']:.2f} µs, "
        f"its other threads {cpu['recorder_other']:.2f} µs; "
        f"publisher {cpu['publisher']:.2f} µs; the baseline Writer "
        f"{1e6 / r['baseline_writer_msgs_per_s']:.2f} µs on one thread"
    )
    if "idle_recorder_cpu_percent" in r:
        idle = r["idle_recorder_cpu_percent"]
        print(f"idle: a ready recorder with nothing to record uses {idle:.2f} % of a core (to 1 clock tick)")
    if "memory" in r:
        m = r["memory"]
        print(
            f"memory: recorder RSS {m['rss_mb_at_half']:.1f} MB at {m['seconds'] / 2:g} s -> "
            f"{m['rss_mb_at_end']:.1f} MB at {m['seconds']:g} s ({m['axes']} axes): "
            f"growth {m['growth_second_half_mb']:+.1f} MB, "
            f"trend {m['slope_second_half_mb_per_min']:+.2f} MB/min over the second half, "
            f"peak {m['peak_rss_mb']:.1f} MB"
        )
        print(f"        RSS MB at each tenth of the run: {m['rss_mb_at_tenths']}")
