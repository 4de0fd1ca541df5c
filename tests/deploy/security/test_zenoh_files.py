"""The Zenoh JSON5 files of a secure folder: written and read back through the json5 library, taken
by Zenoh's own parser, and read the way Zenoh reads them (comments, unquoted keys, trailing commas
accepted; duplicate keys refused by both)."""

from __future__ import annotations

import json

import pytest
import zenoh

from axisflow.deploy.security import SecurityError, SecurityPlan, add_roles, init_security
from axisflow.deploy.security.zenoh_files import (
    check_loads_in_zenoh,
    client_config,
    read_json5,
    router_config,
    to_json5,
)

ROLES = ("planner", "bridge", "recorder")


@pytest.mark.parametrize(
    "config",
    [
        router_config("tls/127.0.0.1:7448", "axisflow", ROLES),
        router_config("tls/[::1]:7448", "plant/cell1", ("planner-cell2", "recorder")),
        client_config("tls/robot.example:7448", "bridge"),
    ],
    ids=["router", "router-v6", "client"],
)
def test_written_files_read_back_equal_and_load_in_zenoh(tmp_path, config):
    text = to_json5(config, "a header\nof two lines")
    assert text.startswith("// a header\n// of two lines\n")
    check_loads_in_zenoh("x.json5", text)  # raises if zenoh refuses it
    path = tmp_path / "x.json5"
    path.write_text(text)
    assert read_json5(path) == config
    loaded = zenoh.Config.from_json5(text)
    assert json.loads(loaded.get_json("mode")) == config["mode"]
    assert json.loads(loaded.get_json("transport/link/tls")) | config["transport"]["link"][
        "tls"
    ] == json.loads(loaded.get_json("transport/link/tls"))


HAND_WRITTEN = """
// an operator's note
{
  mode: 'client', /* single quotes, a block comment */
  connect: { endpoints: ["tls/127.0.0.1:7448",], },   // trailing commas
  scouting: { multicast: { enabled: false } },
}
"""


def test_json5_that_zenoh_takes_is_read_too(tmp_path):
    zenoh.Config.from_json5(HAND_WRITTEN)  # zenoh takes it ...
    path = tmp_path / "hand.json5"
    path.write_text(HAND_WRITTEN)
    assert read_json5(path)["connect"] == {"endpoints": ["tls/127.0.0.1:7448"]}  # ... and so do we


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("{mode: 'peer', mode: 'client'}", r"\(Duplicate key \"mode\" found"),
        ("{oops", r"\(line 1 "),
        ("[1, 2]", "holds a JSON5 list, not a zenoh configuration object"),
        ("", "not the JSON5"),
    ],
    ids=["duplicate-key", "broken", "not-an-object", "empty"],
)
def test_what_zenoh_refuses_is_refused_with_the_file_named(tmp_path, text, match):
    if text and not text.startswith("["):
        with pytest.raises(zenoh.ZError):
            zenoh.Config.from_json5(text)
    path = tmp_path / "bad.json5"
    path.write_text(text)
    with pytest.raises(SecurityError, match=match) as exc:
        read_json5(path)
    assert str(path) in str(exc.value)


def test_a_missing_file_is_named(tmp_path):
    with pytest.raises(SecurityError, match=r"missing\.json5 is missing: not a folder written by"):
        read_json5(tmp_path / "missing.json5")


def test_security_add_takes_a_router_file_reformatted_by_hand(tmp_path):
    """Comments and trailing commas added to router.json5 (its ACL unchanged) do not stop `add`: the
    file is read as JSON5, not line by line."""
    out = tmp_path / "sec"
    init_security(SecurityPlan(out, port=17990, days=2))
    text = (out / "router.json5").read_text()
    edited = text.replace('mode: "router",', 'mode: "router", /* kept as the router */', 1)
    assert edited != text
    (out / "router.json5").write_text(edited + "// checked by the operator\n")
    added = add_roles(out, ("recorder-2",))
    assert "recorder-2" in added.roles
    assert read_json5(out / "router.json5")["access_control"]["subjects"][-1]["id"] == "recorder-2"
