"""Moves sent over Zenoh to a running bridge: queued back to back, bad ones rejected, the moves of a
sender that disappears dropped while the running one ends at rest, moves of senders without a
liveliness token refused (real sessions on tcp/127.0.0.1, in-process)."""

import itertools
import signal
import threading
import time
from contextlib import contextmanager

import numpy as np
import pytest
import zenoh
from axisflow.acquisition import (
    MOVE_TYPE,
    AxisKeys,
    AxisSample,
    BridgeConfig,
    MoveCommand,
    MoveSender,
    MoveState,
    MoveStatus,
    SimulatedAxis,
    ZenohOptions,
    load_plant,
    open_session,
    run_bridge,
)
from axisflow.acquisition.bus.publisher import SequencedPublisher, Traffic, wait_for_subscribers
from axisflow.acquisition.bus.readiness import JoinedSubscriber
from axisflow.model import AxisParams
from axisflow.model.transmission import Belt

from axisflow.deploy.processes import wait_until

PARAMS = AxisParams(
    m=20.0, transmission=Belt(J_m=1.5e-4, J_g=5e-5, J_p=2e-4, r=0.03, i_r=10.0), L=0.8,
    a1=100.0, a2=50.0, a3=20.0, a4=50.0, v_max=1.0, tau_max=3.0,
)  # fmt: skip
T0 = 1_700_000_000_000_000_000
KEYS = AxisKeys("a0")


def _drain(sub) -> list:
    out = []
    while (s := sub.try_recv()) is not None:
        out.append(s)
    return out


class _Bridge:
    """A bridge on its own thread with an observer session subscribed to state, setpoint and event."""

    def __init__(self, port: int, duration_s: float) -> None:
        self.port = port
        self.drive = SimulatedAxis(load_plant(None, PARAMS), PARAMS, T0, axis="a0")
        self.config = BridgeConfig(keys=KEYS, speed=2.0, duration_s=duration_s, wait_subscribers_s=10.0)
        self.report = None
        self.statuses: list[MoveStatus] = []

    def __enter__(self):
        self._bridge_session = open_session(ZenohOptions.loopback(listen_port=self.port))
        self._observer = open_session(ZenohOptions.loopback(connect_port=self.port))
        self._state = self._observer.declare_subscriber(KEYS.state, zenoh.handlers.RingChannel(1))
        self._joined = [  # joined: they miss nothing the bridge publishes
            JoinedSubscriber(self._observer, key, lambda n=n: zenoh.handlers.FifoChannel(n)).__enter__()
            for key, n in ((KEYS.setpoint, 20_000), (KEYS.event, 100))
        ]
        self.setpoints, self.events = (j.subscriber for j in self._joined)
        self._thread = threading.Thread(target=self._run)
        self._thread.start()
        return self

    def _run(self) -> None:
        self.report = run_bridge(self._bridge_session, self.drive, PARAMS, self.config)

    def _collect(self) -> None:
        self.statuses += [MoveStatus.decode(s.payload.to_bytes()) for s in _drain(self.events)]

    def wait_status(self, move_id: int, state: MoveState, timeout_s: float = 20.0) -> MoveStatus:
        def hits() -> list[MoveStatus]:
            self._collect()
            return [s for s in self.statuses if s.move_id == move_id and s.state is state]

        if not wait_until(hits, timeout_s):
            pytest.fail(
                f"no {state.name} status of move {move_id} within {timeout_s} s; got: {self.statuses}"
            )
        return hits()[0]

    def of(self, state: MoveState) -> list[MoveStatus]:
        return [s for s in self.statuses if s.state is state]

    def finish(self) -> list[AxisSample]:
        self._thread.join(timeout=30)
        assert not self._thread.is_alive()
        self._collect()
        return [AxisSample.decode(s.payload.to_bytes()) for s in _drain(self.setpoints)]

    def __exit__(self, *_exc):
        self._state.undeclare()
        for joined in self._joined:
            joined.__exit__()
        self._observer.close()
        self._thread.join(timeout=30)
        self._bridge_session.close()


@contextmanager
def _live_sender(port: int):
    """A planner's session and MoveSender that has found the bridge (closed on exit: the sender goes)."""
    with (
        open_session(ZenohOptions.loopback(connect_port=port)) as planner,
        MoveSender(planner, KEYS) as sender,
    ):
        assert sender.wait_for_bridge(10.0)
        yield sender


@pytest.mark.slow
def test_moves_queue_back_to_back_and_bad_ones_are_rejected(port):
    with _Bridge(port, duration_s=4.0) as bridge:
        with _live_sender(port) as sender:
            sender.send(0.0, 0.3, 0.7, law="poly5")
            sender.send(0.3, 0.1, 0.5, law="poly7")
            sender.send(0.5, 0.6, 0.5)  # jumps from 0.1 m: rejected
            sender.send(0.1, 0.7, 0.0005)  # shorter than a tick: 2250 m/s at its peak, rejected
            done = sender.wait_status(2, {MoveState.COMPLETED}, 20.0)  # the sender stays open while they run
            assert done is not None and done.state is MoveState.COMPLETED
            own = {(st.move_id, st.state) for st in sender.statuses}
        received = bridge.finish()
    r = bridge.report
    assert (r.moves_accepted, r.moves_rejected, r.moves_missed, r.moves_dropped) == (2, 2, 0, 0)
    rejected = {st.move_id: st for st in bridge.of(MoveState.REJECTED)}
    assert set(rejected) == {3, 4}
    assert "start_position_m = 0.5 m jumps 0.4 m" in rejected[3].text
    assert "peak velocity 2250 m/s exceeds v_max = 1.0 m/s" in rejected[4].text
    assert rejected[3].start_tick == rejected[3].end_tick == -1
    # each accepted move was accepted, started and completed, in that order, at the ticks it announced
    for move_id in (1, 2):
        life = [st for st in bridge.statuses if st.move_id == move_id]
        assert [st.state for st in life] == [MoveState.ACCEPTED, MoveState.STARTED, MoveState.COMPLETED]
        accepted, started, completed = life
        assert started.tick == accepted.start_tick and completed.tick == accepted.end_tick
    first, second = ({st.move_id: st for st in bridge.of(MoveState.ACCEPTED)}[i] for i in (1, 2))
    assert second.start_tick == first.end_tick  # appended: no idle tick
    assert second.end_tick - second.start_tick == 500
    # the sender saw the statuses of its own moves, and only those
    assert own >= {(1, MoveState.COMPLETED), (2, MoveState.COMPLETED), (3, MoveState.REJECTED)}
    x = np.array([s.position_m for s in received])
    stamps = np.array([s.stamp_ns for s in received])
    assert set(np.diff(stamps).tolist()) == {1_000_000}
    moving = np.flatnonzero(np.abs(np.diff(x)) > 0)
    start, end = moving[0], moving[-1] + 1
    assert end - start == 1200  # 700 ms + 500 ms with no idle tick in between
    assert x[start:end].max() == pytest.approx(0.3)
    assert x[-1] == pytest.approx(0.1)  # at rest at the end of the last accepted move
    assert bridge.drive.position_m == pytest.approx(0.1, abs=5e-4)


@pytest.mark.slow
def test_a_sender_that_disappears_mid_move_leaves_the_axis_at_rest_and_its_queue_dropped(port):
    with _Bridge(port, duration_s=5.0) as bridge:
        with _live_sender(port) as sender:
            sender.send(0.0, 0.6, 1.5, law="poly5")
            sender.send(0.6, 0.2, 1.0, law="poly5")
            bridge.wait_status(2, MoveState.ACCEPTED)
            # the planner's session ends while move 1 runs (1.5 s of drive time = 0.75 s here)
        received = bridge.finish()
    r = bridge.report
    assert (r.moves_accepted, r.moves_completed, r.moves_dropped) == (2, 1, 1)
    dropped = bridge.of(MoveState.DROPPED)
    assert [st.move_id for st in dropped] == [2] and "disappeared" in dropped[0].text
    assert bridge.of(MoveState.COMPLETED)[0].move_id == 1
    x = np.array([s.position_m for s in received])
    v = np.array([s.velocity_m_s for s in received])
    assert x.max() == pytest.approx(0.6)  # move 1 ran to its end ...
    assert x[-1] == pytest.approx(0.6) and v[-1] == 0.0  # ... and the axis holds there, at rest
    assert np.abs(v).max() <= PARAMS.v_max
    assert bridge.drive.position_m == pytest.approx(0.6, abs=5e-4)


@pytest.mark.slow
def test_at_speed_0_the_next_move_of_a_live_sender_starts_where_the_last_one_ends(port):
    # at speed 0 a 100 ms move runs in a few milliseconds of wall time: less than a sender may need to
    # see it start and send the next one; the bridge waits for it at the tick where the queue runs dry
    drive = SimulatedAxis(load_plant(None, PARAMS), PARAMS, T0, axis="a0")
    stop = threading.Event()
    reports = []
    with (
        open_session(ZenohOptions.loopback(listen_port=port)) as bridge_session,
        open_session(ZenohOptions.loopback(connect_port=port)) as observer,
    ):
        # a consumer that never holds the bridge back (at speed 0 it runs as fast as consumers allow)
        state = observer.declare_subscriber(KEYS.state, zenoh.handlers.RingChannel(1))
        config = BridgeConfig(keys=KEYS, speed=0.0, wait_subscribers_s=10.0)
        thread = threading.Thread(
            target=lambda: reports.append(run_bridge(bridge_session, drive, PARAMS, config, stop))
        )
        thread.start()
        try:
            with _live_sender(port) as sender:
                x = 0.0
                for k in range(5):
                    cmd = sender.send(x, 0.005 - x, 0.1)
                    x = 0.005 - x
                    assert sender.wait_status(cmd.move_id, {MoveState.STARTED}, 20.0) is not None, k
                assert sender.wait_status(cmd.move_id, {MoveState.COMPLETED}, 20.0) is not None
                accepted = [st for st in sender.statuses if st.state is MoveState.ACCEPTED]
        finally:
            stop.set()
            thread.join(timeout=30)
            state.undeclare()
    assert len(accepted) == 5
    assert [b.start_tick - a.end_tick for a, b in itertools.pairwise(accepted)] == [0, 0, 0, 0]
    assert reports and reports[0].moves_completed == 5


def test_moves_of_a_publisher_without_a_sender_token_are_refused(port):
    with _Bridge(port, duration_s=4.0) as bridge:
        with open_session(ZenohOptions.loopback(connect_port=port)) as other:
            pub = SequencedPublisher(other, KEYS.trajectory, MOVE_TYPE, Traffic.COMMAND)
            assert wait_for_subscribers([pub], 10.0)  # the bridge's move subscriber
            pub.put(MoveCommand(time.time_ns(), "a0", 7, 0, "poly5", 0.0, 0.1, 0.5).encode())
            status = bridge.wait_status(7, MoveState.REJECTED)
            pub.undeclare()
        bridge.finish()
    assert "its sender holds no liveliness token axisflow/a0/sender/*" in status.text
    assert status.sender == pub.gid.hex()
    assert bridge.report.moves_accepted == 0


def test_sender_finds_the_bridge_through_the_recorder_by_gossip(cli, tmp_path, port):
    """Recorder listens; bridge and sender only connect to it and must find each other."""
    out = tmp_path / "moves.mcap"
    rec = cli.start("record", "-o", str(out), "--listen", f"tcp/127.0.0.1:{port}", ready=True)
    cli.wait_ready(rec)
    # a long duration: the bridge must not exit before a loaded machine lets the sender find it;
    # it is stopped with SIGINT once the move is done
    bridge = cli.start("bridge", "--sim", "--connect", f"tcp/127.0.0.1:{port}", "--duration", "120", "--json")
    with (
        open_session(ZenohOptions.loopback(connect_port=port)) as planner,
        MoveSender(planner, AxisKeys()) as sender,
    ):
        assert sender.wait_for_bridge(30.0)
        cmd = sender.send(0.0, 0.2, 0.6)
        done = sender.wait_status(cmd.move_id, {MoveState.COMPLETED}, 30.0)
        assert done is not None and done.state is MoveState.COMPLETED, sender.statuses
    bridge.send_signal(signal.SIGINT)
    bridge_out, bridge_err = cli.finish(bridge)
    rec.send_signal(signal.SIGINT)
    rec_out, _ = cli.finish(rec)
    assert '"moves_accepted": 1' in bridge_out, bridge_err
    assert '"moves_completed": 1' in bridge_out
    assert "/axisflow/a0/trajectory" in rec_out


def test_a_test_can_drive_the_bridge_tick_by_tick(port):
    """Bridge.step() runs one tick: no clock, so a move's whole life can be checked tick by tick."""
    from axisflow.acquisition import Bridge

    drive = SimulatedAxis(load_plant(None, PARAMS), PARAMS, T0, axis="a0")
    config = BridgeConfig(keys=KEYS, speed=0.0)
    with (
        open_session(ZenohOptions.loopback(listen_port=port)) as session,
        Bridge(session, drive, PARAMS, config) as bridge,
        _live_sender(port) as sender,
    ):
        cmd = sender.send(0.0, 0.25, 0.6, law="poly7")

        def accepted_yet() -> bool:
            bridge.step()  # the intake validates on its own thread; a tick takes what it has
            return bridge.report.moves_accepted > 0

        assert wait_until(accepted_yet, 20.0, 0.001), bridge.report
        accepted = sender.wait_status(cmd.move_id, {MoveState.ACCEPTED}, 10.0)
        # the queue was empty: the move starts on the tick that accepted it
        assert accepted is not None and accepted.start_tick == accepted.tick == bridge.tick - 1
        assert accepted.end_tick - accepted.start_tick == 600
        for _ in range(accepted.end_tick - bridge.tick):
            bridge.step()
        assert sender.wait_status(cmd.move_id, {MoveState.COMPLETED}, 0.5) is None  # one tick to go
        bridge.step()  # tick end_tick: the move's end at rest
        completed = sender.wait_status(cmd.move_id, {MoveState.COMPLETED}, 10.0)
        assert completed is not None and completed.tick == accepted.end_tick
        assert completed.stamp_ns == T0 + completed.tick * 1_000_000
        for _ in range(300):
            bridge.step()
        assert drive.position_m == pytest.approx(0.25, abs=5e-4)
    assert bridge.report.ticks == bridge.tick and bridge.report.moves_completed == 1


@pytest.mark.slow
def test_a_sampled_move_and_a_polynomial_move_run_back_to_back(port):
    """A trajectory (knots 1 ms apart) sent with send_trajectory runs knot for knot; the poly5 move
    sent after it is appended with no idle tick."""
    from axisflow.model import SampledTrajectory

    w = 2 * np.pi * 1.5
    t = np.arange(0, 2001) * 1e-3  # 2 s: three periods
    v = 0.05 * w * np.sin(w * t)
    v[0] = v[-1] = 0.0
    path = SampledTrajectory(t, 0.05 * (1 - np.cos(w * t)), v, 0.05 * w * w * np.cos(w * t))  # from 0 m
    with _Bridge(port, duration_s=4.8) as bridge:
        with _live_sender(port) as sender:
            first = sender.send_trajectory(path)
            second = sender.send(path.x1_m, 0.4, 0.8, law="poly5")
            assert (
                sender.wait_status(second.move_id, {MoveState.COMPLETED}, 30.0).state is MoveState.COMPLETED
            )
        received = bridge.finish()
    accepted = {st.move_id: st for st in bridge.of(MoveState.ACCEPTED)}
    assert accepted[first.move_id].end_tick - accepted[first.move_id].start_tick == 2000
    assert accepted[second.move_id].start_tick == accepted[first.move_id].end_tick
    x = np.array([s.position_m for s in received])
    k0 = int(np.flatnonzero(np.abs(np.diff(x)) > 0)[0])  # the first tick in motion follows tick k0
    assert x[k0 : k0 + 2000] == pytest.approx(path.position_m[:2000], abs=1e-15)
    assert x[-1] == pytest.approx(0.4)
