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
