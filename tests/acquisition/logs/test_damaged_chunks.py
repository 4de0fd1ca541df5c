"""Chunks that cannot be read: real files with one chunk damaged on disk (bytes flipped in the
compressed data, a wrong CRC, the compressed data cut short) are read around it — every reader says
which chunk, where, why and what it lost, and leaves a hole where it was — and ``recover`` salvages
every other chunk into a file that mcap, rosbags and rerun open, or writes nothing."""

from __future__ import annotations

import contextlib
import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from axisflow.acquisition import (
    DamagedLogWarning,
    RecordingError,
    SkippedChunk,
    is_complete,
    iter_recording,
    list_topics,
    read_joint_states,
    read_messages,
    recover,
)
from axisflow.acquisition.logs.synthetic_log import SyntheticLogSpec, write_synthetic_log
from axisflow.acquisition.wire.messages import JOINT_STATE_TYPE, JointState
from mcap.records import Channel, Chunk, Message
from mcap.stream_reader import StreamReader, breakup_chunk
from mcap.writer import IndexType
from mcap.writer import Writer as McapWriter

STATE, SETPOINT = "/axisflow/a0/state", "/axisflow/a0/setpoint"
COLUMNS = ("stamp_ns", "log_time_ns", "publish_time_ns", "sequence", "position", "velocity", "effort")
DAMAGED = 4
"""the chunk (from 0) damaged in the tests"""


@pytest.fixture(scope="module")
def log(tmp_path_factory) -> Path:
    """3 s of our two topics (6000 messages) in 64 KiB zstd chunks: ~15 chunks."""
    path = tmp_path_factory.mktemp("damaged") / "axis.mcap"
    write_synthetic_log(path, SyntheticLogSpec(duration_s=3.0, chunk_size=64 * 1024))
    return path


def chunk_counts(path: Path, chunk: int) -> dict[str, int]:
    """Messages per topic in chunk number ``chunk`` (from 0) of a sound file, by mcap's reader."""
    channels, chunks = {}, []
    with open(path, "rb") as fh:
        for record in StreamReader(fh, emit_chunks=True).records:
            if isinstance(record, Channel):
                channels[record.id] = record.topic
            elif isinstance(record, Chunk):
                chunks.append(record)
    out: dict[str, int] = {}
    for record in breakup_chunk(chunks[chunk]):
        if isinstance(record, Message):
            out[channels[record.channel_id]] = out.get(channels[record.channel_id], 0) + 1
    return out


def read_warning(path: Path, topic: str, **kw) -> tuple[object, list[str]]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        columns = read_joint_states(path, topic, **kw)
    return columns, [str(w.message) for w in caught if issubclass(w.category, DamagedLogWarning)]


@pytest.mark.parametrize("how", ["flip", "crc", "truncate"])
def test_a_damaged_chunk_is_skipped_with_a_hole_and_one_line(log, damage, tmp_path, how):
    bad = tmp_path / f"{how}.mcap"
    offset = damage.damage(log, bad, DAMAGED, how)
    lost = chunk_counts(log, DAMAGED)
    full = read_joint_states(log, STATE)
    for per_message in (False, True):
        cols, lines = read_warning(bad, STATE, per_message=per_message)
        n = lost[STATE]
        assert len(cols) == len(full) - n > 0
        (hole,) = cols.holes
        assert hole.messages == n and 0 < hole.row < len(cols)
        for name in COLUMNS:  # the rows on both sides of the hole are the file's, in order
            a, b = getattr(cols, name), getattr(full, name)
            assert np.array_equal(a[: hole.row], b[: hole.row])
            assert np.array_equal(a[hole.row :], b[hole.row + n :])
        assert len(lines) == 1 and "\n" not in lines[0]
        line = lines[0]
        assert line.startswith(f"{bad}: chunk {DAMAGED + 1} at byte {offset} cannot be read: ")
        assert f"skipped it: {n} messages of {STATE}" in line
    assert hole.skipped.chunk.offset == offset


def test_the_reasons_name_what_is_wrong(log, damage, tmp_path):
    reasons = {}
    for how in ("crc", "truncate"):
        bad = tmp_path / f"{how}.mcap"
        damage.damage(log, bad, DAMAGED, how)
        (hole,) = read_warning(bad, STATE)[0].holes
        reasons[how] = hole.skipped.chunk.reason
    assert reasons["crc"].startswith("its records fail their CRC check (CRC-32 0x")
    assert "zstd data do not decompress" in reasons["truncate"] or "decompresses to" in reasons["truncate"]


def test_every_reader_goes_around_it(log, damage, tmp_path):
    bad = tmp_path / "flip.mcap"
    damage.damage(log, bad, DAMAGED, "flip")
    lost = chunk_counts(log, DAMAGED)
    assert {t.topic: t.message_count for t in list_topics(bad)} == {STATE: 3000, SETPOINT: 3000}  # summary
    with pytest.warns(DamagedLogWarning, match=rf"chunk {DAMAGED + 1} at byte \d+ cannot be read"):
        setpoints = read_messages(bad, SETPOINT, JOINT_STATE_TYPE)
    assert len(setpoints) == 3000 - lost[SETPOINT]
    skipped: list[SkippedChunk] = []
    messages = list(iter_recording(bad, on_skip=skipped.append))
    assert len(messages) == 6000 - sum(lost.values())
    assert [(s.chunk.ordinal, s.messages, s.of) for s in skipped] == [
        (DAMAGED + 1, sum(lost.values()), "every topic")
    ]
    reference = [m.message.sequence for m in iter_recording(log) if m.channel.topic == STATE]
    got = [m.message.sequence for m in messages if m.channel.topic == STATE]
    missing = sorted(set(reference) - set(got))  # one stretch of the topic's messages, the chunk's
    assert len(missing) == lost[STATE] and missing == list(range(missing[0], missing[-1] + 1))
    assert got == [s for s in reference if s not in missing]


def test_a_chunk_without_message_index_is_skipped_as_an_unknown_loss(tmp_path, damage):
    path, bad = tmp_path / "plain.mcap", tmp_path / "plain-bad.mcap"
    with open(path, "wb") as fh:
        writer = McapWriter(fh, chunk_size=8192, index_types=IndexType.CHUNK, use_summary_offsets=False)
        writer.start(profile="ros2", library="test")
        schema = writer.register_schema(JOINT_STATE_TYPE, "ros2msg", b"")
        channel = writer.register_channel("/js", "cdr", schema)
        for k in range(2000):
            writer.add_message(channel, k, JointState(k, "f", ("a",), (k,), (0.0,), (0.0,)).encode(), k, k)
        writer.finish()
    assert len(damage.chunks(path)) > 5
    damage.damage(path, bad, 2, "flip")
    cols, lines = read_warning(bad, "/js")
    (hole,) = cols.holes
    assert hole.messages is None and len(cols) < 2000
    assert np.array_equal(cols.position[:, 0], cols.stamp_ns.astype(float))  # every row is its own
    assert len(lines) == 1 and "an unknown number of messages of /js" in lines[0]


def test_nothing_readable_is_an_error_naming_the_damage(log, damage, tmp_path):
    bad = tmp_path / "all.mcap"
    data = log
    for k in range(len(damage.chunks(log))):
        damage.damage(data, bad, k, "crc")
        data = bad
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a failed read says it all in its error
        with pytest.raises(RecordingError, match=r"holds no message \(\d+ chunk\(s\) .* could not be read"):
            read_joint_states(bad, STATE)
        why = r"15 chunk\(s\) could not be read; the first: chunk 1 at byte 43: its records fail their CRC"
        with pytest.raises(RecordingError, match=rf"no complete message to recover \({why}"):
            recover(bad, tmp_path / "out.mcap")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["all.mcap"]  # no output, no temporary file


def test_a_reader_that_stops_early_closes_the_file(log):
    def open_files() -> set[str]:
        names = set()
        for fd in os.listdir("/proc/self/fd"):
            with contextlib.suppress(FileNotFoundError):  # the listing's own descriptor, closed since
                names.add(os.readlink(f"/proc/self/fd/{fd}"))
        return names

    before = open_files()
    messages = iter_recording(log)
    next(messages)
    assert str(log) in open_files() - before
    messages.close()
    assert str(log) not in open_files()


# ---- recover ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("how", ["flip", "truncate"])
def test_recover_salvages_every_good_chunk_into_a_file_every_tool_opens(log, damage, tmp_path, how):
    from rerun.chunk import RrdReader
    from rosbags.highlevel import AnyReader

    bad, out, rrd = tmp_path / "bad.mcap", tmp_path / "fixed.mcap", tmp_path / "fixed.rrd"
    damage.damage(log, bad, DAMAGED, how)
    lost = chunk_counts(log, DAMAGED)
    report = recover(bad, out)
    assert report.messages == 6000 - sum(lost.values()) and report.channels == 2
    assert [(s.chunk.ordinal, s.messages) for s in report.skipped] == [(DAMAGED + 1, sum(lost.values()))]
    summary = f"skipped 1 chunk(s) that could not be read ({sum(lost.values())} messages lost)"
    assert summary in report.format()
    assert is_complete(out)
    assert len(read_joint_states(out, STATE)) == 3000 - lost[STATE]
    with AnyReader([out]) as reader:  # rosbags
        assert sum(1 for _ in reader.messages()) == report.messages
    env = {**os.environ, "CI": "1", "RUST_LOG": "error"}
    convert = [sys.executable, "-m", "rerun", "mcap", "convert", str(out), "-o", str(rrd)]
    subprocess.run(convert, check=True, capture_output=True, env=env, timeout=120)
    rows = {}
    for chunk in RrdReader(rrd).store().stream():
        if chunk.entity_path == f"{STATE}/position" and not chunk.is_static:
            rows[chunk.entity_path] = rows.get(chunk.entity_path, 0) + chunk.num_rows
    assert rows == {f"{STATE}/position": 3000 - lost[STATE]}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.mcap", "fixed.mcap", "fixed.rrd"]


def test_a_chunk_in_a_compression_nobody_reads_is_skipped_and_named(log, damage, tmp_path):
    data = bytearray(log.read_bytes())
    record, _start, _length = damage.chunks(log)[DAMAGED]
    assert data[record + 41 : record + 45] == b"zstd"
    data[record + 41 : record + 45] = b"zst9"
    bad = tmp_path / "zst9.mcap"
    bad.write_bytes(bytes(data))
    cols, lines = read_warning(bad, STATE)
    assert len(cols.holes) == 1 and len(lines) == 1
    assert "it uses compression 'zst9'; readable: zstd, lz4 or none" in lines[0]
