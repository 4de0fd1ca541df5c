"""``axisflow security add``: more identities with an existing folder's CA, admitted by its router —
files and certificates checked, refusals that write nothing, and a restarted router (real Zenoh
sessions on loopback) that lets the new identities do what their kind may and nothing more."""

from __future__ import annotations

import datetime as dt
import json
from pathlib import Path

import json5
import pytest
import zenoh
from axisflow.acquisition import AxisKeys, ZenohOptions, open_session
from axisflow.acquisition.bus.readiness import JoinedSubscriber
from axisflow.acquisition.bus.session import build_config
from cryptography import x509

from axisflow.deploy.processes import free_port, wait_until
from axisflow.deploy.security import (
    SecurityArgumentError,
    SecurityError,
    SecurityPlan,
    acl_config,
    add_roles,
    init_security,
)
from axisflow.deploy.security import add as security_add

KEYS = AxisKeys("a0")


def _snapshot(directory: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(directory.iterdir())}


def _router_config(directory: Path) -> dict:
    return json5.loads((directory / "router.json5").read_text())


def test_added_roles_get_certificates_of_the_folders_ca_and_the_router_admits_them(tmp_path):
    out = tmp_path / "sec"
    init_security(SecurityPlan(out, port=17995, days=30, prefix="cell"))
    before = _snapshot(out)
    added = add_roles(out, ("recorder-laptop", "planner-cell2"), days=3650)
    after = _snapshot(out)
    # every file of the folder is as it was, but router.json5; three new files per role
    assert {k: v for k, v in after.items() if k in before and k != "router.json5"} == {
        k: v for k, v in before.items() if k != "router.json5"
    }
    new = sorted(set(after) - set(before))
    roles = ("recorder-laptop", "planner-cell2")
    assert new == sorted(f"{r}.{e}" for r in roles for e in ("pem", "key", "json5"))
    assert (out / "recorder-laptop.key").stat().st_mode & 0o777 == 0o600
    ca = x509.load_pem_x509_certificate(before["ca.pem"])
    for role in added.added:
        cert = x509.load_pem_x509_certificate(after[f"{role}.pem"])
        cert.verify_directly_issued_by(ca)  # raises if not signed by the folder's CA
        assert cert.subject.rfc4514_string() == f"CN={role}"
        assert cert.not_valid_after_utc == ca.not_valid_after_utc  # 3650 days asked: capped at the CA's
        build_config(ZenohOptions(config_file=out / f"{role}.json5"))  # loads in zenoh, paths resolved
    assert added.roles == ("planner", "bridge", "recorder", "recorder-laptop", "planner-cell2")
    assert _router_config(out)["access_control"] == acl_config("cell", added.roles)
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary left
    assert "restart the router" in added.format()


def _hand_edit(out: Path) -> None:
    config = _router_config(out)
    config["access_control"]["rules"][0]["key_exprs"] = ["**"]
    (out / "router.json5").write_text(json.dumps(config))


@pytest.mark.parametrize(
    ("roles", "prepare", "error", "match"),
    [
        (("recorder",), None, SecurityError, r"role 'recorder' is already in .*: not reissuing it"),
        (("pilot",), None, SecurityArgumentError, "role 'pilot' is not one of planner, bridge, recorder"),
        (
            ("bridge-2", "bridge-2"),
            None,
            SecurityArgumentError,
            "roles bridge-2, bridge-2 name a role more than once",
        ),
        (("bridge-2",), lambda d: (d / "ca.key").unlink(), SecurityError, r"ca.key is missing: .*offline"),
        (("bridge-2",), _hand_edit, SecurityError, "not one `axisflow security init` wrote: edited by hand"),
        (
            ("bridge-2",),
            lambda d: (d / "router.json5").write_text("{oops"),
            SecurityError,
            r"router.json5 is not the JSON5 that `axisflow security init` writes \(line 1 ",
        ),
    ],
    ids=["existing-role", "unknown-kind", "twice", "no-ca-key", "hand-edited-acl", "broken-json"],
)
def test_refusals_name_the_reason_and_write_nothing(tmp_path, roles, prepare, error, match):
    out = tmp_path / "sec"
    init_security(SecurityPlan(out, port=17994, days=2))
    if prepare is not None:
        prepare(out)
    before = _snapshot(out)
    with pytest.raises(error, match=match):
        add_roles(out, roles)
    assert _snapshot(out) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sec"]


def test_a_failure_while_writing_leaves_the_folder_as_it_was(tmp_path, monkeypatch):
    out = tmp_path / "sec"
    init_security(SecurityPlan(out, port=17993, days=2))
    before = _snapshot(out)
    real = security_add.check_loads_in_zenoh

    def failing(name, text):
        if name == "router.json5":  # the last file: the new roles' files are written by then
            raise OSError(28, "No space left on device")
        real(name, text)

    monkeypatch.setattr(security_add, "check_loads_in_zenoh", failing)
    with pytest.raises(SecurityError, match="No space left on device"):
        add_roles(out, ("recorder-2",))
    assert _snapshot(out) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sec"]


def test_the_ca_validity_bounds_the_new_certificates(tmp_path):
    out = tmp_path / "sec"
    issued = dt.datetime(2026, 1, 1, tzinfo=dt.UTC)
    init_security(SecurityPlan(out, port=17992, days=10), now=issued)
    later = add_roles(out, ("planner-2",), days=365, now=issued + dt.timedelta(days=5))
    ca = x509.load_pem_x509_certificate((out / "ca.pem").read_bytes())
    assert later.not_after == ca.not_valid_after_utc
    with pytest.raises(SecurityError, match=r"the CA of .* expired on 2026-01-11"):
        add_roles(out, ("planner-3",), now=issued + dt.timedelta(days=11))


@pytest.mark.slow
def test_the_command_adds_and_refuses_with_one_line(cli, tmp_path):
    out = tmp_path / "sec"
    assert cli.run("security", "init", str(out), "--listen-port", "17991", "--days", "3").returncode == 0
    ok = cli.run("security", "add", str(out), "--roles", "recorder-laptop")
    assert ok.returncode == 0, ok.stderr
    assert "added recorder-laptop" in ok.stdout and "axisflow router --zenoh-config" in ok.stdout
    for args, match in [
        (["--roles", "recorder-laptop"], "role 'recorder-laptop' is already in"),
        (["--roles", "pilot"], "role 'pilot' is not one of"),
        (["--roles", "bridge-2", "--days", "0"], "argument --days: 0 must be >= 1"),
    ]:
        bad = cli.run("security", "add", str(out), *args)
        assert bad.returncode == 2 and match in bad.stderr and "Traceback" not in bad.stderr, bad.stderr
        assert bad.stderr.strip().count("\n") == 0
    missing = cli.run("security", "add", str(tmp_path / "nothing"), "--roles", "bridge-2")
    assert missing.returncode == 2 and "does not exist or is not a folder" in missing.stderr


def _drain(sub) -> list[bytes]:
    out = []
    while (sample := sub.try_recv()) is not None:
        out.append(sample.payload.to_bytes())
    return out


@pytest.mark.slow
def test_a_restarted_router_admits_the_added_identities_with_their_kinds_rights(tmp_path):
    """After the add and a router start with the rewritten file, the added planner's move reaches a
    bridge identity, the added recorder hears the bridge's telemetry, and the
    added recorder's own put reaches no one else."""
    port = free_port()
    out = tmp_path / "sec"
    init_security(SecurityPlan(out, port=port, days=2))
    add_roles(out, ("planner-cell2", "recorder-laptop"))

    def options(name: str) -> ZenohOptions:
        return ZenohOptions(config_file=out / f"{name}.json5")

    with (
        open_session(options("router")),
        open_session(options("bridge")) as bridge,
        open_session(options("planner-cell2")) as planner,
        open_session(options("recorder-laptop")) as recorder,
    ):
        handler = lambda: zenoh.handlers.FifoChannel(100)  # noqa: E731
        with (  # joined: the router has both subscriptions
            JoinedSubscriber(bridge, KEYS.trajectory, handler) as moves,
            JoinedSubscriber(recorder, "axisflow/**", handler) as heard,
        ):
            recorder.put(KEYS.trajectory, b"recorder-laptop move")
            # a liveliness query round trip (a recorder may make one): the router has refused that
            # move (or passed it on) before it takes the planner's
            list(recorder.liveliness().get("axisflow/**", timeout=10.0))
            planner.put(KEYS.trajectory, b"planner-cell2 move")
            bridge.put(KEYS.state, b"bridge state")
            got_moves: list[bytes] = []
            got_heard: list[bytes] = []

            def both_came() -> bool:
                got_moves.extend(_drain(moves.subscriber))
                got_heard.extend(_drain(heard.subscriber))
                return b"planner-cell2 move" in got_moves and b"bridge state" in got_heard

            assert wait_until(both_came, 10.0)
    # the added recorder's move was denied at the router: had it passed, it would have come first
    assert got_moves == [b"planner-cell2 move"]
    assert b"bridge state" in got_heard  # the added recorder hears the bridge's telemetry
