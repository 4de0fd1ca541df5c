"""ROS 2: JointState samples per second delivered to an rclpy subscriber, and the latency the node adds.

Everything runs inside a private network namespace (``unshare -n``: DDS discovery stays on this
machine; :mod:`axisflow.deploy.private_network`) with a random ``ROS_DOMAIN_ID`` and
``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``: the command re-runs itself there. Each subscriber and
publisher is a process of its own. Over ``--seconds`` of 1 kHz samples per path:

1. **bridge → Zenoh subscriber**: ``axisflow bridge --sim`` (1× real time) to a plain Zenoh
   subscriber — what reaches any program on the bus;
2. **bridge → axisflow ros2 → rclpy subscriber**: the same bridge, at the same time, through
   ``axisflow ros2`` to an rclpy subscriber (reliable, deserializing: as a user writes one);
3. **rclpy → rclpy** (the baseline): an rclpy publisher paced at 1 kHz, the same JointState (the
   axis's two joints) stamped on a 1 ms grid as the drive stamps its ticks, to the same subscriber.

Each subscriber takes samples for ``--seconds`` plus twice :data:`WARMUP_S`; the measured window is
``--seconds`` of stamps starting :data:`WARMUP_S` after the later subscriber's first one (rows 1 and 2:
the same samples). Per path: messages per second delivered, samples missing from the window's 1 ms
stamp grid, and the latency from the stamp to the subscriber's callback (p50, p90, p99, max; a
stamp is the tick's scheduled time, so a publisher's own lateness counts), with the p50 against the
baseline's. The latency the node adds is measured per sample: its arrival at the rclpy subscriber
less its arrival at the Zenoh subscriber.

Then the relay's cost per sample, in this process: the node's way (decode to check, publish the CDR
bytes as they came) against ``rclpy.serialization.deserialize_message`` + publish and a message built
from the decoded sample + publish (one publisher, no subscriber: the conversion and rcl's publish).
"""

from __future__ import annotations

import argparse
import json
import os
import random
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from axisflow.arguments import finite_float, positive_int

SUBSCRIBER_ENTRY = "axisflow.benchmarks.ros2:subscriber_main"
"""a subscriber process: ``zenoh PORT SECONDS`` or ``ros TOPIC SECONDS``; prints one JSON line"""
PUBLISHER_ENTRY = "axisflow.benchmarks.ros2:publisher_main"
"""the baseline's rclpy publisher: ``TOPIC SECONDS``; prints one JSON line"""
BASELINE_TOPIC = "/axisflow/bench/joint_states"
TICK_NS = 1_000_000
NS = 1_000_000_000
AXIS = "a0"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--seconds",
        type=finite_float,
        default=10.0,
        help="samples per path, in seconds of 1 kHz (default 10)",
    )
    parser.add_argument(
        "--samples",
        type=positive_int,
        default=20_000,
        help="samples of each way in the relay-cost comparison (default 20000)",
    )


# ---- the processes -----------------------------------------------------------------------------------


def _summary(arrivals: list[tuple[int, int]], window: tuple[int, int]) -> dict[str, Any]:
    """Delivered rate, missing samples and latency of the (arrival ns, stamp ns) pairs whose stamps
    lie in ``window`` (ns, both ends included)."""
    import numpy as np

    pairs = np.array([p for p in arrivals if window[0] <= p[1] <= window[1]], dtype=np.int64).reshape(-1, 2)
    if len(pairs) < 2:
        raise ValueError(f"{len(pairs)} messages in the measured window")
    stamps = pairs[:, 1]
    latency_us = (pairs[:, 0] - stamps) / 1e3
    steps = np.diff(stamps) // TICK_NS
    ticks = (window[1] - window[0]) // TICK_NS + 1
    p50, p90, p99 = np.percentile(latency_us, [50, 90, 99])
    return {
        "messages": len(pairs),
        "per_s": len(pairs) / (ticks * TICK_NS / NS),
        "missing": ticks - len(np.unique(stamps)),
        "out_of_order": int(np.sum(steps < 1)),
        "latency_us": {"p50": p50, "p90": p90, "p99": p99, "max": float(latency_us.max())},
    }


def _added_latency(
    node: list[tuple[int, int]], zenoh: list[tuple[int, int]], window: tuple[int, int]
) -> dict:
    """Per sample stamped in ``window`` that reached both: its arrival at the rclpy subscriber less its
    arrival at the Zenoh subscriber [µs], as quantiles."""
    import numpy as np

    at_zenoh = {stamp: arrival for arrival, stamp in zenoh if window[0] <= stamp <= window[1]}
    added = np.array([arrival - at_zenoh[stamp] for arrival, stamp in node if stamp in at_zenoh]) / 1e3
    p50, p90, p99 = np.percentile(added, [50, 90, 99])
    return {"samples": int(added.size), "p50": p50, "p90": p90, "p99": p99, "max": float(added.max())}


class Collector:
    """(arrival ns, stamp ns) of the messages from the first one on, for ``seconds`` (a minute at
    most for the first)."""

    FIRST_WAIT_S = 60.0

    def __init__(self, seconds: float) -> None:
        self.seconds = seconds
        self.arrivals: list[tuple[int, int]] = []
        self._started = time.monotonic()

    def add(self, arrival_ns: int, stamp_ns: int) -> None:
        self.arrivals.append((arrival_ns, stamp_ns))

    def going(self) -> bool:
        if not self.arrivals:
            return time.monotonic() < self._started + self.FIRST_WAIT_S
        return (time.time_ns() - self.arrivals[0][0]) / NS < self.seconds


def subscriber_main() -> None:
    """Entry of a subscriber process: ``zenoh PORT SECONDS`` or ``ros TOPIC SECONDS``. Records
    (arrival, stamp) from its first message for SECONDS, then prints them as one JSON object."""
    kind, where, seconds = sys.argv[1], sys.argv[2], float(sys.argv[3])
    collector = Collector(seconds)
    if kind == "zenoh":
        _zenoh_subscriber(int(where), collector)
    else:
        _ros_subscriber(where, collector)
    print(json.dumps({"arrivals": collector.arrivals}), flush=True)


def _zenoh_subscriber(port: int, collector: Collector) -> None:
    import struct

    from axisflow.acquisition import AxisKeys, ZenohOptions, open_session

    stamp = struct.Struct("<iI")

    def on_sample(sample: Any) -> None:  # on Zenoh's thread: the arrival time first
        now = time.time_ns()
        sec, nsec = stamp.unpack_from(sample.payload.to_bytes(), 4)
        collector.add(now, sec * NS + nsec)

    with open_session(ZenohOptions.loopback(connect_port=port)) as session:
        subscriber = session.declare_subscriber(AxisKeys(AXIS).state, on_sample)
        while collector.going():
            time.sleep(0.05)
        subscriber.undeclare()


def _ros_context() -> Any:
    import rclpy
    from rclpy.signals import SignalHandlerOptions

    context = rclpy.Context()
    rclpy.init(context=context, signal_handler_options=SignalHandlerOptions.NO)
    return context


def _ros_subscriber(topic: str, collector: Collector) -> None:
    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from sensor_msgs.msg import JointState

    def on_message(message: JointState) -> None:
        now = time.time_ns()
        collector.add(now, message.header.stamp.sec * NS + message.header.stamp.nanosec)

    context = _ros_context()
    node = rclpy.create_node("axisflow_bench_subscriber", context=context)
    qos = QoSProfile(depth=10_000, reliability=ReliabilityPolicy.RELIABLE)
    node.create_subscription(JointState, topic, on_message, qos)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    while collector.going():
        executor.spin_once(timeout_sec=0.05)
    executor.shutdown()
    node.destroy_node()
    context.try_shutdown()


def publisher_main() -> None:
    """Entry of the baseline's rclpy publisher: ``TOPIC SECONDS``. Once a subscriber matches, it
    publishes the axis's JointState at 1 kHz for SECONDS + 5 s, stamped on a 1 ms grid (as a drive
    stamps its ticks), each sent when its stamp comes; prints one JSON line."""
    import rclpy
    from axisflow.acquisition.wire.messages import AxisSample

    from axisflow.nodes.ros2.qos import JOINT_STATES_QOS
    from axisflow.nodes.ros2.ros_messages import joint_state, ros_time

    topic, seconds = sys.argv[1], float(sys.argv[2])
    context = _ros_context()
    node = rclpy.create_node("axisflow_bench_publisher", context=context)
    from sensor_msgs.msg import JointState

    publisher = node.create_publisher(JointState, topic, JOINT_STATES_QOS)
    deadline = time.monotonic() + 60.0
    while publisher.get_subscription_count() < 1 and time.monotonic() < deadline:
        time.sleep(0.01)
    message = joint_state(AxisSample(0, AXIS, 0.1, 0.0, 0.0, 25.0, 0.0, 0.0))
    ticks = round((seconds + 5.0) * 1e3)
    t0 = (time.time_ns() // TICK_NS + 10) * TICK_NS
    late = 0
    for k in range(ticks):
        stamp = t0 + k * TICK_NS
        wait = (stamp - time.time_ns()) / NS
        if wait > 0:
            time.sleep(wait)
        else:
            late += 1
        message.header.stamp = ros_time(stamp)
        publisher.publish(message)
    node.destroy_node()
    context.try_shutdown()
    print(json.dumps({"published": ticks, "late": late}), flush=True)


# ---- the relay's cost per sample -------------------------------------------------------------------


def _relay_costs(samples: int) -> dict[str, float]:
    """Microseconds per sample of each way to turn the bridge's CDR bytes into a ROS 2 publication."""
    import rclpy
    from axisflow.acquisition.wire.messages import AxisSample
    from rclpy.serialization import deserialize_message
    from sensor_msgs.msg import JointState

    from axisflow.nodes.ros2.qos import JOINT_STATES_QOS
    from axisflow.nodes.ros2.ros_messages import joint_state

    data = AxisSample(1_700_000_000_000_000_000, AXIS, 0.1, 0.2, 3.0, 25.0, 50.0, 0.5).encode()
    context = _ros_context()
    node = rclpy.create_node("axisflow_bench_costs", context=context)
    publisher = node.create_publisher(JointState, "/axisflow/bench/costs", JOINT_STATES_QOS)

    def raw() -> None:
        AxisSample.decode(data)  # the relay's check (and its stamp)
        publisher.publish(data)

    def deserialized() -> None:
        publisher.publish(deserialize_message(data, JointState))

    def built() -> None:
        publisher.publish(joint_state(AxisSample.decode(data)))

    ways = {"raw": raw, "deserialize_message": deserialized, "built": built}
    best = {name: float("inf") for name in ways}
    for _round in range(5):  # interleaved rounds, the best of each: the machine's load varies
        for name, way in ways.items():
            t0 = time.perf_counter()
            for _ in range(samples):
                way()
            best[name] = min(best[name], (time.perf_counter() - t0) / samples * 1e6)
    node.destroy_node()
    context.try_shutdown()
    return best


# ---- the run ---------------------------------------------------------------------------------------


def run(args: argparse.Namespace) -> int:
    from axisflow.model import AxisflowError

    from axisflow.deploy import private_network
    from axisflow.nodes.ros2.environment import RosEnvironment, require_rclpy

    if not args.seconds > 0:
        raise AxisflowError(f"--seconds {args.seconds:g} must be > 0 s")
    require_rclpy()
    if not private_network.inside():
        why = private_network.unavailable()
        if why is not None:
            raise AxisflowError(f"bench ros2 runs DDS only in a private network namespace, and here {why}")
        return _rerun_inside(args)
    environment = RosEnvironment.from_environ()
    result = {"seconds": args.seconds, "environment": environment.describe(), **_measure(args)}
    if args.json:
        print(json.dumps(result, indent=1))
    else:
        _print_table(result)
    return 0


def _rerun_inside(args: argparse.Namespace) -> int:
    """This benchmark again, inside a fresh private network namespace, on this terminal."""
    from axisflow.deploy import private_network

    argv = [sys.executable, "-m", "axisflow", "bench", "ros2", "--seconds", f"{args.seconds:g}"]
    argv += ["--samples", str(args.samples)] + (["--json"] if args.json else [])
    with tempfile.TemporaryDirectory(prefix="axisflow-bench-ros2-") as tmp:
        env = {
            **os.environ,
            private_network.INSIDE_ENV: "1",
            "ROS_DOMAIN_ID": str(random.SystemRandom().randint(1, 200)),  # any domain: the namespace is ours
            "ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST",
            "ROS_LOG_DIR": str(Path(tmp) / "ros-log"),
        }
        return subprocess.run(private_network.command(argv), env=env, check=False).returncode


def _progress(args: argparse.Namespace, text: str) -> None:
    if not args.json:
        print(f"  … {text}", file=sys.stderr, flush=True)


WARMUP_S = 3.0
"""seconds of samples each subscriber takes before the measured window (its own start-up, the other
processes')"""


def _window(*streams: list[tuple[int, int]], seconds: float) -> tuple[int, int]:
    """The stamps [ns] measured: ``seconds`` from :data:`WARMUP_S` after the latest first stamp, on the
    1 ms grid, within every stream."""
    start = max(stream[0][1] for stream in streams) + round(WARMUP_S * NS)
    start -= start % TICK_NS
    end = min(start + round(seconds * NS) - TICK_NS, *(stream[-1][1] for stream in streams))
    return start, end


def _measure(args: argparse.Namespace) -> dict[str, Any]:
    from axisflow.model import AxisflowError

    from axisflow.deploy import private_network
    from axisflow.deploy.processes import Launcher, free_port

    if private_network.interfaces() != ["lo"]:
        raise AxisflowError(f"not a private network namespace: interfaces {private_network.interfaces()}")
    collect = f"{args.seconds + 2 * WARMUP_S:g}"
    timeout = args.seconds + 120.0
    with tempfile.TemporaryDirectory(prefix="axisflow-bench-ros2-") as tmp, Launcher(Path(tmp)) as launcher:
        port = free_port()
        bridge = launcher.start("bridge", "bridge", "--sim", "--listen", f"tcp/127.0.0.1:{port}", ready=True)
        launcher.wait_ready(bridge, 120.0)
        node = launcher.start(
            "ros2", "ros2", "--axis", AXIS, "--connect", f"tcp/127.0.0.1:{port}", "--json", ready=True
        )
        launcher.wait_ready(node, 120.0)
        _progress(args, f"bridge and axisflow ros2 up; {args.seconds:g} s through both paths")
        topic = f"/axisflow/{AXIS}/joint_states"
        zenoh_sub = launcher.start("zenoh-sub", "zenoh", str(port), collect, entry=SUBSCRIBER_ENTRY)
        ros_sub = launcher.start("ros-sub", "ros", topic, collect, entry=SUBSCRIBER_ENTRY)
        zenoh = launcher.wait(zenoh_sub, timeout).json()["arrivals"]
        via_node = launcher.wait(ros_sub, timeout).json()["arrivals"]
        node_report = launcher.stop(node).json()
        launcher.stop(bridge)
        _progress(args, f"rclpy → rclpy, {args.seconds:g} s")
        base_sub = launcher.start("base-sub", "ros", BASELINE_TOPIC, collect, entry=SUBSCRIBER_ENTRY)
        base_pub = launcher.start("base-pub", BASELINE_TOPIC, collect, entry=PUBLISHER_ENTRY)
        baseline = launcher.wait(base_sub, timeout).json()["arrivals"]
        publisher = launcher.wait(base_pub, timeout).json()
    for name, stream in (("Zenoh", zenoh), ("axisflow ros2", via_node), ("rclpy baseline", baseline)):
        if len(stream) < 2:
            raise AxisflowError(f"bench ros2: the {name} subscriber received {len(stream)} messages")
    shared = _window(zenoh, via_node, seconds=args.seconds)
    rows = {
        "window_s": (shared[1] - shared[0]) / NS + 1e-3,
        "zenoh": _summary(zenoh, shared),
        "node": _summary(via_node, shared),
        "added_us": _added_latency(via_node, zenoh, shared),
        "node_report": node_report,
        "baseline": _summary(baseline, _window(baseline, seconds=args.seconds)),
        "baseline_publisher": publisher,
    }
    _progress(args, f"the relay's cost per sample, {args.samples} samples each way")
    rows["relay_cost_us"] = _relay_costs(args.samples)
    return rows


PATHS = (
    ("zenoh", "bridge → Zenoh subscriber"),
    ("node", "bridge → axisflow ros2 → rclpy"),
    ("baseline", "rclpy → rclpy (baseline)"),
)
WAYS = (
    ("raw", "CDR bytes as they came (decode to check)"),
    ("deserialize_message", "rclpy deserialize_message"),
    ("built", "message built from the decoded sample"),
)


def _print_table(r: dict[str, Any]) -> None:
    print(
        f"ROS 2 benchmark: {r['window_s']:.1f} s of 1 kHz JointState per path (after {WARMUP_S:g} s); "
        f"{r['environment']}"
    )
    print(
        f"{'path':<32} {'msg/s':>7} {'missing':>7} {'p50 ms':>7} {'p90 ms':>7} {'p99 ms':>7} {'max ms':>7} "
        f"{'p50 × baseline':>14}"
    )
    base = r["baseline"]["latency_us"]["p50"]
    for key, label in PATHS:
        row = r[key]
        lat = row["latency_us"]
        ms = {k: v / 1e3 for k, v in lat.items()}
        print(
            f"{label:<32} {row['per_s']:>7.1f} {row['missing']:>7} {ms['p50']:>7.3f} {ms['p90']:>7.3f} "
            f"{ms['p99']:>7.3f} {ms['max']:>7.2f} {lat['p50'] / base:>14.2f}"
        )
    added, report = r["added_us"], r["node_report"]
    print(
        f"added by the node, per sample (rclpy arrival − Zenoh arrival, {added['samples']} samples): "
        f"p50 {added['p50'] / 1e3:.3f} ms, p90 {added['p90'] / 1e3:.3f} ms, p99 {added['p99'] / 1e3:.3f} ms, "
        f"max {added['max'] / 1e3:.2f} ms"
    )
    print(
        f"the node relayed {report['samples_published']} samples, {report['samples_lost']} lost on its Zenoh "
        f"leg; the baseline publisher was late for {r['baseline_publisher']['late']} of "
        f"{r['baseline_publisher']['published']} ticks"
    )
    costs = r["relay_cost_us"]
    print("relay cost per sample (convert + publish, no subscriber; best of 5 rounds)")
    for key, label in WAYS:
        print(f"  {label:<42} {costs[key]:>7.1f} µs  {costs[key] / costs['raw']:>5.2f}×")
