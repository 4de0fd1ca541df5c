"""Zenoh session configuration from the command-line options."""

import json

import pytest
from axisflow.acquisition import ZenohConfigError, ZenohOptions, build_config


def _get(config, key):
    return json.loads(config.get_json(key))


def test_embedded_default_is_loopback_peer_without_multicast():
    c = build_config(ZenohOptions())
    assert _get(c, "mode") == "peer"
    assert _get(c, "scouting/multicast/enabled") is False
    assert _get(c, "listen/endpoints") == ["tcp/127.0.0.1:7447", "tcp/127.0.0.1:0"]
    assert _get(c, "connect/endpoints") == ["tcp/127.0.0.1:7447"]


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


def test_a_new_session_settles_before_a_subscriber_is_declared(port):
    import time

    from axisflow.acquisition.bus.session import SUBSCRIBER_SETTLE_S, open_session, settle

    with open_session(ZenohOptions.loopback(listen_port=port)) as session:
        t0 = time.monotonic()
        settle(session)  # waits out the rest of the settling time ...
        first = time.monotonic() - t0
        t1 = time.monotonic()
        settle(session)  # ... once: a settled session waits no more
        again = time.monotonic() - t1
    assert 0.5 * SUBSCRIBER_SETTLE_S < first <= SUBSCRIBER_SETTLE_S + 0.05
    assert again < 0.01
