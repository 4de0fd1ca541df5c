"""Roles limited to axes (``bridge@a0``, ``planner@a0``, ``recorder@a1``): the names, the access list
they give, and — through a real secure router on loopback with two real bridges — that each reaches
its own axes and nothing of the others."""

from __future__ import annotations

import re
import threading
from contextlib import ExitStack, contextmanager
from pathlib import Path

import pytest
import zenoh
from axisflow.acquisition import AxisKeys, BridgeConfig, MoveSender, MoveState, SimulatedAxis
from axisflow.acquisition.bridge.bridge import run_bridge
from axisflow.acquisition.bus.session import ZenohOptions, open_session
from axisflow.acquisition.drives.plant import load_plant
from axisflow.acquisition.wire.move_status import MoveStatus
from axisflow.model import load_params

from axisflow.deploy.processes import wait_until
from axisflow.deploy.security import SecurityArgumentError, SecurityPlan, acl_config, init_security, role_kind
from axisflow.deploy.security.access_control import acl_roles
from axisflow.deploy.security.add import add_roles
from axisflow.deploy.security.roles import how_to_run, role_axes

from ...conftest import free_port

PARAMS = load_params(None)
ROLES = ("planner@a0", "planner", "bridge@a0", "bridge@a1", "recorder@a1", "recorder")


@pytest.mark.parametrize(
    ("name", "kind", "axes"),
    [
        ("bridge@a0", "bridge", ("a0",)),
        ("planner-line2@a3", "planner", ("a3",)),
        ("bridge-m1@a0+a1", "bridge", ("a0", "a1")),
        ("recorder@Gantry_X", "recorder", ("Gantry_X",)),
        ("recorder-laptop", "recorder", ()),
    ],
)
def test_a_role_names_its_kind_and_the_axes_it_is_limited_to(name, kind, axes):
    assert (role_kind(name), role_axes(name)) == (kind, axes)


@pytest.mark.parametrize(
    "name", ["bridge@", "bridge@a/0", "bridge@*", "bridge@a0+", "pilot@a0", "bridge@a 0"]
)
def test_a_bad_axis_in_a_role_name_is_refused_naming_it(name):
    with pytest.raises(SecurityArgumentError, match=f"role {re.escape(repr(name))} is not one of .*@AXIS"):
        role_kind(name)


def test_a_role_limited_to_axes_is_granted_their_keys_only():
    acl = acl_config("plant/cell1", ("bridge-m1@a1+a2", "recorder@a1", "planner@a0", "planner"))
    rules = {r["id"]: r for r in acl["rules"]}
    assert rules["bridge-m1@a1+a2-1"]["key_exprs"] == [
        f"plant/cell1/{axis}/{kind}"
        for axis in ("a1", "a2")
        for kind in ("state", "setpoint", "event", "drive")
    ]
    assert rules["planner@a0-1"]["key_exprs"] == [
        "plant/cell1/a0/trajectory",
        "plant/cell1/a0/stop",
        "plant/cell1/a0/plan",
    ]
    assert rules["planner-1"]["key_exprs"] == [
        "plant/cell1/*/trajectory",
        "plant/cell1/*/stop",
        "plant/cell1/*/plan",
    ]
    assert {k for r in acl["rules"] if r["id"].startswith("recorder@a1") for k in r["key_exprs"]} == {
        "plant/cell1/a1/**"
    }
    # who listens stays cell-wide: a recorder of the whole cell must receive a limited bridge's data
    assert rules["bridge-m1@a1+a2-7"]["key_exprs"] == ["plant/cell1/**"]
    assert rules["bridge-m1@a1+a2-7"]["flows"] == ["egress"]
    # the list reads back into its prefix and roles (what `security add` relies on)
    assert acl_roles(acl, Path("router.json5")) == (
        "plant/cell1",
        ("bridge-m1@a1+a2", "recorder@a1", "planner@a0", "planner"),
    )


def test_how_to_run_a_limited_role_names_its_axis(tmp_path):
    assert "axisflow bridge --sim --axis a1 --zenoh-config" in how_to_run(tmp_path, "bridge@a1")
    assert "--keys plant/a1/** --zenoh-config" in how_to_run(tmp_path, "recorder@a1", "plant")
    assert "(and the same for a2)" in how_to_run(tmp_path, "bridge-m1@a1+a2")


# ---- through a real secure router -----------------------------------------------------------------------


@pytest.fixture(scope="module")
def cell(tmp_path_factory):
    """A secure folder with axis-limited roles, its router (in-process) and two bridges: bridge@a0 on
    a0, bridge@a1 on a1 (simulated axes at 2× real time), for the module's tests."""
    port = free_port()
    directory = tmp_path_factory.mktemp("secure") / "cell-security"
    init_security(SecurityPlan(directory, port=port, days=2, roles=ROLES))
    stop = threading.Event()
    reports: dict[str, object] = {}
    with ExitStack() as stack:
        stack.enter_context(open_session(ZenohOptions(config_file=directory / "router.json5")))
        threads = []
        for axis in ("a0", "a1"):
            session = stack.enter_context(
                open_session(ZenohOptions(config_file=directory / f"bridge@{axis}.json5"))
            )
            drive = SimulatedAxis(load_plant(None, PARAMS), PARAMS, axis=axis)
            stack.callback(drive.close)
            config = BridgeConfig(keys=AxisKeys(axis), speed=2.0)

            def run(session=session, drive=drive, config=config, axis=axis) -> None:
                reports[axis] = run_bridge(session, drive, PARAMS, config, stop)

            threads.append(threading.Thread(target=run))
            threads[-1].start()
        stack.callback(lambda: [t.join(timeout=30) for t in threads])
        stack.callback(stop.set)
        yield directory, reports


@contextmanager
def _session(directory: Path, role: str):
    with open_session(ZenohOptions(config_file=directory / f"{role}.json5")) as session:
        yield session


def _drain(sub) -> list[zenoh.Sample]:
    out = []
    while (sample := sub.try_recv()) is not None:
        out.append(sample)
    return out


def test_a_planner_limited_to_a0_moves_a0_and_its_move_to_a1_never_arrives(cell):
    directory, _reports = cell
    with _session(directory, "recorder") as watcher, _session(directory, "planner@a0") as session:
        events = watcher.declare_subscriber("axisflow/a1/event", zenoh.handlers.FifoChannel(10_000))
        with MoveSender(session, AxisKeys("a0")) as sender:
            assert sender.wait_for_bridge(10.0)
            sender.send(0.0, 0.1, 0.4)
            done = sender.wait_status(1, {MoveState.COMPLETED}, 20.0)
            assert done is not None and done.state is MoveState.COMPLETED
        statuses: list[MoveStatus] = []

        def completed_seen(sender_id: str) -> bool:
            statuses.extend(MoveStatus.decode(s.payload.to_bytes()) for s in _drain(events))
            return any(s.sender == sender_id and s.state is MoveState.COMPLETED for s in statuses)

        with MoveSender(session, AxisKeys("a1")) as denied:
            assert not denied.bridge_alive  # it does not even see a1's bridge token
            denied.send(0.0, 0.1, 0.4)
            # the cell-wide planner reaches a1: its move runs, every status of a1 is about it
            with _session(directory, "planner") as other, MoveSender(other, AxisKeys("a1")) as sender:
                assert sender.wait_for_bridge(10.0)
                sender.send(0.0, 0.1, 0.4)
                done = sender.wait_status(1, {MoveState.COMPLETED}, 20.0)
                assert done is not None and done.state is MoveState.COMPLETED
                assert wait_until(lambda: completed_seen(sender.sender_id), 10.0)
        events.undeclare()
    assert {s.sender for s in statuses} == {sender.sender_id}, (
        "the limited planner's move reached a1's bridge"
    )
    assert {MoveState.ACCEPTED, MoveState.COMPLETED} <= {s.state for s in statuses}


def test_a_recorder_limited_to_a1_hears_a1_and_nothing_of_a0(cell):
    directory, _reports = cell
    with _session(directory, "recorder@a1") as session:
        mine = session.declare_subscriber("axisflow/a1/**", zenoh.handlers.FifoChannel(100_000))
        others = session.declare_subscriber("axisflow/a0/**", zenoh.handlers.FifoChannel(100_000))
        heard: list[str] = []
        # while a1's bridge publishes 400 samples, a0's (at the same rate) would have published as many
        assert wait_until(
            lambda: len(heard.extend(str(s.key_expr) for s in _drain(mine)) or heard) >= 400, 20.0
        )
        denied = _drain(others)
        mine.undeclare()
        others.undeclare()
    assert {"axisflow/a1/state", "axisflow/a1/setpoint"} <= set(heard)
    assert denied == []


@pytest.mark.parametrize(
    ("role", "denied", "admitted"),
    [
        ("bridge@a0", "axisflow/a1/drive", "axisflow/a0/drive"),  # a bridge of a0 cannot speak for a1
        ("planner@a0", "axisflow/a1/plan", "axisflow/a0/plan"),  # a planner publishes its plans, on its axis
    ],
)
def test_a_role_limited_to_a0_cannot_publish_for_a1(cell, role, denied, admitted):
    directory, _reports = cell
    got: list[tuple[str, bytes]] = []
    with _session(directory, "recorder") as watcher, _session(directory, role) as session:
        sub = watcher.declare_subscriber("axisflow/**", zenoh.handlers.FifoChannel(100_000))

        def heard_mine() -> bool:
            session.put(denied, b"fake")  # first, on the same link and priority ...
            session.put(admitted, b"mine")  # ... as the admitted one
            got.extend((str(s.key_expr), s.payload.to_bytes()) for s in _drain(sub))
            return (admitted, b"mine") in got

        assert wait_until(heard_mine, 10.0, poll_s=0.05)
        sub.undeclare()
    assert (denied, b"fake") not in got


def test_security_add_admits_a_role_limited_to_an_axis(tmp_path):
    directory = tmp_path / "cell"
    init_security(
        SecurityPlan(directory, port=free_port(), days=2, roles=("planner@a0", "bridge@a0", "recorder"))
    )
    added = add_roles(directory, ("bridge@a2", "planner-line2@a2"), days=2)
    assert added.roles == ("planner@a0", "bridge@a0", "recorder", "bridge@a2", "planner-line2@a2")
    assert (directory / "bridge@a2.pem").is_file() and (directory / "planner-line2@a2.json5").is_file()
