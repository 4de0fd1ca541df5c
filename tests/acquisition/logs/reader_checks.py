"""References and comparisons for the log reader's tests: a topic's columns through mcap's StreamReader
and mcap_ros2's own decoder, bit-for-bit comparisons, both reading paths at once, an MCAP file's records
and a file cut off."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from axisflow.acquisition.logs.reader import JointStateColumns, read_joint_states
from axisflow.acquisition.logs.reader.framing import RECORD_PREFIX
from mcap.opcode import Opcode
from mcap.records import Channel, Message, Schema
from mcap.stream_reader import StreamReader
from mcap_ros2.decoder import DecoderFactory

COLUMNS = ("stamp_ns", "log_time_ns", "publish_time_ns", "sequence", "position", "velocity", "effort")


def reference(path: Path, topic: str) -> dict[str, np.ndarray]:
    """The topic's columns in file order through mcap's StreamReader and mcap_ros2's own CDR decoder
    (up to the truncation for a file cut off by a crash)."""
    schemas, channels, rows = {}, {}, []
    decoders = {}
    with open(path, "rb") as fh:
        try:
            for record in StreamReader(fh).records:
                if isinstance(record, Schema):
                    schemas[record.id] = record
                elif isinstance(record, Channel):
                    channels[record.id] = record
                elif isinstance(record, Message) and channels[record.channel_id].topic == topic:
                    if record.channel_id not in decoders:
                        schema = schemas[channels[record.channel_id].schema_id]
                        decoders[record.channel_id] = DecoderFactory().decoder_for("cdr", schema)
                    rows.append((record, decoders[record.channel_id](record.data)))
        except Exception:  # the cut-off tail of a truncated file
            pass
    joints = len(rows[0][1].name)

    def values(v: list[float]) -> list[float]:
        return list(v) if len(v) else [np.nan] * joints

    return {
        "stamp_ns": np.array([d.header.stamp.sec * 10**9 + d.header.stamp.nanosec for _m, d in rows]),
        "log_time_ns": np.array([m.log_time for m, _d in rows]),
        "publish_time_ns": np.array([m.publish_time for m, _d in rows]),
        "sequence": np.array([m.sequence for m, _d in rows]),
        "position": np.array([values(d.position) for _m, d in rows]).reshape(-1, joints),
        "velocity": np.array([values(d.velocity) for _m, d in rows]).reshape(-1, joints),
        "effort": np.array([values(d.effort) for _m, d in rows]).reshape(-1, joints),
        "joint_names": tuple(rows[0][1].name),
    }


def assert_same_bits(a: np.ndarray, b: np.ndarray, what: str) -> None:
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape, f"{what}: shape {a.shape} != {b.shape}"
    if a.dtype.kind == "f" or b.dtype.kind == "f":
        assert np.array_equal(a.astype(np.float64).view(np.uint64), b.astype(np.float64).view(np.uint64)), (
            what
        )
    else:
        assert np.array_equal(a.astype(np.int64), b.astype(np.int64)), what


def assert_columns_equal(got: JointStateColumns, expected: JointStateColumns | dict) -> None:
    get = (
        (lambda name: expected[name])
        if isinstance(expected, dict)
        else (lambda name: getattr(expected, name))
    )
    for name in COLUMNS:
        column = getattr(got, name)
        assert column.dtype == (np.float64 if name in ("position", "velocity", "effort") else np.int64)
        assert_same_bits(column, get(name), name)
    assert got.joint_names == get("joint_names")


def read_both_ways(path: Path, topic: str, **kw) -> JointStateColumns:
    """Read vectorised and per message; check they agree with each other and with mcap_ros2."""
    fast = read_joint_states(path, topic, **kw)
    slow = read_joint_states(path, topic, per_message=True, **kw)
    assert slow.vectorised_messages == 0
    assert_columns_equal(fast, slow)
    assert fast.frame_ids == slow.frame_ids and fast.truncated == slow.truncated
    if not kw:
        assert_columns_equal(fast, reference(path, topic))
    return fast


def record_spans(path: Path) -> list[tuple[int, int, int]]:
    """(opcode, start, end) of each top-level record of an MCAP file."""
    data = path.read_bytes()
    out, pos = [], 8
    while pos + RECORD_PREFIX.size <= len(data):
        opcode, length = RECORD_PREFIX.unpack_from(data, pos)
        end = pos + RECORD_PREFIX.size + length
        out.append((opcode, pos, end))
        if opcode == Opcode.FOOTER:
            break
        pos = end
    return out


def cut(path: Path, size: int, out: Path) -> Path:
    out.write_bytes(path.read_bytes()[:size])
    return out
