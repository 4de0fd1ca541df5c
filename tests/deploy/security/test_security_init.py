"""``axisflow security init``: the files, their modes and contents, refusal to overwrite, bad
arguments, nothing left half-written."""

from __future__ import annotations

import datetime as dt
import ipaddress
import json
import stat

import pytest
import zenoh
from axisflow.acquisition.bus.session import RECONNECT_RETRY, ZenohOptions, build_config
from axisflow.acquisition.wire.keys import KeyExprError
from cryptography import x509
from cryptography.hazmat.primitives import serialization
from cryptography.x509.oid import ExtendedKeyUsageOID, NameOID

from axisflow.deploy.security import (
    ROLE_GRANTS,
    SecurityArgumentError,
    SecurityError,
    SecurityPlan,
    acl_config,
    certificates,
    init_security,
    parse_roles,
)

ROLES = ("planner", "bridge", "recorder")


def _mode(path) -> int:
    return stat.S_IMODE(path.stat().st_mode)


def _cert(path) -> x509.Certificate:
    return x509.load_pem_x509_certificate(path.read_bytes())


def _cn(cert: x509.Certificate) -> str:
    return cert.subject.get_attributes_for_oid(NameOID.COMMON_NAME)[0].value


def test_init_writes_a_ca_and_one_identity_per_role_with_private_keys_0600(tmp_path):
    out = tmp_path / "sec"
    result = init_security(SecurityPlan(out, days=30, port=17999))
    names = {"ca.pem", "ca.key"} | {
        f"{n}.{ext}" for n in ("router", *ROLES) for ext in ("pem", "key", "json5")
    }
    assert {p.name for p in out.iterdir()} == names
    assert {f.path.name for f in result.files} == names
    assert _mode(out) == 0o700
    for path in out.iterdir():
        assert _mode(path) == (0o600 if path.suffix == ".key" else 0o644), path.name
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary folder left

    ca = _cert(out / "ca.pem")
    assert ca.extensions.get_extension_for_class(x509.BasicConstraints).value.ca
    now = dt.datetime.now(dt.UTC)
    for name in ("router", *ROLES):
        cert = _cert(out / f"{name}.pem")
        assert _cn(cert) == name
        cert.verify_directly_issued_by(ca)
        assert cert.not_valid_after_utc - now == pytest.approx(
            dt.timedelta(days=30), abs=dt.timedelta(minutes=1)
        )
        usage = cert.extensions.get_extension_for_class(x509.ExtendedKeyUsage).value
        assert list(usage) == [
            ExtendedKeyUsageOID.SERVER_AUTH if name == "router" else ExtendedKeyUsageOID.CLIENT_AUTH
        ]
        key = serialization.load_pem_private_key((out / f"{name}.key").read_bytes(), password=None)
        assert key.public_key().public_numbers() == cert.public_key().public_numbers()
    san = _cert(out / "router.pem").extensions.get_extension_for_class(x509.SubjectAlternativeName).value
    assert san.get_values_for_type(x509.IPAddress) == [ipaddress.ip_address("127.0.0.1")]


def test_the_zenoh_files_load_and_say_mtls_tls_only_and_default_deny(tmp_path):
    out = tmp_path / "sec"
    init_security(SecurityPlan(out, port=17998, prefix="plant/cell1"))

    def get(config: zenoh.Config, key: str):
        return json.loads(config.get_json(key))

    router = build_config(ZenohOptions(config_file=out / "router.json5"))
    assert get(router, "mode") == "router"
    assert get(router, "listen/endpoints") == ["tls/127.0.0.1:17998"]
    assert get(router, "transport/link/protocols") == ["tls"]
    assert get(router, "transport/link/tls/enable_mtls") is True
    # relative paths in the file are resolved against its folder
    assert get(router, "transport/link/tls/listen_private_key") == str(out / "router.key")
    acl = get(router, "access_control")
    assert (acl["enabled"], acl["default_permission"]) == (True, "deny")
    assert {s["id"]: s["cert_common_names"] for s in acl["subjects"]} == {r: [r] for r in ROLES}
    assert all(r["permission"] == "allow" for r in acl["rules"])
    assert all(k.startswith("plant/cell1/") for r in acl["rules"] for k in r["key_exprs"])
    for role in ROLES:
        config = build_config(ZenohOptions(config_file=out / f"{role}.json5"))
        assert get(config, "mode") == "client"
        assert get(config, "connect/endpoints") == ["tls/127.0.0.1:17998"]
        assert get(config, "connect/retry") == dict(RECONNECT_RETRY)
        assert get(config, "transport/link/tls/connect_certificate") == str(out / f"{role}.pem")
        assert get(config, "transport/link/tls/enable_mtls") is True


def test_only_the_planner_may_put_moves_and_stops_and_the_recorder_puts_nothing():
    acl = acl_config("axisflow", ("planner", "bridge", "recorder", "planner-cell2", "adapter"))
    puts = {}
    for policy in acl["policies"]:
        rules = [r for r in acl["rules"] if r["id"] in policy["rules"]]
        puts[policy["subjects"][0]] = sorted(
            k for r in rules if "put" in r["messages"] and r["flows"] == ["ingress"] for k in r["key_exprs"]
        )
    assert puts == {
        "planner": ["axisflow/*/plan", "axisflow/*/stop", "axisflow/*/trajectory"],
        "planner-cell2": ["axisflow/*/plan", "axisflow/*/stop", "axisflow/*/trajectory"],
        "bridge": ["axisflow/*/drive", "axisflow/*/event", "axisflow/*/setpoint", "axisflow/*/state"],
        "recorder": [],
        "adapter": ["axisflow/*/params"],  # estimates only: never a move or a stop
    }
    assert set(ROLE_GRANTS) == {"planner", "bridge", "recorder", "adapter"}


def test_an_existing_folder_is_not_overwritten_without_force(tmp_path, capsys):
    out = tmp_path / "sec"
    init_security(SecurityPlan(out, port=17997))
    ca_before = (out / "ca.pem").read_bytes()
    with pytest.raises(SecurityError, match=r"exists \(14 entries\): not overwriting its keys; pass --force"):
        init_security(SecurityPlan(out, port=17997))
    assert (out / "ca.pem").read_bytes() == ca_before
    init_security(SecurityPlan(out, port=17997, roles=("planner",), force=True))
    assert (out / "ca.pem").read_bytes() != ca_before
    assert not (out / "bridge.pem").exists()  # replaced as a whole, not merged
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]
    (tmp_path / "file").write_text("x")
    with pytest.raises(SecurityError, match="exists and is not a directory"):
        init_security(SecurityPlan(tmp_path / "file", force=True))


def test_nothing_is_left_half_written_when_issuing_fails(tmp_path, monkeypatch):
    out = tmp_path / "sec"
    calls = []

    def failing(*args, **kwargs):
        calls.append(args)
        if len(calls) == 3:
            raise OSError(28, "No space left on device")
        return real(*args, **kwargs)

    real = certificates.issue_leaf
    monkeypatch.setattr(certificates, "issue_leaf", failing)
    with pytest.raises(SecurityError, match=r"cannot write .*sec: No space left on device"):
        init_security(SecurityPlan(out))
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        (
            dict(roles=("pilot",)),
            SecurityArgumentError,
            "role 'pilot' is not one of planner, bridge, recorder",
        ),
        (dict(roles=("router",)), SecurityArgumentError, "role 'router' is not one of"),
        (dict(roles=("Planner",)), SecurityArgumentError, "role 'Planner' is not one of"),
        (dict(roles=("planner", "planner")), SecurityArgumentError, "name a role more than once"),
        (dict(roles=()), SecurityArgumentError, "no role given"),
        (dict(days=0), SecurityArgumentError, r"validity = 0 days must be in 1…3650 days"),
        (dict(days=4000), SecurityArgumentError, r"validity = 4000 days must be in 1…3650 days"),
        (dict(port=70000), SecurityArgumentError, r"router port = 70000 must be in 1…65535"),
        (dict(host="999.1.1.1"), ValueError, "router host '999.1.1.1' is neither an IP address"),
        (dict(host="bad host"), ValueError, "router host 'bad host' is neither"),
        (dict(prefix="a//b"), KeyExprError, "key prefix 'a//b' is not a valid key-expression part"),
    ],
)
def test_bad_plans_are_rejected_with_the_value_named(tmp_path, kwargs, error, match):
    with pytest.raises(error, match=match):
        SecurityPlan(tmp_path / "sec", **kwargs)
    assert list(tmp_path.iterdir()) == []


def test_role_lists_are_parsed_and_checked():
    assert parse_roles("planner, bridge,recorder,planner-cell2") == (
        "planner",
        "bridge",
        "recorder",
        "planner-cell2",
    )
    with pytest.raises(SecurityArgumentError, match="names planner more than once"):
        parse_roles("planner,bridge,planner")
    with pytest.raises(SecurityArgumentError, match="names no role"):
        parse_roles(",")


@pytest.mark.slow
def test_the_command_writes_the_folder_and_refuses_to_overwrite_it(cli, tmp_path):
    out = tmp_path / "sec"
    first = cli.run(
        "security", "init", str(out), "--roles", "planner,recorder", "--days", "7", "--listen-port", "17996"
    )
    assert first.returncode == 0, first.stderr
    assert "wrote 11 files" in first.stdout and "axisflow router --zenoh-config" in first.stdout
    again = cli.run("security", "init", str(out))
    assert again.returncode == 2
    assert again.stderr.strip().count("\n") == 0 and "pass --force" in again.stderr
    assert cli.run("security", "init", str(out), "--force").returncode == 0


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (["--roles", "planner,pilot"], "role 'pilot' is not one of planner, bridge, recorder"),
        (["--days", "0"], "argument --days: 0 must be >= 1"),
        (["--listen-port", "70000"], "70000 is not a TCP port"),
        (["--host", "999.1.1.1"], "router host '999.1.1.1' is neither an IP address"),
    ],
)
@pytest.mark.slow
def test_bad_arguments_exit_2_with_one_line_and_write_nothing(cli, tmp_path, args, match):
    """(The checks themselves are tabled above on SecurityPlan; here the command's way of failing.)"""
    result = cli.run("security", "init", str(tmp_path / "sec"), *args)
    assert result.returncode == 2, result.stdout
    assert match in result.stderr
    assert "Traceback" not in result.stderr
    assert list(tmp_path.iterdir()) == []
