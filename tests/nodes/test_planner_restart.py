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
    # --speed 4: the kill must land while 0.7 → 0.2 m runs (5.7 s of drive time, ~1.4 s of wall time).
    # The planner's death needs no time-out to be seen: the kernel closes its link with the process,
    # its session's token goes with the link, and the bridge drops the queue on its next tick:
    # milliseconds after the kill, not seconds, even on a loaded machine.
    bridge = cli.start("bridge", "--sim", "--speed", "4", "--listen", endpoint, "--json", ready=True)
    cli.wait_ready(bridge)
    planner_args = ("planner", "--waypoints", str(points), "--case", "min-time-energy", "--connect", endpoint)
    handler = lambda: zenoh.handlers.FifoChannel(10_000)  # noqa: E731
    with (
        open_session(ZenohOptions.loopback(connect_port=port)) as watch,
        JoinedSubscriber(watch, KEYS.event, handler) as events,  # misses no status
    ):
        setpoints = watch.declare_subscriber(KEYS.setpoint, zenoh.handlers.RingChannel(1))
        statuses: list[MoveStatus] = []

        def wait_for(state, count, timeout_s=60.0):
            def seen() -> bool:
                while (s := events.subscriber.try_recv()) is not None:
                    statuses.append(MoveStatus.decode(s.payload.to_bytes()))
                return sum(st.state is state for st in statuses) >= count

            if not wait_until(seen, timeout_s):
                pytest.fail(f"fewer than {count} {state.name} statuses in {timeout_s} s: {statuses}")

        first = cli.start(*planner_args)
        # the move to 0.1 m, the moves to 0.7 and 0.2 m, and — once 0.7 → 0.2 runs — the one to 0.6 m
        wait_for(MoveState.ACCEPTED, 4)
        first.send_signal(signal.SIGKILL)
        first.wait(10)
        wait_for(MoveState.DROPPED, 1)  # its queued moves go with it ...
        wait_for(MoveState.COMPLETED, 3)  # ... while the running one ends, at rest
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
        assert stopped_at == pytest.approx(0.2)  # 0.1 → 0.7 → 0.2 ran; 0.2 → 0.6 was dropped

        restart = cli.run(*planner_args, "--json", timeout=120)
        assert restart.returncode == 0, restart.stderr
        setpoints.undeclare()
    bridge.send_signal(signal.SIGINT)
    out, err = cli.finish(bridge)
    assert '"moves_rejected": 0' in out, out + err
    assert len(completed) == 3
    # the restart began from where the axis was: a move from 0.2 m to the first way point, then the run
    import json

    (report,) = json.loads(restart.stdout)
    assert report["moves"] == 4 and report["idle_ticks"] == [0, 0, 0]
