"""The live view over real Zenoh: a simulated bridge in its own process viewed by `axisflow view
--live -o`, and an in-process publisher of every record kind viewed by :class:`LiveView`; the .rrd is
read back with rerun's reader."""

from __future__ import annotations

import json
import signal
import threading
import time

import numpy as np
import pytest
from axisflow.acquisition import JointState, MoveState, MoveStatus, PlanRecord
from axisflow.acquisition.bus.publisher import SequencedPublisher, Traffic, wait_for_subscribers
from axisflow.acquisition.bus.session import ZenohOptions, open_session
from axisflow.acquisition.wire.messages import AXIS_JOINTS, JOINT_STATE_TYPE
from axisflow.acquisition.wire.move_status import MOVE_STATUS_TYPE
from axisflow.acquisition.wire.params_estimate import PARAMS_ESTIMATE_TYPE, Decision, ParamsEstimate
from axisflow.acquisition.wire.plan_record import PLAN_TYPE
from axisflow.model import EXECUTION_PERIOD_S, EnergyAccounting, default_params, trace_energy
from axisflow.viz.live_view import LiveView
from axisflow.viz.outputs import RerunOutput, ViewOutput

from axisflow.deploy.processes import free_port, wait_until


@pytest.mark.slow
def test_a_live_view_of_a_bridge_holds_every_published_sample(cli, tmp_path, rrd_reader):
    port = cli.free_port()
    out = tmp_path / "live.rrd"
    view = cli.start(
        "view", "--live", "-o", str(out), "--listen", f"tcp/127.0.0.1:{port}", "--json", ready=True
    )
    cli.wait_ready(view)  # its subscriber has joined
    bridge = cli.run(
        "bridge",
        "--sim",
        "--duration",
        "2",
        "--wait-subscribers",
        "15",
        "--connect",
        f"tcp/127.0.0.1:{port}",
        "--json",
        timeout=60,
    )
    assert bridge.returncode == 0, bridge.stderr
    ticks = json.loads(bridge.stdout)["ticks"]
    # the bridge has exited: Zenoh delivered its last samples to the view before its session's close;
    # the view's stop (a hello, then draining its channel) takes them all
    view.send_signal(signal.SIGINT)  # Ctrl-C: a clean stop
    stdout, stderr = cli.finish(view)
    assert view.returncode == 0, stderr
    report = json.loads(stdout)
    assert report["missed"] == 0
    assert report["per_key"]["axisflow/a0/state"]["received"] == ticks
    assert report["latency"]["count"] == 2 * ticks  # (its figures are the benchmark's: `axisflow bench view`)
    data = rrd_reader(out)
    for entity in ("position/measured", "torque/measured", "position/setpoint", "torque/feedforward"):
        stamps = data[f"/axes/a0/{entity}"].stamp_ns
        assert len(stamps) == ticks, entity
        np.testing.assert_array_equal(np.diff(stamps), 1_000_000)  # every tick, none twice
    assert len(data["/axes/a0/tracking_error"].stamp_ns) == ticks
    assert not list(tmp_path.glob(".*.part"))


def test_every_record_kind_reaches_the_view(tmp_path, rrd_reader):
    port = free_port()
    params = default_params()
    out_path = tmp_path / "records.rrd"
    stop = threading.Event()
    sender = "ab" * 16
    t0 = time.time_ns() // 1_000_000 * 1_000_000
    with (
        open_session(ZenohOptions.loopback(listen_port=port)) as view_session,
        open_session(ZenohOptions.loopback(connect_port=port)) as pub_session,
        RerunOutput(ViewOutput(rrd=out_path)) as out,
    ):
        view = LiveView(out, params, "axisflow/**")
        thread = threading.Thread(target=view.run, args=(view_session, stop))
        thread.start()
        assert view.ready.wait(10)
        pubs = {
            kind: SequencedPublisher(pub_session, f"axisflow/x1/{kind}", type_name, Traffic.BULK)
            for kind, type_name in (
                ("state", JOINT_STATE_TYPE),
                ("setpoint", JOINT_STATE_TYPE),
                ("event", MOVE_STATUS_TYPE),
                ("plan", PLAN_TYPE),
                ("params", PARAMS_ESTIMATE_TYPE),
            )
        }
        assert wait_for_subscribers(list(pubs.values()), 10)
        plan = PlanRecord(
            t0,
            "x1",
            7,
            sender,
            "run",
            1,
            "min-time",
            "poly5",
            "exact",
            0.9,
            0.1,
            0.5,
            0.4,
            3.0,
            "positive",
            1.0,
            0.0,
            "converged",
            1,
            0.0,
        )
        pubs["plan"].put(plan.encode())
        v0 = (params.M_eq, params.a1, params.a2, params.a3, params.a4)
        v1 = (params.M_eq, params.a1 * 0.9, params.a2 * 0.8, params.a3 * 0.9, params.a4)
        for record in (
            ParamsEstimate(t0, "x1", 0, 0, Decision.INITIAL, "start", values=v0),
            ParamsEstimate(t0 + 300_000_000, "x1", 1, 0, Decision.ACCEPTED, "accepted", ("a2",), v1),
        ):
            pubs["params"].put(record.encode(), record.stamp_ns)
        pubs["event"].put(
            MoveStatus(t0, "x1", MoveState.ACCEPTED, 7, 0, 100, 500, sender, "accepted").encode()
        )
        rng = np.random.default_rng(0)
        speed, torque = rng.normal(size=1000), rng.normal(size=1000)
        for k in range(1000):
            stamp = t0 + k * 1_000_000
            for kind in ("setpoint", "state"):
                js = JointState(stamp, "x1", AXIS_JOINTS, (0.3, 1.0), (0.1, speed[k]), (10.0, torque[k]))
                pubs[kind].put(js.encode(), stamp)
        pubs["event"].put(
            MoveStatus(
                t0 + 500_000_000, "x1", MoveState.COMPLETED, 7, 500, 100, 500, sender, "completed"
            ).encode()
        )
        assert wait_until(lambda: view.report.received == 1 + 2 + 2 + 2000, 10.0)
        stop.set()
        thread.join(10)
        for pub in pubs.values():
            pub.undeclare()
    assert view.report.received == 1 + 2 + 2 + 2000 and view.report.missed == 0
    data = rrd_reader(out_path)
    assert len(data["/axes/x1/position/measured"].stamp_ns) == 1000
    assert [v[0] for v in data["/axes/x1/events"].values] == ["accepted", "completed"]
    assert data["/axes/x1/position/waypoints"].scalars().tolist() == [0.5]
    assert data["/axes/x1/energy/planned"].scalars().tolist() == [3.0]
    energy = data["/axes/x1/energy/measured"]
    assert energy.stamp_ns.tolist() == [t0 + 500_000_000]
    expected = trace_energy(speed[100:501], torque[100:501], EXECUTION_PERIOD_S, EnergyAccounting.POSITIVE)
    assert energy.scalars().tolist() == [expected]
    error = data["/axes/x1/energy_error"]  # each move's E%, once its plan and its samples are in
    assert error.stamp_ns.tolist() == [t0 + 500_000_000]
    assert error.scalars().tolist() == [(3.0 - expected) / 3.0 * 100.0]
    a2 = data["/axes/x1/params/a2"]  # in % of version 0, with the ±σ series (σ unknown here: 0)
    assert a2.stamp_ns.tolist() == [t0, t0 + 300_000_000]
    assert a2.scalars()[:, 0] == pytest.approx([0.0, -20.0])
    assert data["/axes/x1/friction/now"].stamp_ns.tolist() == [t0, t0 + 300_000_000]
