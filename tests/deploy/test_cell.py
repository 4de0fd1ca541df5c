"""A cell through one router: 4 bridges and a recorder as processes, the router restarted mid-run; and
`axisflow demo --axes N`. Real processes, real Zenoh on tcp/127.0.0.1 (multicast scouting off: the
project's default), real MCAP files."""

from __future__ import annotations

import json
import time
from contextlib import ExitStack

import numpy as np
import pytest
from axisflow.acquisition import AxisKeys, MoveSender, MoveState, ZenohOptions, open_session
from axisflow.acquisition.logs.reader import read_joint_states, read_messages
from axisflow.acquisition.wire.keys import topic_for_key
from axisflow.model import default_params

from axisflow.deploy.cell import Cell, CellLayout, axis_names
from axisflow.deploy.processes import wait_until

PARAMS = default_params()
MOVES = ((0.0, 0.3, 4.0), (0.3, 0.7, 2.0))
"""per axis, the move running when the router goes (4 s) and one queued behind it (to 0.7 m)"""
AFTER = (0.3, 0.15, 1.0)
"""the move sent once the router is back: it starts where the first move ended"""


def _sequences(path, topic: str) -> np.ndarray:
    return np.array([m.sequence for m in read_messages(path, topic)], dtype=np.int64)


@pytest.mark.slow
@pytest.mark.heavy
def test_a_router_restart_keeps_every_axis_safe_and_the_recording_marks_the_gap_only(tmp_path):
    layout = CellLayout.on_loopback(4)  # bridges at 1× real time, as on a machine
    recording = tmp_path / "cell.mcap"
    with Cell(layout, tmp_path / "logs") as cell, ExitStack() as stack:
        cell.start_router()
        cell.start_recorder(recording)
        cell.start_bridges(wait_subscribers_s=10.0)  # each waits for the recorder: it records every sample
        session = stack.enter_context(open_session(ZenohOptions(mode="client", connect=(layout.endpoint,))))
        senders = {axis: stack.enter_context(MoveSender(session, AxisKeys(axis))) for axis in layout.axes}
        first, queued = {}, {}
        for axis, sender in senders.items():
            assert sender.wait_for_bridge(10.0), axis
            first[axis] = sender.send(*MOVES[0])
            queued[axis] = sender.send(*MOVES[1])
        for axis, sender in senders.items():  # the first runs, the second waits in the bridge's queue
            started = sender.wait_status(first[axis].move_id, {MoveState.STARTED}, 10.0)
            assert started is not None and started.state is MoveState.STARTED, axis
            accepted = sender.wait_status(queued[axis].move_id, {MoveState.ACCEPTED}, 10.0)
            assert accepted is not None and accepted.state is MoveState.ACCEPTED, axis

        restart_wall_ns = time.time_ns()
        restart = cell.restart_router()  # SIGINT, then a new router on the same endpoint
        assert wait_until(lambda: all(s.bridge_alive for s in senders.values()), 20.0), "no reconnection"
        back_wall_ns = time.time_ns()
        cell.check_alive()  # no bridge, nor the recorder, ended with the router

        after = {}
        for axis, sender in senders.items():
            after[axis] = sender.send(*AFTER)  # accepted only if the axis holds where move 1 ended
        for axis, sender in senders.items():
            done = sender.wait_status(after[axis].move_id, {MoveState.COMPLETED}, 20.0)
            assert done is not None and done.state is MoveState.COMPLETED, (axis, done)
        stack.close()
        bridges = cell.stop_bridges()
        summary = cell.stop_recorder()
        cell.stop_router()

    assert restart.down_s < 30.0
    for axis in layout.axes:
        report = bridges[axis]
        # the running move finished, the queued one was dropped with its sender's token, none missed
        assert (report["moves_accepted"], report["moves_completed"], report["moves_dropped"]) == (3, 2, 1), (
            axis
        )
        assert (report["moves_rejected"], report["moves_missed"], report["stale_ticks"]) == (0, 0, 0), axis
        keys = AxisKeys(axis)
        for kind in ("state", "setpoint"):
            topic = topic_for_key(getattr(keys, kind))
            stats = summary["topics"][topic]
            [publisher] = stats["publishers"]  # one publisher: the bridge, never restarted
            assert (publisher["first_sequence"], publisher["last_sequence"]) == (1, report["ticks"]), topic
            assert stats["messages"] + stats["missed"] == report["ticks"], topic
            assert stats["missed"] > 0 and stats["duplicates"] == 0, topic
            seq = _sequences(recording, topic)
            steps = np.diff(seq)
            assert (steps >= 1).all(), f"{topic}: a sequence number repeated or out of order"
            columns = read_joint_states(recording, topic)
            gaps = np.flatnonzero(steps > 1)
            where = [(int(steps[g] - 1), (int(columns.stamp_ns[g]) - restart_wall_ns) / 1e9) for g in gaps]
            # the router's outage and nothing else: every gap opens after the stop was asked and closes
            # once the clients are back (the outage, and now and then a sample lost while the links form
            # again: seen once in ten runs, 1 sample 0.31 s after a 307-sample outage); none elsewhere
            # (telemetry drops on congestion: a machine so loaded that a process gets no CPU for a while
            # loses samples elsewhere too)
            assert len(gaps) >= 1 and (steps[gaps] - 1).sum() == stats["missed"], (topic, where)
            for gap in gaps:
                last_before, first_after = columns.stamp_ns[gap], columns.stamp_ns[gap + 1]
                assert last_before >= restart_wall_ns - 1_000_000_000, (topic, where)
                assert first_after <= back_wall_ns + 2_000_000_000, (topic, where)
        setpoints = read_joint_states(recording, topic_for_key(keys.setpoint))
        x = setpoints.position[:, 0]
        assert x.max() <= MOVES[0][1] + 1e-9, f"{axis}: the dropped move towards 0.7 m ran"
        assert np.abs(setpoints.velocity[:, 0]).max() <= PARAMS.v_max


@pytest.mark.slow
@pytest.mark.heavy
def test_demo_of_a_cell_gives_table_2_per_axis_from_one_recording(cli, tmp_path):
    out = tmp_path / "cell"
    done = cli.run("demo", "--axes", "2", "--waypoints", "3", "--out", str(out), timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    summary = json.loads((out / "demo.json").read_text())
    assert summary["axes"] == list(axis_names(2))
    assert summary["seeds"] == {"a0": 0, "a1": 1}
    for axis in axis_names(2):
        counts = summary["recording"][axis]
        assert counts["recorded"] == counts["ticks"] > 0 and counts["missed"] == 0, axis
        table = json.loads((out / f"table2-{axis}.json").read_text())
        assert len(table["rows"]) == 6, axis
        assert summary["idle_ticks"][axis] == 0, axis
        assert all(e is not None for e in summary["energy_error_pct"][axis].values()), axis
        assert f"# Table 2, axis {axis}" in done.stdout
    # the axes moved differently (their own way points), and the recording holds both
    assert summary["energy_error_pct"]["a0"] != summary["energy_error_pct"]["a1"]
    again = cli.run("table2", str(out / "cell.mcap"), "--axis", "a1", "--out", str(tmp_path / "t2"), "--json")
    assert again.returncode == 0, again.stderr
    by_hand, by_demo = json.loads(again.stdout), json.loads((out / "table2-a1.json").read_text())
    assert by_hand.pop("title") == "Table 2, on the axis" and by_demo.pop("title") == "Table 2, axis a1"
    assert by_hand == by_demo
    refused = cli.run("table2", str(out / "cell.mcap"), "--out", str(tmp_path / "t3"))
    assert refused.returncode == 2 and "holds 2 axes (a0, a1): choose one with --axis" in refused.stderr


@pytest.mark.slow
@pytest.mark.heavy
def test_cell_benchmark_runs_both_paths_in_one_run(cli):
    done = cli.run(
        "bench", "cell", "--json", "--axes", "2", "--seconds", "0.5", "--outage-axes", "0", timeout=300
    )
    assert done.returncode == 0, done.stderr[-3000:]
    result = json.loads(done.stdout)
    steps = {s["path"]: s for s in result["steps"]}
    assert set(steps) == {"peer-to-peer", "router"}
    for path, step in steps.items():
        assert step["axes"] == 2 and step["published"] == 1000, path
        assert step["recorded"] + step["lost"] == step["published"] and step["recorded"] > 0, path
        assert step["latency_p50_us"] > 0, path
    assert steps["router"]["router_cpu_s"] > 0 and steps["peer-to-peer"]["router_cpu_s"] is None
    assert set(result["max_axes_zero_loss"]) == {"peer-to-peer", "router"}
