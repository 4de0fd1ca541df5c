"""Command-line behaviour: commands exit (no hang), user errors exit 2 without a traceback."""

import json
import time

import pytest
from axisflow.benchmarks.toolkit.proc_stats import cpu_seconds


@pytest.mark.slow
def test_record_and_bridge_exit_on_their_own(cli, tmp_path, port):
    """A recorder with --duration and a bridge with --duration each end by themselves (a command that
    hangs at exit fails the test); the bridge at speed 0 waits for its consumer, the recorder, and then
    runs as fast as it takes the samples."""
    bridge = cli.start(
        "bridge", "--sim", "--listen", f"tcp/127.0.0.1:{port}", "--duration", "0.5", "--speed", "0", "--json",
        ready=True,
    )  # fmt: skip
    cli.wait_ready(bridge)
    recording = tmp_path / "x.mcap"
    rec = cli.run("record", "-o", str(recording), "--connect", f"tcp/127.0.0.1:{port}", "--duration", "4")
    assert rec.returncode == 0, rec.stderr  # fails the test if the recorder hangs at exit
    assert "recorded" in rec.stdout, rec.stderr
    out, err = cli.finish(bridge, timeout=60)  # fails the test if the bridge hangs at exit
    assert bridge.returncode == 0, err
    assert json.loads(out)["ticks"] == 500
    from axisflow.acquisition import read_joint_states

    # the bridge waited for the recorder to start, and for its receipt before it closed its session
    assert len(read_joint_states(recording, "/axisflow/a0/state")) == 500


def test_a_bridge_at_speed_0_waits_while_nobody_subscribes(cli, port):
    """No consumer: no tick runs and the process sleeps (before, it spun a core for nothing); a
    subscriber makes it run; SIGINT ends it."""
    import signal

    from axisflow.acquisition import AxisKeys, ZenohOptions, open_session
    from axisflow.acquisition.bus.axis_state import AxisState

    from axisflow.deploy.processes import wait_until

    bridge = cli.start(
        "bridge", "--sim", "--speed", "0", "--listen", f"tcp/127.0.0.1:{port}", "--json", ready=True
    )
    cli.wait_ready(bridge)
    busy = cpu_seconds(bridge.pid)
    time.sleep(1.0)  # measuring an interval of idleness: there is no event to wait for
    assert cpu_seconds(bridge.pid) - busy < 0.2  # a spinning loop takes ~1 s of CPU a second
    with (
        open_session(ZenohOptions.loopback(connect_port=port)) as session,
        AxisState(session, AxisKeys(), "setpoint") as setpoint,
    ):
        first = setpoint.wait(20.0)  # a consumer: the ticks run
        assert wait_until(lambda: setpoint.latest().stamp_ns > first.stamp_ns + 10**9, 20.0)
    bridge.send_signal(signal.SIGINT)
    out, err = cli.finish(bridge)
    assert bridge.returncode == 0, err
    assert json.loads(out)["ticks"] >= 1000


@pytest.mark.slow
def test_bridge_with_default_zenoh_config_exits_even_when_7447_is_taken(cli):
    """The embedded default listens on 7447 if free and on a port of its own: it must also work when
    something else (here: a plain socket, or whatever already holds it) has 7447, so the test does
    not depend on the port being free."""
    import socket

    holder = socket.socket()
    holder.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)  # a closed earlier holder may linger
    try:
        holder.bind(("127.0.0.1", 7447))
        holder.listen()
    except OSError:
        pass  # already taken by another process: the same situation
    try:
        result = cli.run("bridge", "--sim", "--duration", "0.2", "--json", timeout=60)
    finally:
        holder.close()
    assert result.returncode == 0, result.stderr
    assert '"ticks": 200' in result.stdout


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (["bridge", "--sim", "--plant", "missing.toml"], "plant file missing.toml does not exist"),
        (["bridge", "--sim", "--speed", "-1"], "speed = -1.0 must be >= 0"),
        (["bridge", "--sim", "--axis", "a/b"], "axis name 'a/b' is not a valid key-expression part"),
        (["record", "-o", "x.txt"], "must end in .mcap"),
        (["record", "-o", "x.mcap", "--duration", "0"], "duration = 0.0 s must be > 0 s"),
        (["record", "-o", "x.mcap", "--keys", "a//b"], "--keys 'a//b' is not a valid Zenoh key expression"),
        (["bridge", "--sim", "--jump-tolerance", "-1"], "jump tolerance = -1.0 m must be >= 0 m"),
        (["recover", "missing.mcap"], "recording missing.mcap does not exist"),
        (["replay", "missing.mcap"], "recording missing.mcap does not exist"),
        (
            ["bridge", "--sim", "--zenoh-config", "missing.json5"],
            "zenoh config file missing.json5 does not exist",
        ),
    ],
)
@pytest.mark.slow
def test_user_errors_exit_2_with_a_message(cli, tmp_path, args, match):
    result = cli.run(*args, timeout=30)
    assert result.returncode == 2, (result.stdout, result.stderr)
    assert match in result.stderr
    assert "Traceback" not in result.stderr


@pytest.mark.slow
def test_pipeline_benchmark_smoke(cli):
    import json

    result = cli.run(
        "bench", "pipeline", "--json", "--axes", "2", "--seconds", "0.5", "--flood", "4000",
        "--flood-rounds", "2", "--memory-seconds", "1", "--memory-axes", "2", "--idle-seconds", "0.5",
        timeout=120,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    r = json.loads(result.stdout)
    step = r["steps"][0]
    assert step["axes"] == 2 and step["lost"] == 0
    # the figure follows the step's verdict (whether a loaded machine's recorder kept up within 100 ms at
    # p99 is the benchmark's finding, not this test's)
    assert r["max_axes_zero_loss"] == (2 if step["zero_loss"] and step["keeps_up"] else 0)
    flood = r["recorder_flood"]
    assert flood["lost"] == 0 and flood["messages"] == 2 * 4000 and len(flood["rounds"]) == 2
    assert flood["ratio_min"] * 0.9999 <= flood["ratio_to_baseline"] <= flood["ratio_max"] * 1.0001
    assert r["memory"]["axes"] == 2 and r["memory"]["peak_rss_mb"] > 0
    assert 0 <= r["idle_recorder_cpu_percent"] < 100
    # (a 4000-message flood lasts about one clock tick: the CPU figures are there, not yet meaningful)
    assert set(flood["cpu_us_per_message"]) == {
        "recorder_main",
        "recorder_zenoh_rx",
        "recorder_other",
        "publisher",
    }


@pytest.mark.parametrize("command", ["recover", "replay"])
@pytest.mark.parametrize("content", [b"abc", bytes(range(256)) * 16], ids=["3-bytes", "4-KiB-noise"])
@pytest.mark.slow
def test_a_file_that_is_not_mcap_is_refused_and_nothing_is_written(cli, tmp_path, command, content):
    source = tmp_path / "noise.mcap"
    source.write_bytes(content)
    result = cli.run(command, str(source), timeout=30)
    assert result.returncode == 2, (result.stdout, result.stderr)
    assert f"{source} is not an MCAP file" in result.stderr
    assert "Traceback" not in result.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["noise.mcap"]


@pytest.mark.parametrize(
    ("existing", "split_args"),
    [("x.mcap", []), ("x_0000.mcap", ["--split-duration", "1"])],
    ids=["single", "split"],
)
@pytest.mark.slow
def test_record_refuses_to_overwrite_unless_asked(cli, tmp_path, port, existing, split_args):
    old = tmp_path / existing
    old.write_bytes(b"precious")
    out = str(tmp_path / "x.mcap")
    listen = ["--listen", f"tcp/127.0.0.1:{port}"]
    result = cli.run("record", "-o", out, *split_args, *listen, "--duration", "0.2", timeout=30)
    assert result.returncode == 2, (result.stdout, result.stderr)
    assert f"output {old} already exists" in result.stderr and "--overwrite" in result.stderr
    assert "Traceback" not in result.stderr
    assert old.read_bytes() == b"precious"
    result = cli.run(
        "record", "-o", out, *split_args, *listen, "--duration", "0.2", "--overwrite", timeout=30
    )
    assert result.returncode == 0, result.stderr
    assert old.read_bytes() != b"precious"


def _tiny_recording(path):
    from axisflow.acquisition import AxisSample
    from axisflow.acquisition.logs.mcap_writer import Ros2McapWriter

    writer = Ros2McapWriter(path)
    channel = writer.channel_for("/axisflow/a0/state", "sensor_msgs/msg/JointState")
    for k in range(3):
        stamp = 1_700_000_000_000_000_000 + k * 1_000_000
        writer.add(channel, stamp, stamp, k + 1, AxisSample(stamp, "a0", 0.1, 0, 0, 25, 0, 0).encode())
    writer.finish()


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (["replay", "{src}", "--wait-subscribers", "-3"], "wait for subscribers = -3.0 s must be >= 0 s"),
        (["replay", "{src}", "--keys", "a//b"], "--keys 'a//b' is not a valid Zenoh key expression"),
        (["recover", "{src}", "-o", "{dir}/out.txt"], "out.txt must end in .mcap"),
        (["recover", "{src}", "-o", "{dir}/taken.mcap"], "taken.mcap already exists: choose another name"),
    ],
)
@pytest.mark.slow
def test_replay_and_recover_refuse_bad_options(cli, tmp_path, args, match):
    src = tmp_path / "src.mcap"
    _tiny_recording(src)
    (tmp_path / "taken.mcap").write_bytes(b"precious")
    before = sorted(p.name for p in tmp_path.iterdir())
    result = cli.run(*[a.format(src=src, dir=tmp_path) for a in args], timeout=30)
    assert result.returncode == 2, (result.stdout, result.stderr)
    assert match in result.stderr
    assert "Traceback" not in result.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == before
    assert (tmp_path / "taken.mcap").read_bytes() == b"precious"


def test_recover_overwrites_only_when_asked(cli, tmp_path):
    src = tmp_path / "src.mcap"
    _tiny_recording(src)
    out = tmp_path / "taken.mcap"
    out.write_bytes(b"old")
    result = cli.run("recover", str(src), "-o", str(out), "--overwrite", timeout=30)
    assert result.returncode == 0, result.stderr
    assert "recovered 3 messages on 1 channels" in result.stdout


def test_recover_of_a_file_with_no_complete_message_writes_nothing(cli, tmp_path):
    src = tmp_path / "src.mcap"
    _tiny_recording(src)
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(src.read_bytes()[:40])  # the magic and part of the header: no chunk
    result = cli.run("recover", str(cut), timeout=30)
    assert result.returncode == 2, (result.stdout, result.stderr)
    assert "holds no complete message to recover" in result.stderr
    assert not (tmp_path / "cut.recovered.mcap").exists()


@pytest.mark.slow
def test_a_bridge_waits_for_its_recorder_and_stamps_its_samples_when_it_starts(cli, tmp_path, port):
    """--wait-subscribers really waits (the recorder starts 2 s after the bridge and still gets the
    first sample), and the drive's clock starts with the loop (stamps close to the publish time)."""
    import signal

    from axisflow.acquisition import AxisKeys, ZenohOptions, open_session
    from axisflow.acquisition.bus.readiness import wait_for_token

    from axisflow.deploy.processes import wait_until

    out = tmp_path / "late.mcap"
    bridge = cli.start(
        "bridge", "--sim", "--listen", f"tcp/127.0.0.1:{port}", "--duration", "1", "--wait-subscribers", "60"
    )
    with open_session(ZenohOptions.loopback(connect_port=port)) as session:
        assert wait_for_token(session, AxisKeys().alive, 60.0)  # it is up (its token is declared last)
    assert bridge.poll() is None  # and still waiting
    rec = cli.start(
        "record", "-o", str(out), "--connect", f"tcp/127.0.0.1:{port}", "--keys", "axisflow/*/state"
    )
    _out, err = cli.finish(bridge, timeout=60)
    assert bridge.returncode == 0, err
    assert wait_until(lambda: cli.on_disk(out) == 1000, 30.0)  # all flushed to disk
    rec.send_signal(signal.SIGINT)
    cli.finish(rec)
    msgs = cli.decoded(out, "/axisflow/a0/state")
    assert len(msgs) == 1000
    assert msgs[0][0].sequence == 1
    lag_ns = [m.publish_time - (d.header.stamp.sec * 10**9 + d.header.stamp.nanosec) for m, d in msgs]
    assert max(lag_ns[:10]) < 50_000_000  # the first samples are stamped when they are taken
