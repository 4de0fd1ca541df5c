"""Reading JointState topics into columns: the vectorised path equals the per-message path equals
mcap_ros2's independent decoder, bit for bit, on our files and on files other writers made (other
topics and joints, interleaved topics, zstd/lz4/none, no message index, no chunks, no summary, cut
off by a crash); the time filter; the errors."""

from __future__ import annotations

import dataclasses
import shutil
from pathlib import Path

import numpy as np
import pytest
from axisflow.acquisition import JOINT_STATE_TYPE, SCHEMAS, JointState, RecordingError, WireError
from axisflow.acquisition.logs.joint_state_layout import JointStateLayout
from axisflow.acquisition.logs.mcap_writer import OFFERED_QOS_PROFILES, Ros2McapWriter
from axisflow.acquisition.logs.reader import list_topics, read_joint_states
from axisflow.acquisition.logs.synthetic_log import (
    BLOCK_TICKS,
    SyntheticLogSpec,
    synthetic_block,
    write_synthetic_log,
)
from axisflow.acquisition.wire.messages import AXIS_JOINTS
from axisflow.model import default_params
from mcap.opcode import Opcode
from mcap.reader import make_reader
from mcap.records import Channel, Chunk, Message
from mcap.stream_reader import StreamReader, breakup_chunk
from mcap.writer import CompressionType, IndexType
from mcap.writer import Writer as McapWriter
from mcap_ros2.writer import Writer as Ros2Writer
from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin
from rosbags.rosbag2 import Writer as RosbagsWriter
from rosbags.typesys import Stores, get_typestore

from .reader_checks import (
    COLUMNS,
    assert_columns_equal,
    assert_same_bits,
    cut,
    read_both_ways,
    record_spans,
    reference,
)

STATE, SETPOINT = "/axisflow/a0/state", "/axisflow/a0/setpoint"
ARM, GRIPPER, HEAD, CHATTER = "/arm/joint_states", "/gripper/joint_states", "/head/joint_states", "/chatter"
ARM_JOINTS = tuple(f"joint_{i}" for i in range(1, 7))
STRING_SCHEMA = "string data\n"


# ---- files ---------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def synthetic(tmp_path_factory) -> Path:
    """3 s of our two topics (6000 messages) in 64 KiB zstd chunks: ~15 chunks."""
    path = tmp_path_factory.mktemp("synthetic") / "axis.mcap"
    write_synthetic_log(path, SyntheticLogSpec(duration_s=3.0, chunk_size=64 * 1024))
    return path


def foreign_messages(seed: int = 7) -> list[tuple[str, int, int, int, JointState | str]]:
    """(topic, sequence, log_time, publish_time, message) interleaved in write order: a 6-joint arm
    (one fixed layout), a gripper whose frame_id changes length and that sends no effort, a head
    whose frame_id changes bytes at a fixed length, and a String topic."""
    rng = np.random.default_rng(seed)
    t0 = 1_700_000_000_000_000_000
    out = []
    for k in range(1500):
        stamp = t0 + k * 2_000_000 + int(rng.integers(0, 1000))
        v = rng.normal(size=(3, 6))
        arm = JointState(stamp, "base_link", ARM_JOINTS, tuple(v[0]), tuple(v[1]), tuple(v[2]))
        out.append((ARM, k + 1, stamp + 500_000, stamp + 100, arm))
        if k % 3 == 0:
            frame = ("", "g", "gripper_link_frame_7")[k // 3 % 3]
            grip = JointState(stamp + 1, frame, ("finger",), (float(v[0, 0]),), (float(v[1, 0]),), ())
            out.append((GRIPPER, k // 3 + 1, stamp + 600_000, stamp + 200, grip))
        if k % 2 == 0:
            head = JointState(
                stamp + 2, ("ha", "hb")[k // 2 % 2], ("pan", "tilt"), (1.0, 2.0), (0.0, -0.0), (3.0, 4.0)
            )
            out.append((HEAD, k // 2 + 1, stamp + 700_000, stamp + 300, head))
        if k % 10 == 0:
            out.append((CHATTER, k // 10 + 1, stamp + 800_000, stamp + 400, f"hello {k}"))
    return out


def expected_columns(topic: str) -> dict[str, np.ndarray]:
    rows = [(seq, log, pub, m) for t, seq, log, pub, m in foreign_messages() if t == topic]
    joints = len(rows[0][3].name)

    def values(v: tuple[float, ...]) -> tuple[float, ...]:
        return v if v else (np.nan,) * joints

    return {
        "stamp_ns": np.array([m.stamp_ns for *_x, m in rows]),
        "log_time_ns": np.array([log for _s, log, _p, _m in rows]),
        "publish_time_ns": np.array([pub for _s, _l, pub, _m in rows]),
        "sequence": np.array([seq for seq, *_x in rows]),
        "position": np.array([values(m.position) for *_x, m in rows]),
        "velocity": np.array([values(m.velocity) for *_x, m in rows]),
        "effort": np.array([values(m.effort) for *_x, m in rows]),
        "joint_names": rows[0][3].name,
    }


def encode(message: JointState | str) -> bytes:
    if isinstance(message, JointState):
        return message.encode()
    data = message.encode() + b"\x00"
    return b"\x00\x01\x00\x00" + len(data).to_bytes(4, "little") + data


def write_plain(path: Path, **writer_options) -> Path:
    """The foreign messages through mcap's plain Writer (pre-encoded, with the given options)."""
    with open(path, "wb") as fh:
        writer = McapWriter(fh, **writer_options)
        writer.start(profile="ros2", library="test")
        js = writer.register_schema(JOINT_STATE_TYPE, "ros2msg", SCHEMAS[JOINT_STATE_TYPE].encode())
        text = writer.register_schema("std_msgs/msg/String", "ros2msg", STRING_SCHEMA.encode())
        channels = {t: writer.register_channel(t, "cdr", js) for t in (ARM, GRIPPER, HEAD)}
        channels[CHATTER] = writer.register_channel(CHATTER, "cdr", text)
        for topic, seq, log, pub, message in foreign_messages():
            writer.add_message(channels[topic], log, encode(message), pub, seq)
        writer.finish()
    return path


def write_mcap_ros2(path: Path) -> Path:
    """The foreign messages through mcap_ros2's writer (its own CDR encoder), 8 KiB zstd chunks."""
    with open(path, "wb") as fh:
        writer = Ros2Writer(fh, chunk_size=8192)
        js = writer.register_msgdef(JOINT_STATE_TYPE, SCHEMAS[JOINT_STATE_TYPE])
        text = writer.register_msgdef("std_msgs/msg/String", STRING_SCHEMA)
        for topic, seq, log, pub, m in foreign_messages():
            if isinstance(m, str):
                writer.write_message(topic, text, {"data": m}, log, pub, seq)
                continue
            sec, nanosec = divmod(m.stamp_ns, 10**9)
            fields = {"position": list(m.position), "velocity": list(m.velocity), "effort": list(m.effort)}
            header = {"stamp": {"sec": sec, "nanosec": nanosec}, "frame_id": m.frame_id}
            writer.write_message(topic, js, {"header": header, "name": list(m.name), **fields}, log, pub, seq)
        writer.finish()
    return path


def write_rosbags(directory: Path, compress: bool) -> Path:
    """The foreign JointStates through rosbags' rosbag2 MCAP writer (its own encoder and framing)."""
    store = get_typestore(Stores.ROS2_HUMBLE)
    types = store.types
    writer = RosbagsWriter(directory, version=9, storage_plugin=StoragePlugin.MCAP)
    if compress:
        writer.set_compression(CompressionMode.STORAGE, CompressionFormat.ZSTD)
    with writer:
        connections = {}
        for topic, _seq, log, _pub, m in foreign_messages():
            if isinstance(m, str):
                continue
            if topic not in connections:
                connections[topic] = writer.add_connection(topic, JOINT_STATE_TYPE, typestore=store)
            sec, nanosec = divmod(m.stamp_ns, 10**9)
            header = types["std_msgs/msg/Header"](
                types["builtin_interfaces/msg/Time"](sec, nanosec), m.frame_id
            )
            arrays = [np.array(a, np.float64) for a in (m.position, m.velocity, m.effort)]
            msg = types[JOINT_STATE_TYPE](header, list(m.name), *arrays)
            writer.write(connections[topic], log, store.serialize_cdr(msg, JOINT_STATE_TYPE))
    return directory / f"{directory.name}.mcap"


PLAIN_VARIANTS = {
    "lz4-4k": {"compression": CompressionType.LZ4, "chunk_size": 4096},
    "none-16k": {"compression": CompressionType.NONE, "chunk_size": 16384},
    "zstd-no-message-index": {"chunk_size": 8192, "index_types": IndexType.CHUNK},
    "unchunked": {"use_chunking": False},
    "no-summary": {
        "chunk_size": 8192,
        "repeat_channels": False,
        "repeat_schemas": False,
        "use_statistics": False,
        "use_summary_offsets": False,
        "index_types": IndexType.MESSAGE,
    },
}


@pytest.fixture(scope="module")
def foreign(tmp_path_factory) -> dict[str, Path]:
    base = tmp_path_factory.mktemp("foreign")
    files = {name: write_plain(base / f"{name}.mcap", **opts) for name, opts in PLAIN_VARIANTS.items()}
    files["mcap_ros2"] = write_mcap_ros2(base / "mcap_ros2.mcap")
    files["rosbags-zstd"] = write_rosbags(base / "rosbags_zstd", compress=True)
    files["rosbags-none"] = write_rosbags(base / "rosbags_none", compress=False)
    return files


# ---- our files -------------------------------------------------------------------------------------------


def test_synthetic_log_reads_back_exactly_as_generated(synthetic):
    spec = SyntheticLogSpec(duration_s=3.0, chunk_size=64 * 1024)
    block = synthetic_block(spec, 0)
    for topic, generated in ((STATE, block.state), (SETPOINT, block.setpoint)):
        cols = read_both_ways(synthetic, topic)
        assert len(cols) == 3000 and cols.vectorised_messages == 3000 and cols.per_message_messages == 0
        assert cols.joint_names == AXIS_JOINTS and cols.frame_id == "a0" and not cols.truncated
        expected = {name: getattr(generated, name) for name in COLUMNS} | {"joint_names": AXIS_JOINTS}
        assert_columns_equal(cols, expected)
        motor = cols.joint("motor")
        assert_same_bits(motor.effort, generated.effort[:, 1], "motor torque")
        assert motor.stamp_ns is cols.stamp_ns


def test_synthetic_log_is_in_the_recorders_format(synthetic):
    with open(synthetic, "rb") as fh:
        reader = make_reader(fh)
        header, summary = reader.get_header(), reader.get_summary()
    assert header.profile == "ros2"
    assert {c.topic for c in summary.channels.values()} == {STATE, SETPOINT}
    for channel in summary.channels.values():
        schema = summary.schemas[channel.schema_id]
        assert (schema.name, schema.encoding, schema.data) == (
            JOINT_STATE_TYPE,
            "ros2msg",
            SCHEMAS[JOINT_STATE_TYPE].encode(),
        )
        assert channel.message_encoding == "cdr"
        assert channel.metadata == {"offered_qos_profiles": OFFERED_QOS_PROFILES}
    assert {c.compression for c in summary.chunk_indexes} == {"zstd"} and len(summary.chunk_indexes) > 10


def test_list_topics_from_the_summary(synthetic):
    topics = list_topics(synthetic)
    assert [(t.topic, t.schema_name, t.message_encoding, t.message_count) for t in topics] == [
        (SETPOINT, JOINT_STATE_TYPE, "cdr", 3000),
        (STATE, JOINT_STATE_TYPE, "cdr", 3000),
    ]
    assert all(t.is_joint_state and t.schema_encoding == "ros2msg" for t in topics)


def test_time_range_filters_on_the_header_stamp(synthetic):
    full = read_joint_states(synthetic, STATE)
    start, end = int(full.stamp_ns[123]), int(full.stamp_ns[2345])
    for kw, mask in (
        ({"start_ns": start, "end_ns": end}, (full.stamp_ns >= start) & (full.stamp_ns < end)),
        ({"start_ns": start}, full.stamp_ns >= start),
        ({"end_ns": end}, full.stamp_ns < end),
    ):
        part = read_both_ways(synthetic, STATE, **kw)
        assert len(part) == int(mask.sum()) > 0
        expected = {name: getattr(full, name)[mask] for name in COLUMNS} | {"joint_names": AXIS_JOINTS}
        assert_columns_equal(part, expected)
    assert len(read_joint_states(synthetic, STATE, start_ns=start, end_ns=start + 1)) == 1


def test_synthetic_log_is_reproducible_and_a_prefix_of_a_longer_one(tmp_path):
    spec = SyntheticLogSpec(duration_s=0.25, seed=3)
    a = write_synthetic_log(tmp_path / "a.mcap", spec)
    b = write_synthetic_log(tmp_path / "b.mcap", spec)
    c = write_synthetic_log(tmp_path / "c.mcap", dataclasses.replace(spec, seed=4))
    assert a.path.read_bytes() == b.path.read_bytes() != c.path.read_bytes()
    assert a.messages_per_topic == 250
    short = synthetic_block(spec, 0).state
    long = synthetic_block(dataclasses.replace(spec, duration_s=25.0), 0).state
    assert len(long.stamp_ns) == BLOCK_TICKS
    for name in COLUMNS:
        assert_same_bits(getattr(short, name), getattr(long, name)[:250], name)


def test_synthetic_motion_stays_in_the_stroke_and_the_limits(synthetic):
    params = default_params()
    state = read_joint_states(synthetic, STATE)
    carriage = state.joint("carriage")
    assert carriage.position.min() > 0.0 and carriage.position.max() < params.L
    assert np.abs(carriage.velocity).max() < params.v_max
    assert np.abs(state.joint("motor").effort).max() < params.tau_max
    assert np.all(np.diff(state.stamp_ns) == 1_000_000)


# ---- foreign files ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", [*PLAIN_VARIANTS, "mcap_ros2", "rosbags-zstd", "rosbags-none"])
@pytest.mark.slow
def test_foreign_files_read_like_mcap_ros2_decodes_them(foreign, name):
    path = foreign[name]
    for topic in (ARM, GRIPPER, HEAD):
        cols = read_both_ways(path, topic)
        expected = expected_columns(topic)
        if name.startswith("rosbags"):  # rosbags writes log time as publish time and sequence 0
            expected |= {"publish_time_ns": expected["log_time_ns"], "sequence": np.zeros(len(cols), int)}
        assert_columns_equal(cols, expected)
        assert not cols.truncated
    arm = read_joint_states(path, ARM)
    assert arm.joint_names == ARM_JOINTS and arm.frame_id == "base_link"
    assert arm.vectorised_messages == 1500  # one fixed layout: every chunk (or batch) vectorised
    gripper = read_joint_states(path, GRIPPER)
    assert gripper.frame_ids == ("", "g", "gripper_link_frame_7")
    assert gripper.per_message_messages > 0  # lengths vary (a chunk with one gripper message is vectorised)
    assert gripper.per_message_messages + gripper.vectorised_messages == 500
    assert np.isnan(gripper.effort).all()  # the gripper sends no effort
    head = read_joint_states(path, HEAD)
    assert head.frame_ids == ("ha", "hb") and head.vectorised_messages < 750  # same length, other bytes


@pytest.mark.parametrize("name", ["no-summary", "rosbags-zstd", "unchunked", "mcap_ros2"])
def test_list_topics_counts_without_relying_on_a_summary(foreign, name):
    counts = {t.topic: t.message_count for t in list_topics(foreign[name])}
    expected = {ARM: 1500, GRIPPER: 500, HEAD: 750, CHATTER: 150}
    if name.startswith("rosbags"):
        del expected[CHATTER]
    assert counts == expected
    chatter = [t for t in list_topics(foreign["mcap_ros2"]) if t.topic == CHATTER]
    assert chatter[0].schema_name == "std_msgs/msg/String" and not chatter[0].is_joint_state


def test_a_channel_defined_chunks_before_its_first_message(tmp_path):
    """Without summary, a channel record that sits in an earlier chunk than its messages is found."""
    path = tmp_path / "late.mcap"
    arm = [m for t, *_x, m in foreign_messages() if t == ARM][:200]
    with open(path, "wb") as fh:
        writer = McapWriter(
            fh, chunk_size=2000, repeat_channels=False, repeat_schemas=False, use_statistics=False
        )
        writer.start(profile="ros2", library="test")
        schema = writer.register_schema(JOINT_STATE_TYPE, "ros2msg", SCHEMAS[JOINT_STATE_TYPE].encode())
        first = writer.register_channel("/first", "cdr", schema)
        for k, m in enumerate(arm[:5]):
            writer.add_message(first, k, m.encode(), k, k)
        late = writer.register_channel("/late", "cdr", schema)  # lands in the chunk being filled
        for k, m in enumerate(arm[5:40]):
            writer.add_message(first, k, m.encode(), k, k)
        for k, m in enumerate(arm[40:]):
            writer.add_message(late, k, m.encode(), k, k)
        writer.finish()
    with open(path, "rb") as fh:  # the setup: /late's channel record is not in its messages' chunks
        chunks = [r for r in StreamReader(fh, emit_chunks=True).records if isinstance(r, Chunk)]
    contents = [breakup_chunk(c) for c in chunks]
    home = next(i for i, c in enumerate(contents) if any(isinstance(r, Channel) and r.id == late for r in c))
    first_message = next(
        i for i, c in enumerate(contents) if any(isinstance(r, Message) and r.channel_id == late for r in c)
    )
    assert home < first_message
    cols = read_both_ways(path, "/late")
    assert len(cols) == 160 and cols.vectorised_messages == 160


# ---- crashes -------------------------------------------------------------------------------------------


@pytest.mark.slow
def test_a_file_cut_anywhere_is_read_up_to_its_last_complete_chunk(synthetic, tmp_path):
    spans = record_spans(synthetic)
    chunk_ends = [(i, end) for i, (op, _s, end) in enumerate(spans) if op == Opcode.CHUNK]
    i3, end3 = chunk_ends[3]
    index_records = [s for s in spans[i3 + 1 :] if s[0] == Opcode.MESSAGE_INDEX][:2]
    cuts = {
        "mid-chunk-data": spans[i3][1] + 100,
        "after-chunk-before-its-indexes": end3,
        "mid-message-index": index_records[0][1] + 20,
        "between-its-message-indexes": index_records[0][2],
        "after-its-message-indexes": index_records[1][2],
        "before-the-summary": next(s for op, s, _e in spans if op == Opcode.DATA_END),
    }
    for label, size in cuts.items():
        path = cut(synthetic, size, tmp_path / f"{label}.mcap")
        for topic in (STATE, SETPOINT):
            cols = read_both_ways(path, topic)
            assert cols.truncated, label
            expected = reference(path, topic)
            assert len(cols) == len(expected["sequence"]) > 0, label
        assert {t.topic: t.message_count for t in list_topics(path)} == {
            SETPOINT: len(read_joint_states(path, SETPOINT)),
            STATE: len(read_joint_states(path, STATE)),
        }
    whole = read_joint_states(synthetic, STATE)
    last = read_joint_states(tmp_path / "before-the-summary.mcap", STATE)
    assert_columns_equal(last, whole)


def test_a_recorder_killed_after_a_flush(tmp_path):
    path, crashed = tmp_path / "live.mcap", tmp_path / "crashed.mcap"
    writer = Ros2McapWriter(path, "lz4", chunk_size=8192)
    channel = writer.channel_for(ARM, JOINT_STATE_TYPE)
    arm = [m for t, *_x, m in foreign_messages() if t == ARM]
    for k, m in enumerate(arm):
        writer.add(channel, k, k, k, m.encode())
        if k == 999:
            writer.flush()
            shutil.copy(path, crashed)  # what is on disk when the process dies here
    writer.finish()
    cols = read_both_ways(crashed, ARM)
    assert cols.truncated and len(cols) == 1000
    assert_same_bits(cols.sequence, np.arange(1000), "sequence")


# ---- errors ----------------------------------------------------------------------------------------------


def test_joint_names_must_not_change_within_a_topic(tmp_path):
    path = tmp_path / "renamed.mcap"
    with open(path, "wb") as fh:
        writer = McapWriter(fh)
        writer.start(profile="ros2", library="test")
        schema = writer.register_schema(JOINT_STATE_TYPE, "ros2msg", SCHEMAS[JOINT_STATE_TYPE].encode())
        channel = writer.register_channel("/js", "cdr", schema)
        for k, names in enumerate([("a", "b")] * 5 + [("a", "c")]):
            writer.add_message(channel, k, JointState(k, "f", names, (1.0, 2.0), (), ()).encode(), k, k)
        writer.finish()
    for per_message in (False, True):
        with pytest.raises(
            RecordingError, match=r"sequence 5 .* names the joints \['a', 'c'\], .* \['a', 'b'\]"
        ):
            read_joint_states(path, "/js", per_message=per_message)


def _write_one_topic(
    path: Path, payloads: list[bytes], encoding: str = "cdr", schema: str = JOINT_STATE_TYPE
) -> Path:
    with open(path, "wb") as fh:
        writer = McapWriter(fh)
        writer.start(profile="ros2", library="test")
        schema_id = writer.register_schema(schema, "ros2msg", SCHEMAS[JOINT_STATE_TYPE].encode())
        channel = writer.register_channel("/js", encoding, schema_id)
        writer.register_channel("/silent", "cdr", schema_id)
        for k, data in enumerate(payloads):
            writer.add_message(channel, 10 + k, data, 20 + k, 30 + k)
        writer.finish()
    return path


GOOD = JointState(5, "f", ("a",), (1.0,), (2.0,), (3.0,)).encode()
BIG_ENDIAN = b"\x00\x00" + GOOD[2:]
BAD_NANOSEC = GOOD[:8] + (10**9).to_bytes(4, "little") + GOOD[12:]
ERRORS = [
    ("missing", lambda d: (d / "nope.mcap", STATE, {}), RecordingError, r"nope\.mcap does not exist"),
    ("not-mcap", lambda d: (d / "notes.txt", STATE, {}), RecordingError, r"is not an MCAP file"),
    (
        "no-topic",
        lambda d: (d / "axis.mcap", "/axisflow/a1/state", {}),
        RecordingError,
        r"has no topic /axisflow/a1/state; its JointState topics: /axisflow/a0/setpoint, /axisflow/a0/state",
    ),
    (
        "not-joint-state",
        lambda d: (d / "foreign.mcap", CHATTER, {}),
        RecordingError,
        r"schema 'std_msgs/msg/String'",
    ),
    (
        "json",
        lambda d: (d / "json.mcap", "/js", {}),
        RecordingError,
        r"message encoding 'json'; only ROS 2 CDR",
    ),
    (
        "no-messages",
        lambda d: (d / "axis-silent.mcap", "/silent", {}),
        RecordingError,
        r"topic /silent holds no message",
    ),
    (
        "empty-range",
        lambda d: (d / "axis.mcap", STATE, {"start_ns": 1, "end_ns": 2}),
        RecordingError,
        r"no message of topic /axisflow/a0/state has a header stamp in \[1, 2\) ns; its stamps span \[17672",
    ),
    (
        "big-endian",
        lambda d: (d / "be.mcap", "/js", {}),
        WireError,
        r"sequence 31 and log time 11 ns .*CDR_LE header",
    ),
    ("bad-nanosec", lambda d: (d / "ns.mcap", "/js", {}), WireError, r"sequence 30 .*nanosec = 1000000000"),
]


@pytest.mark.parametrize(("label", "case", "error", "match"), ERRORS, ids=[e[0] for e in ERRORS])
def test_errors_name_the_value(synthetic, foreign, tmp_path, label, case, error, match):
    shutil.copy(synthetic, tmp_path / "axis.mcap")
    shutil.copy(foreign["mcap_ros2"], tmp_path / "foreign.mcap")
    (tmp_path / "notes.txt").write_text("not a recording\n")
    _write_one_topic(tmp_path / "json.mcap", [b"{}"], encoding="json")
    _write_one_topic(tmp_path / "axis-silent.mcap", [GOOD])
    _write_one_topic(tmp_path / "be.mcap", [GOOD, BIG_ENDIAN])
    _write_one_topic(tmp_path / "ns.mcap", [BAD_NANOSEC, GOOD])
    path, topic, kw = case(tmp_path)
    for per_message in (False, True):
        with pytest.raises(error, match=match):
            read_joint_states(path, topic, per_message=per_message, **kw)


def test_joint_and_frame_id_errors_list_what_is_there(synthetic, foreign):
    with pytest.raises(RecordingError, match=r"has no joint 'wheel'; its joints are \['carriage', 'motor'\]"):
        read_joint_states(synthetic, STATE).joint("wheel")
    with pytest.raises(RecordingError, match=r"has 2 frame_ids \['ha', 'hb'\]: use frame_ids"):
        _ = read_joint_states(foreign["lz4-4k"], HEAD).frame_id


# ---- the layout of the vectorised path -------------------------------------------------------------------


@pytest.mark.parametrize("joints", [0, 1, 2, 6])
@pytest.mark.parametrize("frame_id", ["", "a", "abc", "a0", "base_link", "x" * 13])
def test_layout_encodes_and_decodes_like_joint_state(joints, frame_id):
    rng = np.random.default_rng(joints * 100 + len(frame_id))
    names = tuple(f"j{'x' * i}" for i in range(joints))
    n = 17
    stamps = rng.integers(-(2**62), 2**62, n) // 4
    arrays = [rng.normal(size=(n, joints)) for _ in range(3)]
    arrays[1][0, :] = [np.inf, -0.0, np.nan, 1e-310, -1e300, 0.0][:joints]
    for empty_effort in (False, True):
        effort = () if empty_effort else (0.0,) * joints
        layout, template = JointStateLayout.for_message(
            JointState(0, frame_id, names, (0.0,) * joints, (0.0,) * joints, effort)
        )
        rows = layout.encode(template, stamps, arrays[0], arrays[1], arrays[2])
        messages = [
            JointState(
                int(stamps[i]),
                frame_id,
                names,
                tuple(arrays[0][i]),
                tuple(arrays[1][i]),
                () if empty_effort else tuple(arrays[2][i]),
            )
            for i in range(n)
        ]
        assert [bytes(r) for r in rows] == [m.encode() for m in messages]
        assert layout.matches(rows) and layout.frame_id == frame_id and layout.joint_names == names
        decoded = layout.decode(rows)
        assert_same_bits(decoded.stamp_ns, stamps, "stamp")
        assert_same_bits(decoded.velocity, arrays[1], "velocity")
        assert np.isnan(decoded.effort).all() if empty_effort else np.array_equal(decoded.effort, arrays[2])


def test_layout_refuses_what_it_cannot_lay_out():
    assert JointStateLayout.of(BIG_ENDIAN) is None
    assert JointStateLayout.of(GOOD[:-3]) is None
    assert JointStateLayout.of(JointState(0, "f", ("a", "b"), (1.0,), (), ()).encode()) is None
    assert JointStateLayout.of(b"\x00\x01\x00\x00" + b"\xff" * 12) is None
    with pytest.raises(WireError, match="one value per joint or none"):
        JointStateLayout.for_message(JointState(0, "f", ("a", "b"), (1.0,), (), ()))


def test_read_messages_gives_a_topics_payloads_as_stored(tmp_path):
    """Raw payloads of a rare topic among many JointStates, equal to mcap's own reader's, in order."""
    from axisflow.acquisition import MOVE_STATUS_TYPE, AxisSample, MoveState, MoveStatus
    from axisflow.acquisition.logs.mcap_writer import Ros2McapWriter
    from axisflow.acquisition.logs.reader import read_messages
    from mcap.reader import make_reader

    path = tmp_path / "mixed.mcap"
    writer = Ros2McapWriter(path, "zstd", chunk_size=8192)
    state = writer.channel_for("/axisflow/a0/state", "sensor_msgs/msg/JointState")
    event = writer.channel_for("/axisflow/a0/event", MOVE_STATUS_TYPE)
    for k in range(3000):
        writer.add(state, k, k, k, AxisSample(k, "a0", 0.1, 0.0, 0.0, 0.0, 0.0, 0.0).encode())
        if k % 700 == 0:
            writer.add(
                event, k, k + 1, k // 700, MoveStatus(k, "a0", MoveState.STARTED, k // 700 + 1, k).encode()
            )
    writer.finish()
    got = read_messages(path, "/axisflow/a0/event", MOVE_STATUS_TYPE)
    with open(path, "rb") as fh:
        ref = [m for _s, _c, m in make_reader(fh).iter_messages(topics=["/axisflow/a0/event"])]
    assert [(g.log_time_ns, g.publish_time_ns, g.sequence, g.data) for g in got] == [
        (m.log_time, m.publish_time, m.sequence, m.data) for m in ref
    ]
    assert [MoveStatus.decode(g.data).move_id for g in got] == [1, 2, 3, 4, 5]
    assert read_messages(path, "/nothing/here") == []
    with pytest.raises(
        RecordingError, match="is sensor_msgs/msg/JointState, not axisflow_msgs/msg/MoveStatus"
    ):
        read_messages(path, "/axisflow/a0/state", MOVE_STATUS_TYPE)
