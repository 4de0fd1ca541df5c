"""The recorder's MCAP writer: files every reader reads, flushed data that survives a crash, and a
backlog that stays bounded (messages dropped whole, counted, recorded in the file)."""

import itertools
import random
import shutil
import threading

import pytest
from axisflow.acquisition import read_joint_states, read_messages
from axisflow.acquisition.logs import recording_writer
from axisflow.acquisition.logs.recording_writer import LOSS_METADATA, RecordingWriter
from axisflow.acquisition.wire.messages import AxisSample
from mcap.reader import NonSeekingReader, make_reader

TOPICS = ("/axisflow/a0/state", "/axisflow/a0/setpoint", "/axisflow/a0/event")


def _messages(n: int, seed: int = 3) -> list[tuple[str, int, int, int, bytes]]:
    """(topic, log time, publish time, sequence, data): interleaved topics, JointStates and odd sizes."""
    rng = random.Random(seed)
    out = []
    for i in range(n):
        topic = TOPICS[i % 3]
        if topic == "/axisflow/a0/event":
            data = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 300)))
        else:
            data = AxisSample(10**18 + i, "a0", rng.random(), 0.1, 12.0, 133.0, 33.0, 0.05).encode()
        out.append((topic, 10**18 + 1000 * i, 10**18 + 1000 * i - 7, i // 3 + 1, data))
    return out


def _write(path, messages, **kw) -> RecordingWriter:
    writer = RecordingWriter(path, **kw)
    for topic, log_ns, pub_ns, seq, data in messages:
        type_name = None if topic.endswith("event") else "sensor_msgs/msg/JointState"
        channel = writer.channel_for(topic, type_name, "cdr")
        writer.add(channel, log_ns, pub_ns, seq, data)
    return writer


@pytest.mark.parametrize("compression", ["zstd", "lz4", "none"])
def test_every_message_reads_back_with_mcap_and_our_reader(tmp_path, compression):
    path = tmp_path / "x.mcap"
    messages = _messages(5000)
    _write(path, messages, compression=compression, chunk_size=16384).finish()
    with open(path, "rb") as fh:
        reader = make_reader(fh)  # seeking: summary, chunk and message indexes
        got = [
            (ch.topic, m.log_time, m.publish_time, m.sequence, m.data)
            for _s, ch, m in reader.iter_messages(log_time_order=False)
        ]
        summary = reader.get_summary()
        assert summary.statistics.message_count == len(messages)
        assert len(summary.chunk_indexes) > 10
        counts = {summary.channels[c].topic: n for c, n in summary.statistics.channel_message_counts.items()}
        assert counts == {t: sum(m[0] == t for m in messages) for t in TOPICS}
        log_times = [m[1] for m in messages]
        spans = [(c.message_start_time, c.message_end_time) for c in summary.chunk_indexes]
        assert spans[0][0] == log_times[0] and spans[-1][1] == log_times[-1]
        assert all(end < start for (_s, end), (start, _e) in itertools.pairwise(spans))
        assert {c.topic for c in summary.channels.values()} == set(TOPICS)
        assert summary.schemas[1].name == "sensor_msgs/msg/JointState"
        state = next(c for c in summary.channels.values() if c.topic == TOPICS[0])
        assert state.message_encoding == "cdr" and "offered_qos_profiles" in state.metadata
        loss = [m for m in reader.iter_metadata() if m.name == LOSS_METADATA]
        assert loss[0].metadata["dropped_messages"] == "0"
    assert got == messages
    with open(path, "rb") as fh:  # a streaming read checks every CRC
        streamed = [m.data for _s, _c, m in NonSeekingReader(fh, validate_crcs=True).iter_messages()]
    assert streamed == [m[4] for m in messages]
    for topic in TOPICS:  # the log reader (its fast paths use the chunk and message indexes)
        ours = [(r.log_time_ns, r.publish_time_ns, r.sequence, r.data) for r in read_messages(path, topic)]
        assert ours == [m[1:] for m in messages if m[0] == topic]
    joints = read_joint_states(path, TOPICS[0])
    assert joints.stamp_ns.tolist() == [10**18 + i for i in range(0, 5000, 3)]


def test_a_file_cut_after_a_flush_holds_everything_flushed(tmp_path):
    path, cut = tmp_path / "x.mcap", tmp_path / "cut.mcap"
    messages = _messages(3000)
    writer = _write(path, messages[:2000], chunk_size=8192)
    writer.flush()
    shutil.copy(path, cut)  # what a SIGKILL now leaves behind
    for topic, log_ns, pub_ns, seq, data in messages[2000:]:
        writer.add(writer.channels[topic], log_ns, pub_ns, seq, data)
    writer.finish()
    got = []
    with open(cut, "rb") as fh, pytest.raises(Exception):  # noqa: B017 - no footer: the read ends in an error
        for _s, _c, m in NonSeekingReader(fh).iter_messages(log_time_order=False):
            got.append(m.data)
    assert got == [m[4] for m in messages[:2000]]


def test_a_stalled_writer_keeps_the_backlog_bounded_and_the_file_says_what_was_dropped(tmp_path, monkeypatch):
    stall = threading.Event()
    compress = recording_writer._compress

    def stalled(compression, data):  # the writer thread waits here as on a stalled disk
        stall.wait(30)
        return compress(compression, data)

    monkeypatch.setattr(recording_writer, "_compress", stalled)
    path = tmp_path / "x.mcap"
    writer = RecordingWriter(path, chunk_size=4096, backlog_bytes=32768)
    kept = []
    peak = 0
    for topic, log_ns, pub_ns, seq, data in _messages(3000):
        channel = writer.channel_for(topic, None, "cdr")
        if writer.add(channel, log_ns, pub_ns, seq, data):
            kept.append((topic, data))
        peak = max(peak, writer.backlog)
    assert peak <= 32768
    assert 0 < len(kept) < 3000
    dropped = writer.dropped
    assert sum(dropped.values()) == 3000 - len(kept)
    stall.set()
    writer.finish()
    with open(path, "rb") as fh:
        reader = make_reader(fh)
        got = [(c.topic, m.data) for _s, c, m in reader.iter_messages(log_time_order=False)]
        loss = next(m for m in reader.iter_metadata() if m.name == LOSS_METADATA).metadata
    assert got == kept
    assert loss["dropped_messages"] == str(3000 - len(kept))
    assert loss["backlog_bytes"] == "32768"
    assert {
        k.removeprefix("dropped "): int(v) for k, v in loss.items() if k.startswith("dropped /")
    } == dropped


def test_a_flush_without_waiting_returns_before_the_disk_and_a_waiting_one_after(tmp_path, monkeypatch):
    slow_disk = threading.Event()
    synced = []
    fsync = recording_writer.os.fsync

    def slow_fsync(fd):  # the writer thread waits here as on a slow disk
        slow_disk.wait(30)
        fsync(fd)
        synced.append(fd)

    monkeypatch.setattr(recording_writer.os, "fsync", slow_fsync)
    path = tmp_path / "x.mcap"
    writer = RecordingWriter(path)
    messages = _messages(50)
    for topic, log_ns, pub_ns, seq, data in messages:
        writer.add(writer.channel_for(topic, None, "cdr"), log_ns, pub_ns, seq, data)
    writer.flush(wait=False)  # returns with the fsync still held up
    assert synced == []
    waiter = threading.Thread(target=writer.flush)
    waiter.start()
    waiter.join(0.5)
    assert waiter.is_alive()  # a waiting flush waits for its fsync
    slow_disk.set()
    waiter.join(30)
    assert not waiter.is_alive() and len(synced) == 2
    streamed = []
    with open(path, "rb") as fh, pytest.raises(Exception):  # noqa: B017 - no footer yet: the read ends in an error
        for _s, _c, m in NonSeekingReader(fh).iter_messages(log_time_order=False):
            streamed.append(m.data)
    assert streamed == [m[4] for m in messages]  # what was flushed is in the file before it is finished
    writer.finish()
