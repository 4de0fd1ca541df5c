"""Killing the planner mid-run leaves the axis at rest (the bridge drops its queued moves), and the
planner, restarted, carries on from where the axis is (separate processes, as users run them)."""

import signal

import pytest
import zenoh
from axisflow.acquisition import AxisKeys, AxisSample, MoveState, MoveStatus, ZenohOptions, open_session
from axisflow.acquisition.bus.readiness import JoinedSubscriber

from axisflow.deploy.processes import wait_until

KEYS = AxisKeys()


@pytest.mark.slow
@pytest.mark.heavy
def test_a_killed_planner_leaves_the_axis_at_rest_and_a_restart_carries_on(cli, tmp_path, port):
    points = tmp_path / "points.txt"
    points.write_text("0.1\n0.7\n0.2\n0.6\n0.3\n")
    endpoint = f"tcp/127.0.0.1:{port}"
    # The kill lands on a fact: a move of the planner is queued behind the one that runs (--lookahead 2
    # keeps two there while the planner keeps ahead of the axis at --speed 4; one slowed by a loaded
    # machine may fall behind for a move, and the test waits for the next one queued). The planner's
    # death needs no time-out to be seen: the kernel closes its link with the process, its session's
    # token goes with the link, and the bridge drops the queue on its next tick: milliseconds after the
    # kill, not seconds, even on a loaded machine.
    bridge = cli.start("bridge", "--sim", "--speed", "4", "--listen", endpoint, "--json", ready=True)
    cli.wait_ready(bridge)
    planner_args = ("planner", "--waypoints", str(points), "--case", "min-time-energy", "--lookahead", "2",
                    "--connect", endpoint)  # fmt: skip
    handler = lambda: zenoh.handlers.FifoChannel(10_000)  # noqa: E731
    with (
        open_session(ZenohOptions.loopback(connect_port=port)) as watch,
        JoinedSubscriber(watch, KEYS.event, handler) as events,  # misses no status
    ):
        setpoints = watch.declare_subscriber(KEYS.setpoint, zenoh.handlers.RingChannel(1))
        statuses: list[MoveStatus] = []

        def take() -> None:
            while (s := events.subscriber.try_recv()) is not None:
                statuses.append(MoveStatus.decode(s.payload.to_bytes()))

        def wait_for(what: str, fact, timeout_s=60.0):
            if not wait_until(lambda: take() or fact(), timeout_s):
                pytest.fail(f"no {what} in {timeout_s} s: {statuses}")

        def ids(state: MoveState) -> list[int]:
            return [st.move_id for st in statuses if st.state is state]

        def queued_behind_a_running_move() -> bool:
            """a move from way point 2 on accepted to start after the tick it was accepted on, while one runs
            (the planner is mid-run: the axis has left the first way point)"""
            return any(
                st.state is MoveState.ACCEPTED and st.move_id >= 3 and st.start_tick > st.tick
                and len(ids(MoveState.STARTED)) > len(ids(MoveState.COMPLETED))
                for st in statuses
            )  # fmt: skip

        first = cli.start(*planner_args)
        wait_for("move queued behind a running one", queued_behind_a_running_move)
        first.send_signal(signal.SIGKILL)
        first.wait(10)
        wait_for("dropped move", lambda: bool(ids(MoveState.DROPPED)))  # its queued moves go with it ...
        # ... while the running one ends, at rest, and nothing else starts
        wait_for("end of the running move", lambda: ids(MoveState.COMPLETED) == ids(MoveState.STARTED))
        assert min(ids(MoveState.DROPPED)) > max(ids(MoveState.COMPLETED))
        completed = [st for st in statuses if st.state is MoveState.COMPLETED]
        latest: list[AxisSample] = []

        def a_setpoint_after_the_last_completion() -> bool:
            if (sample := setpoints.try_recv()) is not None:
                latest[:] = [AxisSample.decode(sample.payload.to_bytes())]
            return bool(latest) and latest[0].stamp_ns >= completed[-1].stamp_ns

        assert wait_until(a_setpoint_after_the_last_completion, 10.0)
        rest = latest[0]
        assert rest.velocity_m_s == 0.0
        stopped_at = rest.position_m
        # move k goes to way point k: the axis rests where the last move that ran ends
        way_points = [float(p) for p in points.read_text().split()]
        assert stopped_at == pytest.approx(way_points[completed[-1].move_id - 1])

        restart = cli.run(*planner_args, "--json", timeout=120)
        assert restart.returncode == 0, restart.stderr
        setpoints.undeclare()
    bridge.send_signal(signal.SIGINT)
    out, err = cli.finish(bridge)
    assert '"moves_rejected": 0' in out, out + err
    assert [st.move_id for st in completed] == list(range(1, len(completed) + 1))
    # the restart began from where the axis was: a move from there to the first way point, then the run
    import json

    (report,) = json.loads(restart.stdout)
    assert report["moves"] == 4 and report["idle_ticks"] == [0, 0, 0]
