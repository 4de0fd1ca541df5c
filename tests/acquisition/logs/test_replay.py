"""Replay over real Zenoh sessions: the recorded pace (publish times), the --keys filter, and moves
never replayed to a live drive."""

import time

import pytest
import zenoh
from axisflow.acquisition import (
    JOINT_STATE_TYPE,
    MOVE_TYPE,
    AxisSample,
    MoveCommand,
    ZenohOptions,
    open_session,
)
from axisflow.acquisition.logs.mcap_writer import Ros2McapWriter
from axisflow.acquisition.logs.replay import replay

from axisflow.deploy.processes import wait_until

T0 = 1_700_000_000_000_000_000
MS = 1_000_000


@pytest.fixture
def recording(tmp_path):
    """200 states (publish times 1 ms apart, log times in bursts of 50), 200 setpoints, 2 moves."""
    path = tmp_path / "session.mcap"
    writer = Ros2McapWriter(path)
    state = writer.channel_for("/axisflow/a0/state", JOINT_STATE_TYPE)
    setpoint = writer.channel_for("/axisflow/a0/setpoint", JOINT_STATE_TYPE)
    moves = writer.channel_for("/axisflow/a0/trajectory", MOVE_TYPE)
    for k in range(200):
        publish = T0 + k * MS
        log = T0 + (k // 50) * 50 * MS + 3 * MS  # the recorder wrote them in bursts
        sample = AxisSample(publish, "a0", 0.1, 0.0, 0.0, 2.5, 0.0, 0.0).encode()
        writer.add(state, log, publish, k + 1, sample)
        writer.add(setpoint, log, publish, k + 1, sample)
        if k in (10, 20):
            cmd = MoveCommand(publish, "a0", k, 0, "poly5", 0.1, 0.2, 0.5)
            writer.add(moves, log, publish, k // 10, cmd.encode())
    writer.finish()
    return path


def _received(sub) -> list:
    out = []
    while (s := sub.try_recv()) is not None:
        out.append((str(s.key_expr), time.monotonic_ns()))
    return out


class _Arrivals(list):
    """A subscriber callback that notes each key with its arrival time (on Zenoh's thread)."""

    def __call__(self, sample) -> None:
        self.append((str(sample.key_expr), time.monotonic_ns()))


def test_replay_keeps_the_publish_pace_filters_keys_and_skips_moves(recording, port):
    with (
        open_session(ZenohOptions.loopback(listen_port=port)) as listener,
        open_session(ZenohOptions.loopback(connect_port=port)) as player,
        listener.declare_subscriber("axisflow/**", got := _Arrivals()),
    ):
        report = replay(player, recording, speed=1.0, wait_subscribers_s=10.0, keys="axisflow/*/state")
        assert wait_until(lambda: len(got) >= 200, 10.0)
    assert (report.messages, report.skipped_moves, report.skipped_keys) == (200, 2, 200)
    assert "skipped 2 moves (commands to a drive are never replayed)" in report.format()
    assert {key for key, _t in got} == {"axisflow/a0/state"}
    assert len(got) == 200
    arrivals = [t for _key, t in got]
    # paced by publish time (199 ms from first to last), not by the recorder's bursts of log times
    assert 0.17e9 <= arrivals[-1] - arrivals[0] <= 0.5e9
    assert arrivals[100] - arrivals[0] >= 0.08e9


def test_replay_as_fast_as_possible_waits_for_a_subscriber_first(recording, port):
    with (
        open_session(ZenohOptions.loopback(listen_port=port)) as listener,
        open_session(ZenohOptions.loopback(connect_port=port)) as player,
    ):
        early = replay(player, recording, speed=0.0, wait_subscribers_s=0.5)
        assert early.messages == 400  # nobody subscribed: published anyway after the wait, lost
        with listener.declare_subscriber("axisflow/**", zenoh.handlers.FifoChannel(10_000)) as sub:
            report = replay(player, recording, speed=0.0, wait_subscribers_s=10.0)
            got: list = []

            def all_there() -> bool:
                got.extend(_received(sub))
                return len(got) >= 400

            assert wait_until(all_there, 10.0)
    assert report.messages == 400 and report.skipped_moves == 2
    assert len(got) == 400


def test_a_topic_that_is_no_zenoh_key_is_skipped(tmp_path, port):
    path = tmp_path / "other_tool.mcap"
    writer = Ros2McapWriter(path)
    odd = writer.channel_for("/weird//topic", JOINT_STATE_TYPE)
    good = writer.channel_for("/axisflow/a0/state", JOINT_STATE_TYPE)
    sample = AxisSample(T0, "a0", 0.1, 0.0, 0.0, 2.5, 0.0, 0.0).encode()
    writer.add(odd, T0, T0, 1, sample)
    writer.add(good, T0, T0, 1, sample)
    writer.finish()
    with open_session(ZenohOptions.loopback(listen_port=port)) as player:
        report = replay(player, path, speed=0.0)
    assert (report.messages, report.skipped_keys) == (1, 1)


def test_a_damaged_chunk_is_skipped_named_and_the_replay_goes_on(tmp_path, port, damage):
    whole, damaged = tmp_path / "whole.mcap", tmp_path / "damaged.mcap"
    writer = Ros2McapWriter(whole, chunk_size=8192)
    state = writer.channel_for("/axisflow/a0/state", JOINT_STATE_TYPE)
    for k in range(2000):
        writer.add(
            state, T0 + k * MS, T0 + k * MS, k + 1, AxisSample(T0 + k * MS, "a0", 0.1, 0, 0, 0, 0, 0).encode()
        )
    writer.finish()
    offset = damage.damage(whole, damaged, 3, "crc")
    heard = []
    with open_session(ZenohOptions.loopback(listen_port=port)) as player:
        report = replay(player, damaged, speed=0.0, progress=heard.append)
    (skipped,) = report.skipped_chunks
    assert (skipped.chunk.ordinal, skipped.chunk.offset) == (4, offset)
    assert report.messages == 2000 - skipped.messages and skipped.messages > 50
    assert f"skipped 1 chunk(s) that could not be read ({skipped.messages} messages not replayed)" in (
        report.format()
    )
    assert heard and heard[0].messages == 1 and heard[0].recorded_span_s == pytest.approx(1.999)
