"""A session that must connect and cannot is an error, not a deaf session: another CA's certificate,
nothing listening, an impossible address. The embedded default, alone, still opens."""

from __future__ import annotations

import json
import shutil
import time
from pathlib import Path

import json5
import pytest
from axisflow.acquisition import ZenohConfigError, ZenohConnectError, ZenohOptions, open_session
from axisflow.acquisition.bus.session import check_endpoint

from .conftest import free_port


def _as_peer(role_file: Path, out: Path) -> Path:
    """The role's file as a TLS peer that listens nowhere (absolute paths: written elsewhere)."""
    config = json5.loads(role_file.read_text())
    tls = config["transport"]["link"]["tls"]
    for key in ("root_ca_certificate", "connect_certificate", "connect_private_key"):
        tls[key] = str(role_file.parent / tls[key])
    config.update(mode="peer", listen={"endpoints": []})
    out.write_text(json.dumps(config))
    return out


@pytest.mark.slow
def test_a_certificate_of_another_ca_is_a_clear_error_not_a_hang(secure, other_ca, router, tmp_path):
    peer_file = _as_peer(other_ca.config("planner"), tmp_path / "peer.json5")
    # a client's open() fails, a peer's returns a deaf session: both are errors, within the wait
    for file, where in [
        (other_ca.config("planner"), "(client mode, connecting to"),
        (peer_file, "(peer mode) reached no router or peer at"),
    ]:
        t0 = time.monotonic()
        with pytest.raises(ZenohConnectError) as err:
            open_session(ZenohOptions(config_file=file, connect_wait_s=1.0))
        assert time.monotonic() - t0 < 10.0
        message = str(err.value)
        assert f"{where} tls/127.0.0.1:{secure.port}" in message
        assert "a certificate not signed by the CA the other side trusts" in message
        assert "\n" not in message
    with open_session(secure.options("planner", connect_wait_s=1.0)) as ok:  # the right CA connects
        assert list(ok.info.routers_zid())
    with open_session(
        ZenohOptions(config_file=_as_peer(secure.config("planner"), tmp_path / "ok.json5"))
    ) as ok:
        assert list(ok.info.routers_zid())  # and so does the right CA as a peer


@pytest.mark.slow
def test_a_client_with_no_router_running_is_a_clear_error(secure):
    port = free_port()  # nothing listens here
    with pytest.raises(ZenohConnectError, match=rf"client mode, connecting to tls/127.0.0.1:{port}\): .*"):
        open_session(secure.options("planner", connect=(f"tls/127.0.0.1:{port}",), connect_wait_s=1.0))


def test_a_peer_told_to_connect_where_nothing_listens_fails_after_the_bounded_wait():
    port = free_port()
    t0 = time.monotonic()
    with pytest.raises(ZenohConnectError, match=rf"at tcp/127.0.0.1:{port} within 0.5 s; likely: nothing"):
        open_session(ZenohOptions(connect=(f"tcp/127.0.0.1:{port}",), connect_wait_s=0.5))
    assert time.monotonic() - t0 < 10.0


def test_the_embedded_default_and_a_lone_listener_still_open_alone():
    with open_session(ZenohOptions(listen=(f"tcp/127.0.0.1:{free_port()}",))) as alone:
        assert list(alone.info.peers_zid()) == []
    with open_session(ZenohOptions()) as default:  # its connection to 7447 is optional
        assert default.info.zid()


@pytest.mark.parametrize(
    ("endpoint", "listen", "match"),
    [
        ("localhost", False, "is not of the form <proto>/<address>"),
        ("tcp/999.1.1.1:1", False, "host '999.1.1.1' is neither an IP address"),
        ("tcp/127.0.0.1", False, "has no <host>:<port> after tcp/"),
        ("tcp/127.0.0.1:99999", False, "port '99999' is not in 1…65535"),
        (
            "tcp/127.0.0.1:0",
            False,
            "port '0' is not in 1…65535 (port 0, any free port, is for --listen only)",
        ),
        ("tls/bad host:7448", False, "host 'bad host' is neither"),
        ("tls/-router:7448", False, "host '-router' is neither"),
        ("tcp/[::1:7447", False, "has no <host>:<port>"),
    ],
)
def test_impossible_endpoints_fail_at_once(endpoint, listen, match):
    with pytest.raises(ZenohConfigError, match=match.replace("(", r"\(").replace(")", r"\)")):
        check_endpoint(endpoint, listen)


@pytest.mark.parametrize(
    ("endpoint", "listen"),
    [
        ("tcp/127.0.0.1:7447", False),
        ("tls/axis-router.lan:7448", False),
        ("tcp/[::1]:7447", False),
        ("tcp/[::]:0", True),
        ("tcp/0.0.0.0:0", True),
        ("tcp/192.168.1.10:7447#iface=eth0", False),
        ("unixsock-stream//tmp/zenoh.sock", False),
    ],
)
def test_valid_endpoints_pass(endpoint, listen):
    assert check_endpoint(endpoint, listen) == endpoint


def test_bridge_with_an_impossible_connect_address_exits_2_at_once(cli):
    t0 = time.monotonic()
    result = cli.run("bridge", "--sim", "--connect", "tcp/999.1.1.1:1", "--duration", "1", timeout=60)
    assert result.returncode == 2, (result.stdout, result.stderr)
    assert result.stderr.strip().count("\n") == 0
    assert "host '999.1.1.1' is neither an IP address" in result.stderr
    assert "Traceback" not in result.stderr
    assert time.monotonic() - t0 < 30.0


@pytest.mark.slow
def test_bridge_connecting_to_a_closed_port_exits_2_with_one_line(cli):
    port = free_port()
    result = cli.run("bridge", "--sim", "--connect", f"tcp/127.0.0.1:{port}", "--duration", "1", timeout=60)
    assert result.returncode == 2, (result.stdout, result.stderr)
    assert result.stderr.strip().count("\n") == 0, result.stderr
    assert f"reached no router or peer at tcp/127.0.0.1:{port} within 5 s" in result.stderr
    assert "Traceback" not in result.stderr
    assert result.stdout == ""  # no report: the bridge never ran


@pytest.mark.parametrize(
    ("args", "match"),
    [
        ([], "axisflow router needs --zenoh-config FILE (e.g. DIR/router.json5) or --listen EP"),
        (["--mode", "peer", "--listen", "tcp/127.0.0.1:17995"], "runs in mode router, not --mode peer"),
    ],
)
@pytest.mark.slow
def test_router_command_user_errors_exit_2(cli, args, match):
    result = cli.run("router", *args, timeout=30)
    assert result.returncode == 2
    assert match in result.stderr and "Traceback" not in result.stderr


def test_router_refuses_a_role_file(cli, secure):
    result = cli.run("router", "--zenoh-config", str(secure.config("planner")), timeout=30)
    assert result.returncode == 2
    assert "is for mode client, not a router" in result.stderr


@pytest.mark.slow
def test_a_roles_four_files_copied_elsewhere_connect_from_any_working_directory(
    secure, router, tmp_path, monkeypatch
):
    host = tmp_path / "planner-host"
    host.mkdir()
    for name in ("ca.pem", "planner.pem", "planner.key", "planner.json5"):
        shutil.copy2(secure.directory / name, host / name)
    monkeypatch.chdir(tmp_path)
    with open_session(ZenohOptions(config_file=host / "planner.json5", connect_wait_s=5.0)) as session:
        assert list(session.info.routers_zid())


def test_a_missing_tls_file_is_named(secure, tmp_path):
    config = tmp_path / "planner.json5"
    config.write_text(secure.config("planner").read_text())  # its ca.pem etc. are not beside it
    with pytest.raises(ZenohConfigError, match=r"root_ca_certificate 'ca.pem' does not exist \(looked in"):
        open_session(ZenohOptions(config_file=config))
