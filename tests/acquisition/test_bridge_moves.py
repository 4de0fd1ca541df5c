"""Moves sent over Zenoh to a running bridge: queued back to back, bad ones rejected, the axis rests
at the end even though the sender's session is gone (real sessions on tcp/127.0.0.1, in-process)."""

import signal
import threading
import time

import numpy as np
import pytest
import zenoh
from axisflow.acquisition import (
    AxisKeys,
    AxisSample,
    BridgeConfig,
    BridgeEvent,
    MoveSender,
    SimulatedAxis,
    ZenohOptions,
    load_plant,
    open_session,
    run_bridge,
)
from axisflow.model import AxisParams

PARAMS = AxisParams(
    m=20.0, J_m=1.5e-4, J_g=5e-5, J_p=2e-4, r=0.03, i_r=10.0, L=0.8,
    a1=100.0, a2=50.0, a3=20.0, a4=50.0, v_max=1.0, tau_max=3.0,
)  # fmt: skip
T0 = 1_700_000_000_000_000_000


def _drain(sub) -> list:
    out = []
    while (s := sub.try_recv()) is not None:
        out.append(s)
    return out


def test_moves_queue_back_to_back_and_bad_ones_are_rejected(port):
    keys = AxisKeys("a0")
    drive = SimulatedAxis(load_plant(None, PARAMS), PARAMS, T0, axis="a0")
    config = BridgeConfig(keys=keys, speed=2.0, duration_s=4.0, wait_subscribers_s=10.0)
    report = {}
    with (
        open_session(ZenohOptions.loopback(listen_port=port)) as bridge_session,
        open_session(ZenohOptions.loopback(connect_port=port)) as observer,
        observer.declare_subscriber(keys.setpoint, zenoh.handlers.FifoChannel(10_000)) as setpoints,
        observer.declare_subscriber(keys.event, zenoh.handlers.FifoChannel(100)) as events,
    ):
        thread = threading.Thread(
            target=lambda: report.setdefault("r", run_bridge(bridge_session, drive, PARAMS, config))
        )
        thread.start()
        # the planner: sends three moves, then its session disappears mid-move
        with (
            open_session(ZenohOptions.loopback(connect_port=port)) as planner,
            MoveSender(planner, keys) as sender,
        ):
            assert sender.wait_for_bridge(10.0)
            sender.send(0.0, 0.3, 0.7, law="poly5")
            sender.send(0.3, 0.1, 0.5, law="poly7")
            sender.send(0.5, 0.6, 0.5)  # jumps from 0.1 m: rejected
        thread.join(timeout=30)
        assert not thread.is_alive()
        received = [AxisSample.decode(s.payload.to_bytes()) for s in _drain(setpoints)]
        texts = [BridgeEvent.decode(s.payload.to_bytes()).text for s in _drain(events)]
    r = report["r"]
    assert (r.moves_accepted, r.moves_rejected, r.moves_missed) == (2, 1, 0)
    assert any("rejected move 3: start_position_m = 0.5 m jumps 0.4 m" in t for t in texts)
    assert sum(t.startswith("accepted") for t in texts) == 2
    x = np.array([s.position_m for s in received])
    stamps = np.array([s.stamp_ns for s in received])
    assert set(np.diff(stamps).tolist()) == {1_000_000}
    moving = np.flatnonzero(np.abs(np.diff(x)) > 0)
    start, end = moving[0], moving[-1] + 1
    assert end - start == 1200  # 700 ms + 500 ms with no idle tick in between
    assert x[start:end].max() == pytest.approx(0.3)
    assert x[-1] == pytest.approx(0.1)  # at rest at the end of the last accepted move
    assert drive.position_m == pytest.approx(0.1, abs=5e-4)


def test_sender_finds_the_bridge_through_the_recorder_by_gossip(cli, tmp_path, port):
    """Recorder listens; bridge and sender only connect to it and must find each other."""
    out = tmp_path / "moves.mcap"
    rec = cli.start("record", "-o", str(out), "--listen", f"tcp/127.0.0.1:{port}")
    cli.wait_for_file(out)
    # a long duration: the bridge must not exit before a loaded machine lets the sender find it;
    # it is stopped with SIGINT once the move is done
    bridge = cli.start("bridge", "--sim", "--connect", f"tcp/127.0.0.1:{port}", "--duration", "120", "--json")
    with (
        open_session(ZenohOptions.loopback(connect_port=port)) as planner,
        MoveSender(planner, AxisKeys()) as sender,
    ):
        assert sender.wait_for_bridge(30.0)
        sender.send(0.0, 0.2, 0.6)
        time.sleep(2.0)  # the 0.6 s move runs to its end
    bridge.send_signal(signal.SIGINT)
    bridge_out, bridge_err = cli.finish(bridge)
    rec.send_signal(signal.SIGINT)
    rec_out, _ = cli.finish(rec)
    assert '"moves_accepted": 1' in bridge_out, bridge_err
    assert '"moves_completed": 1' in bridge_out
    assert "/axisflow/a0/trajectory" in rec_out
