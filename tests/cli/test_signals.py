"""SIGTERM and SIGINT to every long-running command, mid-work, through the real command line: each ends
within 2 s, and what it writes is complete or absent (never half-written)."""

from __future__ import annotations

import json
import signal
import time
from pathlib import Path

import pytest
from axisflow.acquisition import AxisKeys, AxisSample, ZenohOptions, is_complete, open_session
from axisflow.acquisition.bus.axis_state import AxisState
from axisflow.acquisition.logs.mcap_writer import Ros2McapWriter
from axisflow.acquisition.wire.messages import JOINT_STATE_TYPE

from axisflow.deploy.processes import wait_until

pytestmark = [pytest.mark.slow, pytest.mark.heavy]  # each stop is bounded in wall time (2 s)

STOP_WITHIN_S = 2.0
SIGNALS = pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
KEYS = AxisKeys()


def _stop(cli, proc, sig) -> tuple[float, str, str]:
    """Send ``sig``; (seconds until the process exited, its stdout, its stderr)."""
    t0 = time.monotonic()
    proc.send_signal(sig)
    end = cli.launcher.wait(proc, 30.0)
    return time.monotonic() - t0, end.stdout, end.stderr


def _bridge(cli, port: int, *extra: str):
    bridge = cli.start("bridge", "--sim", "--listen", f"tcp/127.0.0.1:{port}", "--json", *extra, ready=True)
    cli.wait_ready(bridge)
    return bridge


def _publishing(port: int, timeout_s: float = 60.0) -> None:
    """Return once the axis's bridge publishes (a state sample arrived)."""
    with (
        open_session(ZenohOptions.loopback(connect_port=port)) as session,
        AxisState(session, KEYS, "state") as state,
    ):
        assert wait_until(lambda: state.latest() is not None, timeout_s)


def _running_moves(port: int, timeout_s: float = 60.0) -> None:
    """Return once the axis moves (a setpoint with a speed): a sender's moves are running."""
    with (
        open_session(ZenohOptions.loopback(connect_port=port)) as session,
        AxisState(session, KEYS, "setpoint") as setpoint,
    ):
        assert wait_until(lambda: (s := setpoint.latest()) is not None and s.velocity_m_s != 0.0, timeout_s)


@SIGNALS
def test_bridge(cli, port, sig):
    bridge = _bridge(cli, port)
    _publishing(port)
    seconds, out, err = _stop(cli, bridge, sig)
    assert seconds < STOP_WITHIN_S and bridge.returncode == 0, err
    assert json.loads(out)["ticks"] > 0  # its report, whole


@SIGNALS
def test_record(cli, tmp_path, port, sig):
    out = tmp_path / "r.mcap"
    rec = cli.start("record", "-o", str(out), "--listen", f"tcp/127.0.0.1:{port}", "--json", ready=True)
    cli.wait_ready(rec)
    bridge = cli.start("bridge", "--sim", "--connect", f"tcp/127.0.0.1:{port}", "--wait-subscribers", "30")
    assert wait_until(lambda: cli.on_disk(out) > 1000, 60.0)  # mid-work: recording the bridge
    seconds, stdout, err = _stop(cli, rec, sig)
    assert seconds < STOP_WITHIN_S and rec.returncode == 0, err
    assert is_complete(out)
    assert json.loads(stdout)["messages"] == cli.on_disk(out)  # its summary counts what is in the file
    cli.launcher.stop(bridge)


@SIGNALS
def test_planner(cli, tmp_path, port, sig):
    _bridge(cli, port)
    points = tmp_path / "points.txt"
    points.write_text("0.1\n0.7\n0.2\n0.6\n0.3\n0.5\n")
    planner = cli.start("planner", "--waypoints", str(points), "--connect", f"tcp/127.0.0.1:{port}")
    _running_moves(port)
    seconds, out, err = _stop(cli, planner, sig)
    assert seconds < STOP_WITHIN_S, err
    assert planner.returncode == 130 and err.strip().endswith("axisflow planner: interrupted"), err
    assert out == ""  # no half a report


@SIGNALS
def test_excite(cli, port, sig):
    _bridge(cli, port)
    excite = cli.start("excite", "--connect", f"tcp/127.0.0.1:{port}")
    _running_moves(port)
    seconds, out, err = _stop(cli, excite, sig)
    assert seconds < STOP_WITHIN_S, err
    assert excite.returncode == 130 and err.strip().endswith("axisflow excite: interrupted"), err
    assert out == ""


def _long_recording(path: Path, seconds: int = 60) -> None:
    writer = Ros2McapWriter(path)
    channel = writer.channel_for("/axisflow/a0/state", JOINT_STATE_TYPE)
    t0 = 1_700_000_000_000_000_000
    for k in range(seconds * 100):  # 100 Hz: a minute of recording
        stamp = t0 + k * 10_000_000
        sample = AxisSample(stamp, "a0", 0.1, 0.0, 0.0, 2.5, 0.0, 0.0).encode()
        writer.add(channel, stamp, stamp, k + 1, sample)
    writer.finish()


@SIGNALS
def test_replay(cli, tmp_path, port, sig):
    path = tmp_path / "long.mcap"
    _long_recording(path)
    with (
        open_session(ZenohOptions.loopback(listen_port=port)) as session,
        AxisState(session, KEYS, "state") as state,
    ):
        replay = cli.start("replay", str(path), "--connect", f"tcp/127.0.0.1:{port}")
        assert wait_until(lambda: state.latest() is not None, 60.0)  # mid-work: publishing
        seconds, out, err = _stop(cli, replay, sig)
    assert seconds < STOP_WITHIN_S and replay.returncode == 0, err
    assert out.startswith("replayed ")  # its report, whole


@SIGNALS
def test_view_live(cli, tmp_path, port, sig):
    from rerun.chunk import RrdReader

    out = tmp_path / "live.rrd"
    view = cli.start("view", "--live", "-o", str(out), "--listen", f"tcp/127.0.0.1:{port}", ready=True)
    cli.wait_ready(view)
    bridge = cli.start("bridge", "--sim", "--connect", f"tcp/127.0.0.1:{port}", "--wait-subscribers", "30")
    _publishing(port)  # mid-work: the view gets samples
    seconds, _out, err = _stop(cli, view, sig)
    assert seconds < STOP_WITHIN_S and view.returncode == 0, err
    rows = sum(c.num_rows for c in RrdReader(str(out)).store().stream() if "/axes/a0/" in str(c.entity_path))
    assert rows > 0  # a whole .rrd that rerun reads
    assert not list(tmp_path.glob(".*.part"))
    cli.launcher.stop(bridge)


@SIGNALS
def test_demo(cli, tmp_path, sig):
    out = tmp_path / "session"
    demo = cli.start("demo", "--waypoints", "2", "--out", str(out))
    recording = out / "excitation.mcap"
    assert wait_until(lambda: cli.on_disk(recording) > 1000 or demo.poll() is not None, 180.0)
    assert demo.poll() is None, demo.stderr_text()  # mid-work: the excitation is being recorded
    seconds, _out, err = _stop(cli, demo, sig)
    assert seconds < STOP_WITHIN_S, err
    assert demo.returncode == 130 and "axisflow demo: interrupted" in err, err
    assert is_complete(recording)  # the recorder was stopped cleanly
    assert not (out / "demo.json").exists()  # no summary of a demo that did not finish
