"""Moves: the pipeline at ``--speed 0`` while the planner's moves run, against the bridge at rest and
a raw Zenoh put loop of the same payload, all in this run.

Three runs, each in fresh processes on loopback (the bridge and the recorder are ``axisflow`` processes,
the planner node runs in this process as the demo runs it):

1. **raw Zenoh**: a publisher process puts the same two JointState payloads a bridge publishes per tick
   (``state`` and ``setpoint``, with the 33-byte attachment) with plain ``zenoh`` calls, as fast as a
   plain ``zenoh`` subscriber process that drains them allows (congestion control BLOCK): ticks/s and
   CPU µs per tick of both processes — what Zenoh itself costs;
2. **bridge at rest**: ``axisflow bridge --speed 0 --duration D`` with ``axisflow record`` attached:
   ticks/s from the bridge's report and CPU µs per tick of the two;
3. **during moves**: the same two plus the planner node (random way points, both cases, ``--law``):
   drive time of the moves over the wall time of the run (× real time) and CPU µs per tick summed over
   the bridge, the recorder and this process.

CPU per process is read from ``/proc/<pid>/stat`` (user + system) at the start and end of each run.
The goal (issue 23): during moves ≥ 40× real time and ≤ 50 µs of CPU per tick.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

from axisflow.arguments import finite_float, positive_int
from axisflow.deploy.processes import Launcher, free_port

from .toolkit.proc_stats import cpu_seconds

GOAL_SPEED = 40.0
GOAL_CPU_US = 50.0
RAW_PUBLISHER = "axisflow.benchmarks.moves:raw_publisher_main"
RAW_SUBSCRIBER = "axisflow.benchmarks.moves:raw_subscriber_main"
_TICKS_PER_S = 1000


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--waypoints", type=positive_int, default=60, help="way points of the moves run (default 60)"
    )
    parser.add_argument("--law", default="poly5", help="motion law of the moves (default poly5)")
    parser.add_argument(
        "--rest-seconds",
        type=finite_float,
        default=60.0,
        help="drive time of the bridge-at-rest run [s] (default 60)",
    )
    parser.add_argument(
        "--raw-ticks", type=positive_int, default=100_000, help="ticks of the raw Zenoh run (default 100000)"
    )


# --------------------------------------------------------------------------- raw Zenoh processes


def _payloads() -> tuple[bytes, bytes]:
    from axisflow.acquisition.wire.messages import AxisSample

    return (
        AxisSample(1_700_000_000_000_000_000, "a0", 0.4, 0.1, 12.0, 133.0, 33.0, 0.05).encode(),
        AxisSample(1_700_000_000_000_000_000, "a0", 0.4, 0.1, 12.5, 133.0, 33.0, 0.052).encode(),
    )


def raw_subscriber_main() -> None:
    """``PORT TICKS``: a plain zenoh subscriber on bench/raw/** that drains 2·TICKS messages, then says so."""
    import zenoh

    port, ticks = int(sys.argv[1]), int(sys.argv[2])
    config = zenoh.Config()
    config.insert_json5("mode", '"peer"')
    config.insert_json5("listen/endpoints", json.dumps([f"tcp/127.0.0.1:{port}"]))
    config.insert_json5("scouting/multicast/enabled", "false")
    with zenoh.open(config) as session:
        sub = session.declare_subscriber("bench/raw/**", zenoh.handlers.FifoChannel(1 << 16))
        print("ready", flush=True)
        for _ in range(2 * ticks):
            sub.recv()
        print(json.dumps({"received": 2 * ticks}), flush=True)
        sub.undeclare()


def raw_publisher_main() -> None:
    """``PORT TICKS``: plain zenoh puts of two payloads per tick (BLOCK), as fast as they go."""
    import zenoh
    from axisflow.acquisition.wire.attachment import pack_attachment

    port, ticks = int(sys.argv[1]), int(sys.argv[2])
    config = zenoh.Config()
    config.insert_json5("mode", '"peer"')
    config.insert_json5("connect/endpoints", json.dumps([f"tcp/127.0.0.1:{port}"]))
    config.insert_json5("scouting/multicast/enabled", "false")
    state, setpoint = _payloads()
    gid = os.urandom(16)
    with zenoh.open(config) as session:
        block = zenoh.CongestionControl.BLOCK
        pubs = [
            session.declare_publisher(f"bench/raw/{k}", congestion_control=block)
            for k in ("state", "setpoint")
        ]
        deadline = time.monotonic() + 30.0
        while not all(p.matching_status.matching for p in pubs):
            if time.monotonic() > deadline:
                raise SystemExit("no subscriber within 30 s")
            time.sleep(0.01)
        t0 = time.perf_counter()
        for k in range(1, ticks + 1):
            pubs[0].put(state, attachment=pack_attachment(k, time.time_ns(), gid))
            pubs[1].put(setpoint, attachment=pack_attachment(k, time.time_ns(), gid))
        print(json.dumps({"wall_s": time.perf_counter() - t0}), flush=True)
        for p in pubs:
            p.undeclare()


# --------------------------------------------------------------------------- helpers


def _self_cpu_s() -> float:
    t = os.times()
    return t.user + t.system


def _say(args: argparse.Namespace, text: str) -> None:
    if not args.json:
        print(f"  … {text}", file=sys.stderr, flush=True)


# --------------------------------------------------------------------------- the runs


def raw_zenoh(tmp: Path, ticks: int) -> dict[str, float]:
    port = free_port()
    with Launcher(tmp / "raw") as launcher:
        sub = launcher.start("raw-subscriber", str(port), str(ticks), entry=RAW_SUBSCRIBER)
        pub = launcher.start("raw-publisher", str(port), str(ticks), entry=RAW_PUBLISHER)
        t0 = time.perf_counter()
        cpu = {}
        while pub.poll() is None:
            cpu = {p.pid: cpu_seconds(p.pid) for p in (pub, sub) if p.poll() is None}
            time.sleep(0.05)
        published = launcher.wait(pub)
        received = launcher.wait(sub, 60.0)
        wall = time.perf_counter() - t0
    if published.returncode != 0 or received.returncode != 0:
        raise RuntimeError(f"raw zenoh run failed: {published.stderr[-1000:]} {received.stderr[-1000:]}")
    pub_wall = json.loads(published.stdout.strip().splitlines()[-1])["wall_s"]
    return {
        "ticks": ticks,
        "ticks_per_s": ticks / pub_wall,
        "speed": ticks / pub_wall / _TICKS_PER_S,
        "cpu_us_per_tick": sum(cpu.values()) / ticks * 1e6,
        "wall_s": wall,
    }


def _start_pair(launcher: Launcher, tmp: Path, speed0_args: list[str]) -> tuple:
    port = free_port()
    endpoint = f"tcp/127.0.0.1:{port}"
    bridge = launcher.start(
        "bridge", "bridge", "--sim", "--speed", "0", "--listen", endpoint, *speed0_args, ready=True
    )
    launcher.wait_ready(bridge, 60.0)
    out = tmp / f"rec-{time.monotonic_ns()}.mcap"
    rec = launcher.start("recorder", "record", "-o", str(out), "--connect", endpoint, "--json", ready=True)
    launcher.wait_ready(rec, 60.0)
    return bridge, rec, endpoint, out


def bridge_at_rest(tmp: Path, seconds: float) -> dict[str, float]:
    with Launcher(tmp / "rest") as launcher:
        # the bridge waits for a consumer: it starts ticking once the recorder has joined
        bridge, rec, _endpoint, out = _start_pair(launcher, tmp, ["--duration", f"{seconds:g}", "--json"])
        cpu0 = {p.pid: cpu_seconds(p.pid) for p in (bridge, rec)}
        cpu1 = dict(cpu0)
        while bridge.poll() is None:
            cpu1 = {p.pid: cpu_seconds(p.pid) for p in (bridge, rec)}
            time.sleep(0.05)
        done = launcher.wait(bridge)
        launcher.stop(rec, 60.0)
        out.unlink(missing_ok=True)
    report = json.loads(done.stdout)
    ticks, wall = report["ticks"], report["wall_time_s"]
    return {
        "ticks": ticks,
        "ticks_per_s": ticks / wall,
        "speed": ticks / wall / _TICKS_PER_S,
        "cpu_us_per_tick": sum(cpu1[p] - cpu0[p] for p in cpu0) / ticks * 1e6,
        "wall_s": wall,
    }


def during_moves(tmp: Path, waypoints: int, law: str) -> dict[str, object]:
    from axisflow.acquisition import AxisKeys
    from axisflow.acquisition.bus.session import ZenohOptions, open_session
    from axisflow.model import default_params
    from axisflow.planner import DEFAULT_OMEGA, make_backend

    from axisflow.experiment.offline import CASES
    from axisflow.experiment.waypoints import random_waypoints
    from axisflow.nodes.planner_node import NodeRun, NodeSettings, PlannerNode

    params = default_params()
    points = random_waypoints(waypoints, 0, params)
    runs = tuple(NodeRun(case, law) for case in CASES)
    settings = NodeSettings(AxisKeys(), runs, DEFAULT_OMEGA, 1, 60.0, "bench")
    with Launcher(tmp / "moves") as launcher:
        bridge, rec, endpoint, out = _start_pair(launcher, tmp, [])
        with (
            open_session(ZenohOptions(connect=(endpoint,))) as session,
            PlannerNode(session, settings, params, make_backend("exact"), lambda _line: None) as node,
        ):
            cpu0 = {p.pid: cpu_seconds(p.pid) for p in (bridge, rec)}
            self0, t0 = _self_cpu_s(), time.perf_counter()
            reports = node.run(points)
            wall = time.perf_counter() - t0
            cpu1 = {p.pid: cpu_seconds(p.pid) for p in (bridge, rec)}
            self1 = _self_cpu_s()
        launcher.stop(rec, 60.0)
        launcher.stop(bridge, 30.0)
        out.unlink(missing_ok=True)
    starts = [m.accepted.start_tick for r in reports for m in r.moves if m.accepted is not None]
    ends = [m.accepted.end_tick for r in reports for m in r.moves if m.accepted is not None]
    ticks = max(ends) - min(starts)
    cpu = {"bridge": cpu1[bridge.pid] - cpu0[bridge.pid], "recorder": cpu1[rec.pid] - cpu0[rec.pid],
           "planner": self1 - self0}  # fmt: skip
    return {
        "moves": len(starts),
        "ticks": ticks,
        "speed": ticks / _TICKS_PER_S / wall,
        "wall_s": wall,
        "cpu_us_per_tick": sum(cpu.values()) / ticks * 1e6,
        "cpu_us_per_tick_by_process": {k: v / ticks * 1e6 for k, v in cpu.items()},
        "idle_ticks": sum(sum(r.idle_ticks) for r in reports),
    }


def run(args: argparse.Namespace) -> int:
    result: dict[str, object] = {"goal_speed": GOAL_SPEED, "goal_cpu_us_per_tick": GOAL_CPU_US}
    with tempfile.TemporaryDirectory(prefix="axisflow-bench-moves-") as tmpdir:
        tmp = Path(tmpdir)
        _say(args, f"raw zenoh: {args.raw_ticks} ticks of two puts")
        result["raw_zenoh"] = raw_zenoh(tmp, args.raw_ticks)
        _say(args, f"bridge at rest with a recorder: {args.rest_seconds:g} s of drive time")
        result["bridge_at_rest"] = bridge_at_rest(tmp, args.rest_seconds)
        _say(args, f"during moves: {args.waypoints} way points, both cases, {args.law}")
        result["during_moves"] = during_moves(tmp, args.waypoints, args.law)
    moves = result["during_moves"]
    assert isinstance(moves, dict)
    result["goals_met"] = moves["speed"] >= GOAL_SPEED and moves["cpu_us_per_tick"] <= GOAL_CPU_US
    if args.json:
        print(json.dumps(result, indent=2))
    else:
        print(table(result))
    return 0


def table(r: dict) -> str:
    raw, rest, moves = r["raw_zenoh"], r["bridge_at_rest"], r["during_moves"]
    by = ", ".join(f"{k} {v:.1f}" for k, v in moves["cpu_us_per_tick_by_process"].items())
    lines = [
        "pipeline at --speed 0 (loopback Zenoh; one tick = a state and a setpoint message)",
        f"{'run':34} {'× real time':>12} {'CPU µs/tick':>12} {'ticks':>9}",
        f"{'raw zenoh put loop (baseline)':34} {raw['speed']:>12.1f} {raw['cpu_us_per_tick']:>12.1f} "
        f"{raw['ticks']:>9}",
        f"{'bridge at rest + recorder':34} {rest['speed']:>12.1f} {rest['cpu_us_per_tick']:>12.1f} "
        f"{rest['ticks']:>9}",
        f"{'moves: bridge + recorder + planner':34} {moves['speed']:>12.1f} "
        f"{moves['cpu_us_per_tick']:>12.1f} {moves['ticks']:>9}",
        f"during moves against raw zenoh: speed ratio {moves['speed'] / raw['speed']:.2f}, CPU ratio "
        f"{moves['cpu_us_per_tick'] / raw['cpu_us_per_tick']:.2f}; against the bridge at rest: speed ratio "
        f"{moves['speed'] / rest['speed']:.2f}",
        f"CPU µs per tick by process during moves: {by}",
        f"goals (>= {r['goal_speed']:g}× real time, <= {r['goal_cpu_us_per_tick']:g} µs CPU per tick): "
        f"{'met' if r['goals_met'] else 'NOT met'}",
    ]
    return "\n".join(lines)
