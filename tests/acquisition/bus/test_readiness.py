"""Readiness on facts, over real Zenoh sessions and real bridge processes: a subscriber that joins a
running publisher misses nothing, over many joins; a publisher's first messages after a match all
arrive; a hello that is not answered says who was silent; the matching watch follows subscribers."""

import threading
import time

import pytest
import zenoh
from axisflow.acquisition import AxisKeys, MoveSender, MoveState, ZenohOptions, load_plant, open_session
from axisflow.acquisition.bus.publisher import SequencedPublisher, Traffic, wait_for_subscribers
from axisflow.acquisition.bus.readiness import (
    JoinedSubscriber,
    NotReadyError,
    confirm_delivery,
    say_hello,
    wait_for_token,
)
from axisflow.acquisition.wire.attachment import unpack_attachment
from axisflow.acquisition.wire.keys import hello_key, recorder_token
from axisflow.acquisition.wire.sequence import SequenceTracker
from axisflow.model import default_params

from axisflow.deploy.processes import wait_until

JOINS = 40
"""joins per test: without the hellos, 6–10 in 100 lost a run of samples (docs/acquisition.md)"""


def _collect(sub, trackers: dict[str, SequenceTracker], samples: int, timeout_s: float = 20.0) -> None:
    """Read ``samples`` samples from a subscriber, counting each key's sequence numbers."""

    def enough() -> bool:
        while (sample := sub.try_recv()) is not None:
            seq, _stamp, gid = unpack_attachment(sample.attachment.to_bytes())
            trackers.setdefault(str(sample.key_expr), SequenceTracker()).add(gid, seq)
        return sum(t.messages for t in trackers.values()) >= samples

    assert wait_until(enough, timeout_s, 0.0005), {k: t.messages for k, t in trackers.items()}


@pytest.mark.parametrize("speed", ["0", "1"])
@pytest.mark.slow
@pytest.mark.heavy
def test_a_subscriber_joining_a_running_bridge_misses_no_sample(cli, port, speed):
    """A fresh session joins a running bridge again and again (the case that lost samples): at speed 0
    the bridge runs flat out for a keeper subscriber; at speed 1 at 1 kHz. No join has a gap."""
    bridge = cli.start("bridge", "--sim", "--speed", speed, "--listen", f"tcp/127.0.0.1:{port}", ready=True)
    cli.wait_ready(bridge)
    keys = AxisKeys()
    samples = 2000 if speed == "0" else 200
    with (
        open_session(ZenohOptions.loopback(connect_port=port)) as keeper,
        keeper.declare_subscriber(keys.state, zenoh.handlers.RingChannel(1)),
    ):
        gaps = []
        for _ in range(JOINS):
            trackers: dict[str, SequenceTracker] = {}
            with (
                open_session(ZenohOptions.loopback(connect_port=port)) as session,
                JoinedSubscriber(
                    session, f"{keys.prefix}/{keys.axis}/*", lambda: zenoh.handlers.FifoChannel(1 << 16)
                ) as joined,  # fmt: skip
            ):
                assert [h.key for h in joined.report.publishers if h.key == keys.state] == [keys.state]
                _collect(joined.subscriber, trackers, samples)
            gaps.append({k: t.missed for k, t in trackers.items() if t.missed})
            assert set(trackers) >= {keys.state, keys.setpoint}
    assert gaps == [{}] * JOINS
    assert bridge.poll() is None


@pytest.mark.slow
@pytest.mark.heavy
def test_messages_published_once_a_subscriber_matches_all_arrive(port):
    """The publisher waits for Zenoh's matching listener, then publishes at once (no settling time):
    every message, from the first, reaches a subscriber that was already there — over many new
    publisher sessions."""
    with open_session(ZenohOptions.loopback(listen_port=port)) as listener:
        sub = listener.declare_subscriber("axisflow/t/**", zenoh.handlers.FifoChannel(1 << 16))
        for attempt in range(30):
            key = f"axisflow/t/{attempt}"
            with (
                open_session(ZenohOptions.loopback(connect_port=port)) as session,
                SequencedPublisher(session, key, "sensor_msgs/msg/JointState", Traffic.BULK) as pub,
            ):
                assert wait_for_subscribers([pub], 10.0)
                for _ in range(100):
                    pub.put(b"\x00\x01\x00\x00")
                trackers: dict[str, SequenceTracker] = {}
                _collect(sub, trackers, 100)
            (tracker,) = trackers.values()
            (first,) = tracker.publishers.values()
            assert (first.first, first.last, tracker.missed) == (1, 100, 0), attempt
        sub.undeclare()


@pytest.mark.slow
@pytest.mark.heavy
def test_a_sender_is_ready_for_the_bridge_when_it_says_so(cli, port):
    """Right after wait_for_bridge, a new sender's first move is accepted and its statuses reach it —
    over many senders, each on a fresh session (the bridge's token and a hello are the facts)."""
    bridge = cli.start("bridge", "--sim", "--listen", f"tcp/127.0.0.1:{port}", "--json", ready=True)
    cli.wait_ready(bridge)
    x = load_plant(None, default_params()).simulation.initial_position_m
    for attempt in range(20):
        with (
            open_session(ZenohOptions.loopback(connect_port=port)) as session,
            MoveSender(session, AxisKeys()) as sender,
        ):
            assert sender.wait_for_bridge(10.0)
            x_to = x + (0.01 if attempt % 2 == 0 else -0.01)
            cmd = sender.send(x, x_to, 0.1)  # 1 cm in 0.1 s: the shortest duration the planner gives a move
            x = x_to
            status = sender.wait_status(cmd.move_id, {MoveState.COMPLETED}, 10.0)
            assert status is not None and status.state is MoveState.COMPLETED, (attempt, sender.statuses)
            assert [s.state for s in sender.statuses[:2]] == [MoveState.ACCEPTED, MoveState.STARTED]
    bridge.send_signal(2)
    out, err = cli.finish(bridge)
    assert '"moves_missed": 0' in out and '"moves_rejected": 0' in out, err


def test_a_hello_that_is_not_answered_names_who_answered_and_who_did_not(port):
    """(The asking session opens after the publishers: it knows their queryables from the answer to its
    initial interest, as a joining recorder does.)"""
    with (
        open_session(ZenohOptions.loopback(listen_port=port)) as quiet,
        SequencedPublisher(
            quiet, "axisflow/a0/state", "sensor_msgs/msg/JointState", Traffic.TELEMETRY
        ) as pub,
    ):
        with open_session(ZenohOptions.loopback(connect_port=port)) as asking:
            answered = say_hello(asking, "axisflow/**", 5.0)
        assert [(h.key, h.publisher, h.zid) for h in answered.hellos] == [
            ("axisflow/a0/state", pub.gid.hex(), str(quiet.info.zid()))
        ]
        held: list[zenoh.Query] = []  # a publisher that never answers
        mute = quiet.declare_queryable(hello_key("axisflow/a0/setpoint", b"\x01" * 16), held.append)
        try:
            with (
                open_session(ZenohOptions.loopback(connect_port=port)) as asking,
                pytest.raises(NotReadyError) as refused,
            ):
                say_hello(asking, "axisflow/**", 0.5)
        finally:
            held.clear()
            mute.undeclare()
    message = str(refused.value)
    assert "did not all answer the hello" in message and "within 0.5 s" in message
    assert "answered: axisflow/a0/state" in message  # the one that did is named


def test_a_hello_ends_at_once_when_its_stop_is_set(port):
    stop = threading.Event()
    with open_session(ZenohOptions.loopback(listen_port=port)) as quiet:
        held: list[zenoh.Query] = []
        mute = quiet.declare_queryable(hello_key("axisflow/a0/state", b"\x02" * 16), held.append)
        stop.set()
        try:
            with open_session(ZenohOptions.loopback(connect_port=port)) as asking:
                t0 = time.monotonic()
                assert say_hello(asking, "axisflow/**", 30.0, stop) is None
                assert time.monotonic() - t0 < 5.0  # not the 30 s of its time-out
        finally:
            held.clear()
            mute.undeclare()


def test_the_matching_watch_follows_subscribers_coming_and_going(port):
    with (
        open_session(ZenohOptions.loopback(listen_port=port)) as pub_session,
        open_session(ZenohOptions.loopback(connect_port=port)) as sub_session,
        SequencedPublisher(
            pub_session, "axisflow/a0/state", "sensor_msgs/msg/JointState", Traffic.BULK
        ) as pub,
        pub.watch_matching() as watch,
    ):
        assert not watch.matched
        sub = sub_session.declare_subscriber("axisflow/**", zenoh.handlers.RingChannel(1))
        assert watch.wait(10.0)
        sub.undeclare()
        assert wait_until(lambda: not watch.matched, 10.0)


def test_a_ready_recorder_holds_its_token(cli, tmp_path, port):
    rec = cli.start("record", "-o", str(tmp_path / "r.mcap"), "--listen", f"tcp/127.0.0.1:{port}", ready=True)
    cli.wait_ready(rec)
    with open_session(ZenohOptions.loopback(connect_port=port)) as session:
        import socket

        assert wait_for_token(session, recorder_token(socket.gethostname(), rec.pid), 10.0)
        assert not wait_for_token(session, recorder_token(socket.gethostname(), rec.pid + 1), 0.2)
    rec.send_signal(2)
    cli.finish(rec)
    assert rec.returncode == 0


@pytest.mark.parametrize("traffic", [Traffic.BULK, Traffic.COMMAND])
def test_a_confirmed_delivery_means_everything_sent_before_is_in_the_subscribers_channel(port, traffic):
    """A publisher that starts as soon as a joined subscriber matches can already ask for its receipt
    (the receipt queryable is declared before the subscriber), and the answer comes only once every
    sample put before the question is in the subscriber's channel: counted there without waiting.
    (Telemetry is left out: it drops on congestion by design, so on a busy machine not every sample
    put is sent.)"""
    n = 20_000
    with (
        open_session(ZenohOptions.loopback(listen_port=port)) as publishing,
        open_session(ZenohOptions.loopback(connect_port=port)) as subscribing,
        SequencedPublisher(publishing, "axisflow/a0/state", "sensor_msgs/msg/JointState", traffic) as pub,
        JoinedSubscriber(subscribing, "axisflow/**", lambda: zenoh.handlers.FifoChannel(n + 10)) as joined,
    ):
        assert wait_for_subscribers([pub], 10.0)
        payload = bytes(200)
        for _ in range(n):
            pub.put(payload)
        assert confirm_delivery(publishing, [pub.priority]) == 1
        taken = 0
        while joined.subscriber.try_recv() is not None:
            taken += 1
        assert taken == n


def test_delivery_is_confirmed_at_once_when_no_subscriber_listens(port):
    with open_session(ZenohOptions.loopback(listen_port=port)) as session:
        assert confirm_delivery(session, [zenoh.Priority.DATA, zenoh.Priority.DATA_HIGH], timeout_s=30.0) == 0
