"""Who may command an axis, with the files of ``security init``: real Zenoh sessions on loopback — an
in-process secure router (mTLS + the default-deny ACL), a real bridge with the simulated axis, and a
client per role (each with its role's certificate)."""

from __future__ import annotations

import threading
from contextlib import contextmanager

import pytest
import zenoh
from axisflow.acquisition import AxisKeys, BridgeConfig, MoveCommand, MoveSender, MoveState, SimulatedAxis
from axisflow.acquisition.bridge.bridge import run_bridge
from axisflow.acquisition.bus.readiness import JoinedSubscriber
from axisflow.acquisition.bus.session import open_session
from axisflow.acquisition.drives.plant import load_plant
from axisflow.acquisition.wire.move_status import MoveStatus
from axisflow.model import load_params

from axisflow.deploy.processes import wait_until

pytestmark = pytest.mark.slow

KEYS = AxisKeys("a0")
PARAMS = load_params(None)


def _drain(sub) -> list:
    out = []
    while (sample := sub.try_recv()) is not None:
        out.append(sample)
    return out


def _through_the_router(session: zenoh.Session, identity: str) -> None:
    """A liveliness query round trip (each role may make one on the tokens it reads): once answered,
    the router has processed whatever this session sent before it — a denied message was dropped, an
    admitted one passed on. (A session sends its queued messages of a priority at least as high first:
    the query goes at DATA priority, moves and puts at DATA or above.)"""
    key = {"planner": KEYS.alive, "bridge": KEYS.senders}.get(identity.split("-")[0], "axisflow/**")
    list(session.liveliness().get(key, timeout=10.0))


class Watcher:
    """A recorder-identity session subscribed to everything under the prefix (what a recorder gets),
    joined: once created, nothing the router passes on to it is missed."""

    def __init__(self, session: zenoh.Session) -> None:
        self.samples: list[zenoh.Sample] = []
        handler = lambda: zenoh.handlers.FifoChannel(100_000)  # noqa: E731
        self._joined = JoinedSubscriber(session, "axisflow/**", handler).__enter__()
        self._sub = self._joined.subscriber
        self._open = True

    def collect(self) -> list[zenoh.Sample]:
        if self._open:
            self.samples += _drain(self._sub)
        return self.samples

    def on(self, key: str) -> list[zenoh.Sample]:
        return [s for s in self.collect() if str(s.key_expr) == key]

    def close(self) -> None:
        self.collect()
        self._open = False
        self._joined.__exit__()


@contextmanager
def secure_bridge(secure):
    """A real bridge (simulated axis, 2× real time) on the bridge identity, until the block ends."""
    stop = threading.Event()
    result = {}
    with open_session(secure.options("bridge")) as session:
        drive = SimulatedAxis(load_plant(None, PARAMS), PARAMS, axis="a0")
        config = BridgeConfig(keys=KEYS, speed=2.0)
        thread = threading.Thread(
            target=lambda: result.update(report=run_bridge(session, drive, PARAMS, config, stop))
        )
        thread.start()
        try:
            yield result
        finally:
            stop.set()
            thread.join(timeout=30)
            drive.close()
    assert not thread.is_alive()


@contextmanager
def watching(secure):
    with open_session(secure.options("recorder")) as session:
        watcher = Watcher(session)
        try:
            yield watcher
        finally:
            watcher.close()


def test_the_planners_moves_reach_the_bridge_and_the_recorder_sees_everything(secure, router):
    with watching(secure) as watcher, secure_bridge(secure) as bridge:
        with open_session(secure.options("planner")) as planner, MoveSender(planner, KEYS) as sender:
            assert sender.wait_for_bridge(10.0)
            sender.send(0.0, 0.2, 0.6)
            sender.send(0.2, 0.1, 0.6)
            done = sender.wait_status(2, {MoveState.COMPLETED}, 20.0)
            assert done is not None and done.state is MoveState.COMPLETED
            assert {s.state for s in sender.statuses if s.move_id == 1} >= {
                MoveState.ACCEPTED,
                MoveState.COMPLETED,
            }
        assert wait_until(lambda: len(watcher.on(KEYS.event)) >= 6, 10.0)
    report = bridge["report"]
    assert (report.moves_accepted, report.moves_completed, report.moves_rejected) == (2, 2, 0)
    assert len(watcher.on(KEYS.trajectory)) == 2  # the recorder identity reads moves ...
    assert len(watcher.on(KEYS.state)) > 100  # ... and telemetry


@pytest.mark.parametrize("identity", ["recorder", "bridge"])
def test_an_identity_other_than_the_planner_gets_no_move_to_the_bridge(secure, router, identity):
    """Its MoveSender (publisher, sender token, everything) is refused by the router: the bridge never
    hears of its move — not even to reject it — and a recorder records nothing of it. A planner's move
    sent afterwards shows the path works."""
    with (
        watching(secure) as watcher,
        secure_bridge(secure) as bridge,
        open_session(secure.options(identity)) as intruder,
        MoveSender(intruder, KEYS) as bad,
        open_session(secure.options("planner")) as planner,
        MoveSender(planner, KEYS) as good,
    ):
        assert good.wait_for_bridge(10.0)
        for _ in range(3):
            bad.send(0.0, 0.3, 0.8, move_id=666)
        _through_the_router(intruder, identity)  # the router has refused them (or passed them on) ...
        good.send(0.0, 0.2, 0.6, move_id=1)  # ... before it sees this one
        accepted = good.wait_status(1, {MoveState.ACCEPTED}, 10.0)
        assert accepted is not None and accepted.state is MoveState.ACCEPTED
        # the refusal, observed: move 1 reached the recorder identity, and 666, had it passed, would
        # have reached it first (the router passes on in the order it takes them)
        assert wait_until(lambda: watcher.on(KEYS.trajectory), 10.0)
        assert bad.poll_status() == []
    report = bridge["report"]
    assert (report.moves_accepted, report.moves_rejected, report.moves_missed) == (1, 0, 0)
    moves = [MoveCommand.decode(s.payload.to_bytes()) for s in watcher.on(KEYS.trajectory)]
    assert [m.move_id for m in moves] == [1]
    events = [MoveStatus.decode(s.payload.to_bytes()) for s in watcher.on(KEYS.event)]
    assert {e.move_id for e in events} == {1}


# (identity, key, delivered): every put that matters, observed by a recorder identity in another session
PUTS = [
    ("planner", KEYS.trajectory, True),
    ("planner", KEYS.stop, True),
    ("planner", KEYS.state, False),  # a planner cannot fake telemetry ...
    ("planner", KEYS.event, False),  # ... nor move statuses
    ("bridge", KEYS.state, True),
    ("bridge", KEYS.setpoint, True),
    ("bridge", KEYS.event, True),
    ("bridge", KEYS.trajectory, False),
    ("bridge", KEYS.stop, False),
    ("planner", KEYS.plan, True),  # its plan records
    ("planner", KEYS.params, False),  # it follows an adaptive node's estimates, it does not make them
    ("bridge", KEYS.params, False),
    ("adapter", KEYS.params, True),  # an adaptive node publishes estimates ...
    ("adapter", KEYS.trajectory, False),  # ... and cannot command the axis
    ("adapter", KEYS.stop, False),
    ("adapter", KEYS.state, False),
    ("recorder", KEYS.params, False),
    ("recorder", KEYS.state, False),  # a recorder only listens
    ("recorder", KEYS.trajectory, False),
    ("recorder", KEYS.stop, False),
    ("recorder", KEYS.event, False),
]


def test_each_identity_puts_only_on_its_keys(secure, router):
    names = ("planner", "bridge", "recorder", "adapter")
    sessions = {name: open_session(secure.options(name)) for name in names}
    try:
        with watching(secure) as watcher:  # joined: the router has its subscription
            for identity, key, _ in PUTS:
                for _ in range(3):
                    sessions[identity].put(key, f"{identity}->{key}".encode())
            for identity, session in sessions.items():
                if identity != "adapter":  # it may make no query: its own last put is its barrier
                    _through_the_router(session, identity)  # each put refused or passed on by now ...
            sessions["adapter"].put(KEYS.params, b"adapter-end")  # (the router keeps a session's order)
            sessions["bridge"].put(KEYS.state, b"end")  # ... and this one passed on after them
            ends = {b"end", b"adapter-end"}
            assert wait_until(lambda: ends <= {s.payload.to_bytes() for s in watcher.collect()}, 10.0)
            got = {s.payload.to_bytes().decode() for s in watcher.collect()} - {"end", "adapter-end"}
    finally:
        for session in sessions.values():
            session.close()
    assert got == {f"{i}->{k}" for i, k, ok in PUTS if ok}


def test_a_quick_stop_reaches_a_bridge_identity_only_from_the_planner(secure, router):
    with open_session(secure.options("bridge")) as bridge_session:
        handler = lambda: zenoh.handlers.FifoChannel(100)  # noqa: E731
        with (
            JoinedSubscriber(bridge_session, KEYS.stop, handler) as stops,  # the router has it
            open_session(secure.options("planner")) as planner,
            open_session(secure.options("recorder")) as recorder,
        ):
            recorder.put(KEYS.stop, b"recorder")
            _through_the_router(recorder, "recorder")  # refused (or passed on) by now ...
            planner.put(KEYS.stop, b"planner")  # ... before the router takes this one
            got: list[bytes] = []

            def the_planners_came() -> bool:
                got.extend(sample.payload.to_bytes() for sample in _drain(stops.subscriber))
                return b"planner" in got

            assert wait_until(the_planners_came, 10.0)
    assert got == [b"planner"]  # the recorder's, had it passed, would have come first


def test_a_peer_without_a_valid_certificate_gets_nothing(secure, other_ca, router, tmp_path):
    """Zenoh's own open() of a TLS peer returns a session whatever the handshake did (the reason for
    the connection check); such a session, subscribed to everything while the bridge publishes, gets
    no sample and no router."""
    import json

    no_cert = tmp_path / "no-cert.json5"
    no_cert.write_text(
        json.dumps(
            {
                "mode": "peer",
                "connect": {"endpoints": [f"tls/127.0.0.1:{secure.port}"]},
                "listen": {"endpoints": []},
                "scouting": {"multicast": {"enabled": False}},
                "transport": {"link": {"tls": {"root_ca_certificate": str(secure.directory / "ca.pem")}}},
            }
        )
    )
    plain_tcp = zenoh.Config()
    plain_tcp.insert_json5("mode", '"peer"')
    plain_tcp.insert_json5("scouting/multicast/enabled", "false")
    plain_tcp.insert_json5("listen/endpoints", "[]")
    plain_tcp.insert_json5("connect/endpoints", json.dumps([f"tcp/127.0.0.1:{secure.port}"]))
    other = zenoh.Config.from_file(str(other_ca.config("recorder")))
    other.insert_json5("mode", '"peer"')
    other.insert_json5("listen/endpoints", "[]")
    for key in ("root_ca_certificate", "connect_certificate", "connect_private_key"):
        value = json.loads(other.get_json(f"transport/link/tls/{key}"))
        other.insert_json5(f"transport/link/tls/{key}", json.dumps(str(other_ca.directory / value)))
    configs = {
        "no certificate": zenoh.Config.from_file(str(no_cert)),
        "plain tcp": plain_tcp,
        "other CA": other,
    }
    with secure_bridge(secure) as bridge, watching(secure) as control:
        outsiders = {name: zenoh.open(config) for name, config in configs.items()}
        try:
            subs = {
                name: s.declare_subscriber("axisflow/**", zenoh.handlers.FifoChannel(10_000))
                for name, s in outsiders.items()
            }
            # the bridge publishes to the admitted control meanwhile: the outsiders had their chance
            assert wait_until(lambda: len(control.on(KEYS.state)) > 100, 30.0)
            received = {name: len(_drain(sub)) for name, sub in subs.items()}
            linked = {
                name: list(s.info.routers_zid()) + list(s.info.peers_zid()) for name, s in outsiders.items()
            }
            for sub in subs.values():
                sub.undeclare()
        finally:
            for s in outsiders.values():
                s.close()
        assert len(control.on(KEYS.state)) > 100  # the bridge was publishing all along
    assert received == {name: 0 for name in configs}
    assert linked == {name: [] for name in configs}
    assert bridge["report"].ticks > 0


def test_the_commands_take_the_files_router_bridge_record(cli, tmp_path):
    """`axisflow router`, `bridge` and `record` with the files of `security init`: the planner's move
    runs; a move sent with the recorder's identity reaches neither the bridge nor the recording."""
    import json
    import signal

    from axisflow.acquisition import iter_recording

    from axisflow.deploy.security import SecurityPlan, init_security

    from .conftest import Secure, free_port

    port = free_port()
    secure = Secure(tmp_path / "sec", port)
    init_security(SecurityPlan(secure.directory, port=port, days=1))
    router = cli.start("router", "--zenoh-config", str(secure.config("router")))
    assert wait_until(lambda: "listening on" in router.stdout_text(), 30.0)
    out = tmp_path / "session.mcap"
    rec = cli.start("record", "-o", str(out), "--zenoh-config", str(secure.config("recorder")), ready=True)
    cli.wait_ready(rec)  # joined: the router has its subscription
    bridge = cli.start(
        "bridge", "--sim", "--zenoh-config", str(secure.config("bridge")), "--duration", "60", "--json"
    )
    with (
        open_session(secure.options("planner")) as planner,
        MoveSender(planner, KEYS) as sender,
        open_session(secure.options("recorder")) as intruder,
        MoveSender(intruder, KEYS) as bad,
    ):
        assert sender.wait_for_bridge(30.0)
        bad.send(0.0, 0.3, 0.8, move_id=666)
        _through_the_router(intruder, "recorder")  # refused (or passed on) before move 1 ...
        sender.send(0.0, 0.2, 0.6, move_id=1)
        done = sender.wait_status(1, {MoveState.COMPLETED}, 20.0)
        assert done is not None and done.state is MoveState.COMPLETED
        bad.send(0.2, 0.3, 0.8, move_id=667)
        _through_the_router(intruder, "recorder")  # ... and 667 before move 2
        sender.send(0.2, 0.1, 0.6, move_id=2)
        done = sender.wait_status(2, {MoveState.COMPLETED}, 20.0)
        assert done is not None and done.state is MoveState.COMPLETED
    # the recording holds move 2 (flushed every second) before the recorder stops: had 666 or 667
    # passed the router, the recorder would have had them first
    assert wait_until(lambda: cli.on_disk(out, "/axisflow/a0/trajectory") >= 2, 30.0)
    bridge.send_signal(signal.SIGINT)
    bridge_out, bridge_err = cli.finish(bridge)
    assert bridge.returncode == 0, bridge_err
    report = json.loads(bridge_out)
    assert (report["moves_accepted"], report["moves_rejected"], report["moves_missed"]) == (2, 0, 0)
    rec.send_signal(signal.SIGINT)
    _rec_out, rec_err = cli.finish(rec)
    assert rec.returncode == 0, rec_err
    router.send_signal(signal.SIGTERM)
    router_out, router_err = cli.finish(router)
    assert router.returncode == 0, router_err
    assert "router stopped" in router_out
    topics: dict[str, list[bytes]] = {}
    for m in iter_recording(out):
        topics.setdefault(m.channel.topic, []).append(m.message.data)
    assert [MoveCommand.decode(data).move_id for data in topics["/axisflow/a0/trajectory"]] == [1, 2]
    assert len(topics["/axisflow/a0/state"]) > 500
