"""bridge → recorder → MCAP over real Zenoh sessions on loopback (separate processes).

One run of N seconds at --speed 1 is shared by the tests of this module: the state topic must hold
N·1000 ± 1 messages with stamps exactly 1 ms apart and no missed sequence numbers, the values decode
to the two-joint contract, and rerun's MCAP importer, rosbags and replay accept the file.
"""

import math
import signal
import subprocess
from pathlib import Path

import numpy as np
import pytest
from axisflow.acquisition import SCHEMAS
from axisflow.model import default_params

pytestmark = pytest.mark.slow  # a module fixture of several seconds: the whole module is in the slow tier

N_SECONDS = 2
STATE = "/axisflow/a0/state"
SETPOINT = "/axisflow/a0/setpoint"


@pytest.fixture(scope="module")
def recording(cli, tmp_path_factory):
    """A bridge whose axis starts at 0.3 m (so positions are not zero) runs one move 0.3 → 0.6 m."""
    from axisflow.acquisition import AxisKeys, MoveSender, ZenohOptions, open_session

    tmp = tmp_path_factory.mktemp("pipeline")
    out = tmp / "run.mcap"
    plant = tmp / "plant.toml"
    plant.write_text("[scale]\nm = 1.05\n\n[simulation]\ninitial_position_m = 0.3\n")
    port = cli.free_port()
    rec = cli.start("record", "-o", str(out), "--listen", f"tcp/127.0.0.1:{port}")
    cli.wait_for_file(out)
    bridge = cli.start(
        "bridge", "--sim", "--plant", str(plant), "--connect", f"tcp/127.0.0.1:{port}",
        "--duration", str(N_SECONDS), "--speed", "1", "--wait-subscribers", "10",
    )  # fmt: skip
    with (
        open_session(ZenohOptions.loopback(connect_port=port)) as planner,
        MoveSender(planner, AxisKeys()) as sender,
    ):
        assert sender.wait_for_bridge(20.0)
        sender.send(0.3, 0.6, 0.8, law="poly5")
        bridge_out, bridge_err = cli.finish(bridge)
    assert bridge.returncode == 0, bridge_err
    rec.send_signal(signal.SIGINT)
    rec_out, rec_err = cli.finish(rec)
    assert rec.returncode == 0, rec_err
    return {"path": out, "bridge": bridge_out, "recorder": rec_out, "port": port}


def test_state_topic_has_every_tick_one_ms_apart(cli, recording):
    msgs = cli.decoded(recording["path"], STATE)
    assert abs(len(msgs) - N_SECONDS * 1000) <= 1
    stamps = np.array([d.header.stamp.sec * 10**9 + d.header.stamp.nanosec for _m, d in msgs])
    assert set(np.diff(stamps).tolist()) == {1_000_000}
    seqs = np.array([m.sequence for m, _d in msgs])
    assert seqs[0] == 1 and set(np.diff(seqs).tolist()) == {1}  # none missed
    assert "missed 0" in recording["recorder"]
    assert f"{STATE}" in recording["recorder"]


def test_values_decode_to_the_two_joint_contract(cli, recording):
    params = default_params()
    states = cli.decoded(recording["path"], STATE)
    positions = np.array([d.position[0] for _m, d in states])
    speeds = np.array([d.velocity[0] for _m, d in states])
    assert positions.min() == pytest.approx(0.3, abs=1e-3) and positions.max() == pytest.approx(0.6, abs=2e-3)
    assert np.abs(speeds).max() > 0.5  # the move ran: the joint relations below are checked in motion
    for _m, d in states[::97]:
        assert d.header.frame_id == "a0"
        assert d.name == ["carriage", "motor"]
        x, theta = d.position
        v, omega = d.velocity
        force, torque = d.effort
        assert 0.0 <= x <= params.L
        assert theta == pytest.approx(x * params.i_r / params.r)
        assert omega == pytest.approx(v * params.i_r / params.r)
        assert force == pytest.approx(torque * params.i_r / params.r)
        assert abs(torque) <= params.tau_max + 0.1
    setpoints = cli.decoded(recording["path"], SETPOINT)
    assert abs(len(setpoints) - N_SECONDS * 1000) <= 1
    assert all(d.name == ["carriage", "motor"] for _m, d in setpoints[::50])
    moving = [d for _m, d in setpoints if d.velocity[0] != 0.0]
    assert 795 <= len(moving) <= 800  # the 0.8 s move, sampled at 1 kHz (its two ends at rest)


def test_bridge_reports_period_jitter(recording):
    assert f"{N_SECONDS * 1000} ticks" in recording["bridge"]
    assert "period jitter: p50" in recording["bridge"]


def test_file_is_ros2_profile_with_schemas_and_qos(recording):
    from mcap.reader import make_reader

    with open(recording["path"], "rb") as fh:
        reader = make_reader(fh)
        assert reader.get_header().profile == "ros2"
        summary = reader.get_summary()
    expected = {
        STATE: "sensor_msgs/msg/JointState",
        SETPOINT: "sensor_msgs/msg/JointState",
        "/axisflow/a0/trajectory": "axisflow_msgs/msg/Move",
        "/axisflow/a0/event": "axisflow_msgs/msg/MoveStatus",
        "/axisflow/a0/drive": "axisflow_msgs/msg/DriveInfo",  # what the bridge drives, once a second
    }
    assert {ch.topic: summary.schemas[ch.schema_id].name for ch in summary.channels.values()} == expected
    for ch in summary.channels.values():
        schema = summary.schemas[ch.schema_id]
        assert (ch.message_encoding, schema.encoding) == ("cdr", "ros2msg")
        assert schema.data.decode() == SCHEMAS[schema.name]
        assert "offered_qos_profiles" in ch.metadata
    assert all(ci.compression == "zstd" for ci in summary.chunk_indexes)


def test_rosbags_reads_the_file_as_a_ros2_bag(recording):
    from rosbags.highlevel import AnyReader

    with AnyReader([Path(recording["path"])]) as reader:
        counts = {c.topic: c.msgcount for c in reader.connections}
        conn = next(c for c in reader.connections if c.topic == STATE)
        _c, _t, raw = next(reader.messages(connections=[conn]))
        msg = reader.deserialize(raw, conn.msgtype)
    assert conn.msgtype == "sensor_msgs/msg/JointState"
    assert abs(counts[STATE] - N_SECONDS * 1000) <= 1
    assert list(msg.name) == ["carriage", "motor"]


def test_rerun_mcap_import_gives_position_velocity_effort(recording, tmp_path):
    from rerun.chunk import RrdReader

    rrd = tmp_path / "run.rrd"
    proc = subprocess.run(
        ["rerun", "mcap", "convert", str(recording["path"]), "-o", str(rrd)],
        capture_output=True,
        text=True,
        timeout=60,
        env={"CI": "1", "PATH": __import__("os").environ["PATH"]},
    )
    assert proc.returncode == 0, proc.stderr
    paths = set(RrdReader(str(rrd)).store().schema().entity_paths())
    for series in ("position", "velocity", "effort"):
        assert f"{STATE}/{series}" in paths
        assert f"{SETPOINT}/{series}" in paths


def test_replay_publishes_the_recording_back(cli, recording, tmp_path):
    port = cli.free_port()
    out = tmp_path / "replayed.mcap"
    rec = cli.start("record", "-o", str(out), "--listen", f"tcp/127.0.0.1:{port}")
    cli.wait_for_file(out)
    # no --wait-subscribers: by default the replay waits for the recorder, so nothing is lost
    replay = cli.run("replay", str(recording["path"]), "--speed", "0", "--connect", f"tcp/127.0.0.1:{port}")
    assert replay.returncode == 0, replay.stderr
    rec.send_signal(signal.SIGINT)
    rec_out, _ = cli.finish(rec)
    assert "missed 0" in rec_out
    assert "n/a (stamps not live" in rec_out  # not the histogram ceiling for old stamps
    original = cli.decoded(recording["path"], STATE)
    replayed = cli.decoded(out, STATE)
    assert len(replayed) == len(original)
    assert [m.data for m, _ in replayed] == [m.data for m, _ in original]  # bytes unchanged
    assert [m.publish_time for m, _ in replayed] == [m.publish_time for m, _ in original]
    assert math.isclose(len(original), N_SECONDS * 1000, abs_tol=1)
