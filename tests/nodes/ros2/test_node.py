"""``axisflow ros2`` against real ROS 2 nodes written with rclpy (no mocks): a subscriber that counts
every sample, a publisher that sends trajectories and watches the axis arrive, service clients that
stop the axis and reset its drive, a diagnostics listener.

DDS discovers its peers by multicast, which must not leave this machine. The outer test therefore
re-runs this file's inner tests inside a private network namespace (``unshare -n``, only a loopback
interface, multicast routed to it: :mod:`axisflow.deploy.private_network`) with a random
``ROS_DOMAIN_ID``, ``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST`` and ``ROS_LOG_DIR`` in a temporary
folder; every process — the bridge, the node, the drive simulator, this test's rclpy node — runs in
there, and each inner test first proves that ``lo`` is the only interface it can see. Where no
namespace can be made (not root, no unshare) the outer test is skipped with the reason; without
rclpy the whole file is.
"""

from __future__ import annotations

import itertools
import json
import os
import random
import signal
import subprocess
import sys
from dataclasses import dataclass

import pytest

pytest.importorskip("rclpy", reason='ROS 2 is not installed (pip install "axisflow[ros2]")')

from axisflow.deploy import private_network
from axisflow.deploy.processes import wait_until

INSIDE = private_network.inside()
inside_only = pytest.mark.skipif(
    not INSIDE, reason="runs inside the private network namespace the outer test makes"
)
NS = 1_000_000_000
TICK_NS = 1_000_000
CANOPEN_CONFIG = """[can]
interface = "udp_multicast"
channel = "239.74.163.3"

[drive]
node_id = 5
cycle_hz = 1000
encoder_counts_per_rev = 131072
pacing = "lockstep"
# Python processes on a machine others load too: a lock-step wait may last; only a dead drive counts
pdo_timeout_ms = 2000
heartbeat_timeout_ms = 2000
"""
PEER_PROFILE = """<?xml version="1.0" encoding="UTF-8" ?>
<profiles xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <participant profile_name="axisflow_test_peer" is_default_profile="true">
    <rtps><builtin><discovery_config>
      <leaseAnnouncement><sec>0</sec><nanosec>200000000</nanosec></leaseAnnouncement>
    </discovery_config></builtin></rtps>
  </participant>
</profiles>
"""
"""The test's participant announces itself every 0.2 s instead of every 3 s: a participant made later
(the node's) learns of it from such an announcement, unless it happens to catch the answer to its own
first ones; that way, the test's subscriptions are matched while the processes start, not seconds
later"""
FAULT_AT_S = 3.0
"""when the simulated drive faults [s of drive time]: the node must have seen it OK by then"""


@pytest.mark.slow
@pytest.mark.heavy
def test_the_node_against_ros2_nodes_inside_a_private_network_namespace(tmp_path):
    if INSIDE:
        pytest.skip("this is the namespace's own run")
    why = private_network.unavailable()
    if why is not None:
        pytest.skip(f"no private network namespace here: {why}")
    env = {
        **os.environ,
        private_network.INSIDE_ENV: "1",
        "ROS_DOMAIN_ID": str(random.SystemRandom().randint(1, 200)),  # not test data: any free domain
        "ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST",
        "ROS_LOG_DIR": str(tmp_path / "ros-log"),
        "CI": "1",
        "RUST_LOG": "error",
    }
    inner = [
        sys.executable,
        "-m",
        "pytest",
        "-q",
        "-p",
        "no:cacheprovider",
        "-x",
        "-s",
        "-k",
        os.environ.get("AXISFLOW_ROS2_INNER", "inside_"),
        __file__,
    ]
    run = subprocess.run(
        private_network.command(inner), capture_output=True, text=True, env=env, timeout=900, cwd=tmp_path
    )
    passed = "passed" if "AXISFLOW_ROS2_INNER" in os.environ else "4 passed"
    assert run.returncode == 0 and passed in run.stdout, run.stdout[-6000:] + run.stderr[-3000:]


# ---- inside the namespace ------------------------------------------------------------------------------


@dataclass(frozen=True)
class Sample:
    stamp_ns: int
    frame_id: str
    names: tuple[str, ...]
    position_m: float
    velocity_m_s: float


@dataclass(frozen=True)
class Status:
    level: int
    name: str
    message: str
    hardware_id: str
    values: dict[str, str]


class Samples(list[Sample]):
    """The samples one subscription received, in arrival order."""

    first_raw: bytes | None = None
    """the first message, serialized (for rclpy to deserialize)"""


class RosPeer:
    """This test's own rclpy node (its own context, nothing global), spun on the test's thread."""

    def __init__(self) -> None:
        import rclpy
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.signals import SignalHandlerOptions

        self.context = rclpy.Context()
        rclpy.init(context=self.context, signal_handler_options=SignalHandlerOptions.NO)
        self.node = rclpy.create_node("axisflow_test_peer", context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)

    def spin_until(self, predicate, timeout_s: float, what: str) -> None:
        import time

        deadline = time.monotonic() + timeout_s
        while not predicate():
            if time.monotonic() > deadline:
                pytest.fail(f"{what} did not happen within {timeout_s:g} s")
            self.executor.spin_once(timeout_sec=0.01)

    def joint_states(self, axis: str = "a0", best_effort: bool = False) -> Samples:
        """Every JointState on the axis's topic from now on: a reliable subscriber (as ``ros2 topic
        echo``) that takes the serialized messages and reads them with axisflow's codec, which is
        cheaper than rclpy's conversion: a Python subscriber on a loaded machine must keep up with
        1 kHz."""
        from axisflow.acquisition.wire.messages import AxisSample
        from axisflow.acquisition.wire.messages import JointState as Contract
        from rclpy.qos import QoSProfile, ReliabilityPolicy
        from sensor_msgs.msg import JointState

        got = Samples()

        def on_message(data: bytes) -> None:
            if got.first_raw is None:
                got.first_raw = data
            js = Contract.decode(data)
            s = AxisSample.from_joint_state(js)
            got.append(Sample(s.stamp_ns, s.axis, js.name, s.position_m, s.velocity_m_s))

        reliability = ReliabilityPolicy.BEST_EFFORT if best_effort else ReliabilityPolicy.RELIABLE
        qos = QoSProfile(depth=10_000, reliability=reliability)
        self.node.create_subscription(JointState, f"/axisflow/{axis}/joint_states", on_message, qos, raw=True)
        return got

    def diagnostics(self) -> list[Status]:
        from diagnostic_msgs.msg import DiagnosticArray

        got: list[Status] = []

        def on_message(m: DiagnosticArray) -> None:
            for s in m.status:
                got.append(
                    Status(s.level[0], s.name, s.message, s.hardware_id, {v.key: v.value for v in s.values})
                )

        self.node.create_subscription(DiagnosticArray, "/diagnostics", on_message, 100)
        return got

    def client(self, service: str):
        """A Trigger client of ``service``, for :meth:`call` (made early, it finds the service while
        the test waits for other things)."""
        from std_srvs.srv import Trigger

        return self.node.create_client(Trigger, service)

    def call(self, client, timeout_s: float = 30.0):
        from std_srvs.srv import Trigger

        service = client.srv_name
        self.spin_until(client.service_is_ready, timeout_s, f"the service {service}")
        future = client.call_async(Trigger.Request())
        self.spin_until(future.done, timeout_s, f"the answer of {service}")
        return future.result()

    def close(self) -> None:
        self.executor.shutdown()
        self.node.destroy_node()
        self.context.try_shutdown()


@pytest.fixture
def ros(tmp_path, monkeypatch):
    """This test's :class:`RosPeer`, made before the axisflow processes, its DDS participant announcing
    itself every 0.2 s (:data:`PEER_PROFILE`; the node keeps Fast DDS's defaults)."""
    profile = tmp_path / "fastdds-peer.xml"
    profile.write_text(PEER_PROFILE)
    with monkeypatch.context() as env:  # read once, as this process's first participant is made
        env.setenv("FASTRTPS_DEFAULT_PROFILES_FILE", str(profile))
        peer = RosPeer()
    yield peer
    peer.close()


def latest(statuses: list[Status], kind: str) -> Status | None:
    mine = [s for s in statuses if s.name == f"axisflow_a0: {kind}"]
    return mine[-1] if mine else None


def start_axis(cli, port: int, *node_args: str, speed: float = 1.0):
    """A simulated axis's bridge (at ``speed`` × real time) and its ROS 2 node, both ready: started
    together, the node's session connects to the bridge once the bridge listens (a session that must
    connect retries: :mod:`axisflow.acquisition.bus.session`)."""
    bridge = cli.start(
        "bridge", "--sim", "--speed", f"{speed:g}", "--listen", f"tcp/127.0.0.1:{port}", ready=True
    )
    node = cli.start(
        "ros2", "--axis", "a0", "--connect", f"tcp/127.0.0.1:{port}", "--json", *node_args, ready=True
    )
    cli.wait_ready(bridge, 90)
    cli.wait_ready(node, 90)
    return bridge, node


def at_rest_at(states: list[Sample], x: float):
    """A predicate: the latest sample is at rest within 20 µm of ``x``."""
    return lambda: abs(states[-1].position_m - x) < 2e-5 and abs(states[-1].velocity_m_s) < 1e-3


def trajectory(*points):
    from builtin_interfaces.msg import Duration
    from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

    message = JointTrajectory()
    message.joint_names = ["carriage"]
    for x, t_s in points:
        ns = round((t_s or 0.0) * NS)
        message.points.append(
            JointTrajectoryPoint(positions=[x], time_from_start=Duration(sec=ns // NS, nanosec=ns % NS))
        )
    return message


@inside_only
def test_inside_every_sample_reaches_a_subscriber_and_diagnostics_follow_the_bridge(cli, port, ros):
    from rclpy.serialization import deserialize_message
    from sensor_msgs.msg import JointState

    assert private_network.interfaces() == ["lo"]  # discovery has nowhere else to go
    states, diagnostics = ros.joint_states(), ros.diagnostics()
    sensor_data = ros.joint_states(best_effort=True)  # as qos_profile_sensor_data asks: it matches too
    bridge, node = start_axis(cli, port)  # in real time: this subscriber keeps up with 1 kHz
    ros.spin_until(lambda: len(states) >= 3000, 60, "3000 JointState messages")
    received = list(states)
    assert len(sensor_data) > 1000, "a best-effort subscriber did not match the node's reliable publisher"
    ros.spin_until(lambda: latest(diagnostics, "drive") is not None, 10, "the drive's diagnostics")
    drive = latest(diagnostics, "drive")
    cli.launcher.stop(bridge)
    ros.spin_until(lambda: latest(diagnostics, "drive").level == 3, 20, "the drive's diagnostics going STALE")
    stale = latest(diagnostics, "drive")
    node.send_signal(signal.SIGINT)
    out, err = cli.finish(node, 60)
    report = json.loads(out)
    assert node.returncode == 0, err
    assert {(s.frame_id, s.names) for s in received} == {("a0", ("carriage", "motor"))}
    message = deserialize_message(states.first_raw, JointState)  # what any ROS 2 subscriber gets
    assert (message.header.frame_id, list(message.name)) == ("a0", ["carriage", "motor"])
    assert message.header.stamp.sec * NS + message.header.stamp.nanosec == received[0].stamp_ns
    # every sample the node received reached this subscriber, in order: a gap in the drive stamps is
    # one the node counted as lost on the Zenoh leg (the bridge drops telemetry a loaded reader cannot
    # take within 1 ms; docs/ros2.md)
    steps = [(b.stamp_ns - a.stamp_ns) // TICK_NS for a, b in itertools.pairwise(received)]
    assert min(steps) >= 1, f"samples out of order or repeated: {[s for s in steps if s < 1][:5]}"
    missing = sum(step - 1 for step in steps)
    assert missing <= report["samples_lost"], f"{missing} samples missing, the node lost {report}"
    assert report["samples_malformed"] == 0
    assert report["samples_published"] == report["samples_received"] >= len(received)
    assert (drive.level, drive.hardware_id, drive.message) == (0, "a0", "the drive follows setpoints")
    assert drive.values["bridge"] == "running"
    assert int(drive.values["samples lost on Zenoh"]) <= report["samples_lost"]
    assert (stale.level, stale.message) == (3, "no bridge runs axis 'a0'")


@inside_only
def test_inside_the_samples_are_decimated_to_the_rate_on_the_drive_clock(cli, port, ros):
    assert private_network.interfaces() == ["lo"]
    states = ros.joint_states()
    # the drive's clock runs at 4× real time: the node decimates on it, not on the wall clock
    _bridge, node = start_axis(cli, port, "--rate", "100", speed=4)
    ros.spin_until(lambda: len(states) >= 200, 60, "200 JointState messages at 100 Hz")
    node.send_signal(signal.SIGINT)
    out, _err = cli.finish(node, 60)
    report = json.loads(out)
    # one sample per 10 ms period of drive time, the period's first: its first tick unless the node
    # lost that sample on the Zenoh leg (then the next one that arrived)
    periods = [s.stamp_ns // (10 * TICK_NS) for s in states]
    skipped = sum(b - a - 1 for a, b in itertools.pairwise(periods))
    assert all(b > a for a, b in itertools.pairwise(periods)), "two samples of one period, or out of order"
    assert skipped * 10 <= report["samples_lost"], f"{skipped} periods without a sample; {report}"
    # the node's first sample opens its first period wherever the node joined the stream, off the
    # grid: this subscriber, matched while the node started, may have it
    off_grid = sum(1 for s in states[1:] if s.stamp_ns % (10 * TICK_NS))
    assert off_grid <= report["samples_lost"], f"{off_grid} samples off the 10 ms grid; {report}"
    # as many as the periods the samples the node saw span (its first, then the boundaries crossed),
    # less those whose every sample was lost (at most one per 10 lost)
    span, lost = report["samples_received"] + report["samples_lost"] - 1, report["samples_lost"]
    assert span // 10 + 1 - lost // 10 <= report["samples_published"] <= -(-span // 10) + 1, report


@inside_only
def test_inside_trajectories_arrive_when_asked_are_refused_when_too_fast_and_stop_on_the_service(
    cli, port, ros
):
    import zenoh
    from axisflow.acquisition import AxisKeys, MoveState, MoveStatus
    from axisflow.acquisition.bus.readiness import JoinedSubscriber
    from axisflow.acquisition.bus.session import ZenohOptions, open_session
    from trajectory_msgs.msg import JointTrajectory

    assert private_network.interfaces() == ["lo"]
    states, diagnostics = ros.joint_states(), ros.diagnostics()
    publisher = ros.node.create_publisher(JointTrajectory, "/axisflow/a0/joint_trajectory", 10)
    quick_stop = ros.client("/axisflow/a0/quick_stop")
    # 100 Hz is plenty to watch moves (the bridge's statuses give the exact ticks), and lets this
    # process's subscriber keep up on a machine that others load; every duration checked is one of
    # drive time (ticks, stamps), which runs at 4× real time
    _bridge, node = start_axis(cli, port, "--rate", "100", speed=4)
    ros.spin_until(lambda: publisher.get_subscription_count() >= 1, 30, "the node's trajectory subscription")
    ros.spin_until(lambda: len(states) > 0, 30, "a JointState")
    keys = AxisKeys("a0")
    with (
        open_session(ZenohOptions.loopback(connect_port=port)) as session,
        JoinedSubscriber(session, keys.event, lambda: zenoh.handlers.FifoChannel(10_000)) as events,
    ):
        # way point 0 as fast as the planner makes it, way point 1 at 2.5 s after the start
        publisher.publish(trajectory((0.4, None), (0.15, 2.5)))
        ros.spin_until(at_rest_at(states, 0.15), 30, "the axis at rest at 0.15 m")
        ros.spin_until(lambda: "done" in latest(diagnostics, "motion").message, 10, "the trajectory done")
        statuses = [MoveStatus.decode(s.payload.to_bytes()) for s in iter(events.subscriber.try_recv, None)]
    started = [s for s in statuses if s.state is MoveState.STARTED]
    completed = [s for s in statuses if s.state is MoveState.COMPLETED]
    assert len(started) == len(completed) == 2
    assert completed[-1].end_tick - started[0].tick == 2500  # arrives 2.5 s after the start, to the tick
    # the same, as a ROS 2 node sees it: the carriage leaves 0 m and settles at 0.15 m 2.5 s later
    # (within a micrometre of where it rests, a few encoder counts off 0.15 m: the plant is not the
    # model; the poly5 law spends ~5 ms leaving and ~15 ms arriving at that scale)
    rest = states[-1].position_m
    leave = next(s.stamp_ns for s in states if s.position_m > 1e-6)
    arrive = next(s.stamp_ns for s in states if s.stamp_ns > leave + NS and abs(s.position_m - rest) < 1e-6)
    assert 2.45 <= (arrive - leave) / NS <= 2.55
    assert (
        latest(diagnostics, "motion").message
        == "trajectory 1 done: at point 1 (0.15 m), 2.500 s after its start"
    )

    publisher.publish(trajectory((0.75, 0.1)))  # 0.6 m in 0.1 s: faster than any poly5 move
    ros.spin_until(lambda: latest(diagnostics, "motion").level == 1, 10, "the refusal on /diagnostics")
    refusal = latest(diagnostics, "motion")
    assert refusal.hardware_id == "a0" and refusal.message.startswith(
        "trajectory refused: point 0 asks to arrive 0.1 s"
    )
    assert (
        "faster than the fastest poly5 move" in refusal.message
        and refusal.values["trajectories refused"] == "1"
    )

    # slow (30 s of drive time, 7.5 s here), so that the quick stop comes while it moves, however late
    # this process sees it
    since = len(diagnostics)
    publisher.publish(trajectory((0.75, 30.0)))

    def moving_or_failed() -> bool:
        news = [s for s in diagnostics[since:] if s.name == "axisflow_a0: motion"]
        return states[-1].velocity_m_s > 0.005 or any(s.level > 0 for s in news)

    ros.spin_until(moving_or_failed, 60, "the axis moving towards 0.75 m")
    assert states[-1].velocity_m_s > 0.005, latest(diagnostics, "motion")
    answer = ros.call(quick_stop)
    assert answer.success and answer.message.startswith("quick stop: at rest at "), answer.message
    assert "bridge tick" in answer.message and "drive time" in answer.message and "setpoint" in answer.message
    stopped_at = float(answer.message.removeprefix("quick stop: at rest at ").split(" m")[0])
    ros.spin_until(at_rest_at(states, stopped_at), 30, f"the axis at rest at {stopped_at} m")
    assert 0.15 < stopped_at < 0.7
    node.send_signal(signal.SIGINT)
    out, err = cli.finish(node, 60)
    report = json.loads(out)
    assert (report["trajectories_sent"], report["trajectories_done"], report["trajectories_refused"]) == (
        2,
        1,
        1,
    )
    assert report["quick_stops"] == 1
    assert "trajectory refused: point 0 asks to arrive 0.1 s" in err  # the node's log says it too


@pytest.mark.timeout(300)
@inside_only
def test_inside_a_drive_fault_is_an_error_on_diagnostics_until_the_reset_service(cli, port, ros, tmp_path):
    assert private_network.interfaces() == ["lo"]
    config = tmp_path / "drive.toml"
    config.write_text(CANOPEN_CONFIG)
    diagnostics = ros.diagnostics()
    reset_fault = ros.client("/axisflow/a0/reset_fault")
    # the node first (it listens; the bridge connects to it): it watches the bridge from its first
    # tick, so that it sees the drive follow setpoints before the fault, FAULT_AT_S of drive time
    # after the master made it operational
    drive = cli.start("drive-sim", "--drive-config", str(config), "--fault-at", f"{FAULT_AT_S:g}:4310")
    node = cli.start("ros2", "--axis", "a0", "--listen", f"tcp/127.0.0.1:{port}", ready=True)
    booted = lambda: "booted (pre-operational)" in drive.stderr_text()  # noqa: E731
    assert wait_until(booted, 60), f"the simulated drive did not boot: {drive.stderr_text()[-2000:]}"
    cli.wait_ready(node, 90)
    bridge = cli.start(
        "bridge", "--drive-config", str(config), "--connect", f"tcp/127.0.0.1:{port}", ready=True
    )
    cli.wait_ready(bridge, 120)
    # STALE (no bridge, then no sample yet) until the samples flow: then OK, or already the fault
    ros.spin_until(
        lambda: latest(diagnostics, "drive") is not None and latest(diagnostics, "drive").level < 3,
        30,
        "the drive's diagnostics with the bridge running",
    )
    assert latest(diagnostics, "drive").level == 0, (
        f"the node did not see the drive follow setpoints before the fault at {FAULT_AT_S:g} s of drive "
        f"time (raise it later): {latest(diagnostics, 'drive')}"
    )
    ros.spin_until(lambda: latest(diagnostics, "drive").level == 2, 120, "the drive's fault as an ERROR")
    fault = latest(diagnostics, "drive")
    assert fault.hardware_id == "a0" and "drive temperature too high" in fault.message
    assert (fault.values["last drive event"], fault.values["error_code"]) == ("FAULT", "0x4310")
    answer = ros.call(reset_fault)
    assert answer.success and "operation enabled" in answer.message, answer.message
    ros.spin_until(lambda: latest(diagnostics, "drive").level == 0, 15, "the drive OK again")
    assert latest(diagnostics, "drive").values["last drive event"] == "ENABLED"
    for process in (node, bridge, drive):
        process.send_signal(signal.SIGINT)
        cli.finish(process, 60)
        assert process.returncode == 0, process.stderr_text()[-2000:]
