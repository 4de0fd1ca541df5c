"""The ROS 2 MCAP writer: chunk indexes kept on disk (flat memory) yet a correct summary."""

import pytest
from axisflow.acquisition import AxisSample, is_complete, iter_recording
from axisflow.acquisition.logs.mcap_writer import Ros2McapWriter
from mcap.reader import make_reader
from rosbags.highlevel import AnyReader


@pytest.mark.parametrize("compression", ["zstd", "lz4", "none"])
def test_spilled_chunk_indexes_make_a_complete_summary(tmp_path, compression):
    path = tmp_path / "x.mcap"
    writer = Ros2McapWriter(path, compression, chunk_size=4096)
    channels = [writer.channel_for(f"/axisflow/a{i}/state", "sensor_msgs/msg/JointState") for i in range(3)]
    n = 0
    for _k in range(50):
        for _ in range(40):
            n += 1
            for c in channels:
                writer.add(c, n, n, n, AxisSample(n, "a", 0.1, 0.0, 0.0, 0.0, 0.0, 0.0).encode())
        writer.flush()
        assert writer._writer._Writer__chunk_indices == []  # nothing held in memory after a flush
    writer.finish()
    assert is_complete(path)
    with open(path, "rb") as fh:
        reader = make_reader(fh)
        summary = reader.get_summary()
        assert len(summary.chunk_indexes) == summary.statistics.chunk_count > 50
        assert summary.statistics.message_count == 3 * n
        seqs = [m.sequence for _s, _c, m in reader.iter_messages(topics=["/axisflow/a1/state"])]
    assert seqs == list(range(1, n + 1))
    assert sum(1 for _ in iter_recording(path)) == 3 * n
    with AnyReader([path]) as bag:
        assert {c.msgcount for c in bag.connections} == {n}
    assert not list(tmp_path.glob(".axisflow-chunk-index-*"))  # the spill file is gone


def test_a_second_writer_on_a_file_being_recorded_is_refused_before_it_truncates(tmp_path):
    from axisflow.acquisition import RecordingError

    path = tmp_path / "busy.mcap"
    first = Ros2McapWriter(path)
    channel = first.channel_for("/axisflow/a0/state", "sensor_msgs/msg/JointState")
    first.add(channel, 1, 1, 1, AxisSample(1, "a", 0.1, 0.0, 0.0, 0.0, 0.0, 0.0).encode())
    first.flush()
    size = path.stat().st_size
    with pytest.raises(RecordingError, match="is being recorded by another process"):
        Ros2McapWriter(path)
    assert path.stat().st_size == size  # not truncated
    first.finish()
    assert is_complete(path)
