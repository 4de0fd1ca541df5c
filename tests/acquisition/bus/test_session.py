"""Zenoh session configuration from the command-line options."""

import json

import pytest
import zenoh
from axisflow.acquisition import ZenohConfigError, ZenohOptions, build_config, open_session
from axisflow.acquisition.bus.session import RECONNECT_RETRY

from axisflow.deploy.processes import wait_until


def _get(config, key):
    return json.loads(config.get_json(key))


def test_embedded_default_is_loopback_peer_without_multicast():
    c = build_config(ZenohOptions())
    assert _get(c, "mode") == "peer"
    assert _get(c, "scouting/multicast/enabled") is False
    assert _get(c, "listen/endpoints") == ["tcp/127.0.0.1:7447", "tcp/127.0.0.1:0"]
    assert _get(c, "connect/endpoints") == ["tcp/127.0.0.1:7447"]
    assert _get(c, "transport/unicast/open_timeout") == 2000  # zenoh's own default: 10 000


def test_flags_override_and_listen_stays_on_loopback():
    c = build_config(ZenohOptions(mode="client", connect=("tcp/10.0.0.2:7447",)))
    assert _get(c, "mode") == "client"
    assert _get(c, "connect/endpoints") == ["tcp/10.0.0.2:7447"]
    assert _get(c, "listen/endpoints") == ["tcp/127.0.0.1:0"]


def test_config_file_then_flags(tmp_path):
    f = tmp_path / "z.json5"
    f.write_text('{ mode: "router", listen: { endpoints: ["tcp/127.0.0.1:17999"] } }')
    c = build_config(ZenohOptions(config_file=f, connect=("tcp/127.0.0.1:18000",)))
    assert _get(c, "mode") == "router"
    assert _get(c, "listen/endpoints") == ["tcp/127.0.0.1:17999"]
    assert _get(c, "connect/endpoints") == ["tcp/127.0.0.1:18000"]


@pytest.mark.parametrize(
    ("options", "match"),
    [
        (dict(mode="server"), "mode 'server' is not one of peer, client, router"),
        (dict(connect=("localhost",)), "endpoint 'localhost' is not of the form"),
    ],
)
def test_bad_options_rejected(options, match):
    with pytest.raises(ZenohConfigError, match=match):
        ZenohOptions(**options)


def test_bad_config_file_rejected(tmp_path):
    f = tmp_path / "z.json5"
    f.write_text("{ mode: ")
    with pytest.raises(ZenohConfigError, match="is invalid"):
        build_config(ZenohOptions(config_file=f))


def test_a_session_that_connects_retries_a_lost_link_quickly():
    c = build_config(ZenohOptions(mode="client", connect=("tcp/10.0.0.2:7447",)))
    assert _get(c, "connect/retry") == dict(RECONNECT_RETRY)
    assert RECONNECT_RETRY["period_max_ms"] <= 1000  # back within about a second of its router
    # the embedded default and a listener have nothing to retry
    assert _get(build_config(ZenohOptions()), "connect/retry") is None
    assert _get(build_config(ZenohOptions.loopback(listen_port=17998)), "connect/retry") is None


def test_a_client_reconnects_to_a_router_restarted_on_its_port(port):
    """A real router session closed and opened again on the same port: the client built from the
    command-line options finds it again by itself (its subscriber hears a put made after the
    restart) without being reopened."""
    router_options = ZenohOptions(mode="router", listen=(f"tcp/127.0.0.1:{port}",))
    client_options = ZenohOptions(mode="client", connect=(f"tcp/127.0.0.1:{port}",))
    router = open_session(router_options)
    try:
        with open_session(client_options) as client, open_session(client_options) as other:
            heard = client.declare_subscriber("test/reconnect", zenoh.handlers.FifoChannel(16))
            router.close()
            assert wait_until(lambda: not list(client.info.routers_zid()), 10.0)
            router = open_session(router_options)
            assert wait_until(lambda: list(client.info.routers_zid()), 10.0)
            assert wait_until(lambda: list(other.info.routers_zid()), 10.0)

            def delivered() -> bool:
                other.put("test/reconnect", b"after")
                return heard.try_recv() is not None

            assert wait_until(delivered, 10.0), "the subscriber was not declared again to the new router"
            heard.undeclare()
    finally:
        router.close()
