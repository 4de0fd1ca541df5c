"""A cell's launch file (cell.toml) and `axisflow cell up`: the commands each machine runs, bad files
refused by name, and a whole cell started from a file and stopped with Ctrl-C (real processes)."""

from __future__ import annotations

import signal
import textwrap

import pytest
from axisflow.acquisition.logs.recorded_axes import recorded_axes

from axisflow.deploy.cell_file import CellFileError, load_cell_file
from axisflow.deploy.security import SecurityPlan, init_security

CELL = """
router = "tcp/192.168.10.5:7447"
listen = "tcp/0.0.0.0:7447"

[machine.hub]
router = true
recorder = "data/cell.mcap"

[machine.m1]
axes = ["a0", "a1"]

[machine.m2]
axes = ["a2"]
bridge = ["--drive-config", "m2.toml"]
"""


def _file(tmp_path, text: str, name: str = "cell.toml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def test_each_machine_runs_its_commands_in_order(tmp_path):
    cell = load_cell_file(_file(tmp_path, CELL))
    client = ("--mode", "client", "--connect", "tcp/192.168.10.5:7447")
    assert [(p.machine, p.args) for p in cell.processes()] == [
        ("hub", ("router", "--listen", "tcp/0.0.0.0:7447")),
        ("hub", ("record", "-o", str(tmp_path / "data" / "cell.mcap"), "--keys", "axisflow/**", *client)),
        ("m1", ("bridge", "--axis", "a0", "--prefix", "axisflow", "--sim", *client)),
        ("m1", ("bridge", "--axis", "a1", "--prefix", "axisflow", "--sim", *client)),
        ("m2", ("bridge", "--axis", "a2", "--prefix", "axisflow", "--drive-config", "m2.toml", *client)),
    ]
    assert [p.name for p in cell.processes("m1")] == ["bridge-a0", "bridge-a1"]
    assert cell.processes("hub")[1].command.endswith(
        "--keys 'axisflow/**' --mode client --connect tcp/192.168.10.5:7447"
    )


def test_with_security_each_process_takes_its_role_file(tmp_path):
    folder = tmp_path / "sec"
    init_security(SecurityPlan(folder, days=2, roles=("bridge@a0", "bridge-m1@a1+a3", "bridge", "recorder")))
    text = CELL.replace('listen = "tcp/0.0.0.0:7447"', 'security = "sec"')
    cell = load_cell_file(_file(tmp_path, text))
    configs = {p.name: p.args[p.args.index("--zenoh-config") + 1] for p in cell.processes()}
    assert configs == {
        "router": str(folder / "router.json5"),
        "recorder-hub": str(folder / "recorder.json5"),
        "bridge-a0": str(folder / "bridge@a0.json5"),
        "bridge-a1": str(folder / "bridge-m1@a1+a3.json5"),
        "bridge-a2": str(folder / "bridge.json5"),  # no role limited to a2: the cell-wide one
    }
    (folder / "bridge.json5").unlink()
    with pytest.raises(
        CellFileError, match=r"holds no bridge.json5 nor a bridge role limited to a2 .* --roles bridge@a2"
    ):
        load_cell_file(_file(tmp_path, text)).processes("m2")


@pytest.mark.parametrize(
    ("change", "says"),
    [
        (("router = ", "routr = "), r"unknown key\(s\) routr in the file; allowed: router, listen"),
        (('axes = ["a2"]', 'axes = ["a2"]\nspeed = 2'), r"unknown key\(s\) speed in \[machine.m2\]"),
        (
            ("[machine.m1]", "[machine.m1]\nrouter = true"),
            r"2 machines run the router \(hub, m1\): a cell has one",
        ),
        (("router = true", "router = false"), r"0 machines run the router \(none\)"),
        (('axes = ["a2"]', 'axes = ["a1"]'), "axis a1 is driven by machine m1 and by machine m2"),
        (('192.168.10.5:7447"', '192.168.10.5:99999"'), r"router: .*port '99999' is not in 1…65535"),
        (("cell.mcap", "cell.bag"), r"recorder = 'data/cell.bag' must end in .mcap"),
        (('["--drive-config", "m2.toml"]', '["--axis", "x"]'), "bridge gives --axis: the launch file sets"),
        (('axes = ["a2"]', 'axes = ["a/2"]'), r"\[machine.m2\] axes: axis name 'a/2'"),
        (('axes = ["a2"]\nbridge', "axes = []\nbridge"), r"\[machine.m2\] runs nothing"),
        (("router = true", 'router = "yes"'), r"router = 'yes' must be true or false"),
    ],
    ids=lambda v: v if isinstance(v, str) else None,
)
def test_a_bad_launch_file_is_refused_naming_the_key_and_value(tmp_path, change, says):
    old, new = change
    assert old in CELL
    with pytest.raises(CellFileError, match=says):
        load_cell_file(_file(tmp_path, CELL.replace(old, new, 1)))


def test_an_unknown_machine_is_refused_with_the_list(tmp_path):
    cell = load_cell_file(_file(tmp_path, CELL))
    with pytest.raises(CellFileError, match=r"--machine m9: .* has no such machine; it has hub, m1, m2"):
        cell.processes("m9")


@pytest.mark.slow
def test_cell_up_starts_a_whole_cell_from_its_file_and_ctrl_c_stops_it(cli, tmp_path, port, eventually):
    path = _file(
        tmp_path,
        f"""
        router = "tcp/127.0.0.1:{port}"

        [machine.hub]
        router = true
        recorder = "cell.mcap"

        [machine.m1]
        axes = ["a0", "a1"]
        """,
    )
    assert "m1: axisflow bridge --axis a1" in cli.run("cell", "up", str(path), "--print").stdout
    proc = cli.start("cell", "up", str(path), "--logs", str(tmp_path / "logs"), ready=True)
    cli.wait_ready(proc, 120)
    recording = tmp_path / "cell.mcap"
    for axis in ("a0", "a1"):
        eventually(
            lambda a=axis: cli.on_disk(recording, f"/axisflow/{a}/state") > 0, 30, f"{axis}'s samples on disk"
        )
    proc.send_signal(signal.SIGINT)
    _out, err = cli.finish(proc, 60)
    assert proc.returncode == 0, err
    for name in ("bridge-a0", "bridge-a1", "recorder-hub", "router"):
        assert f"{name}: exit code 0" in err
    assert [a.label for a in recorded_axes(recording)] == ["a0", "a1"]  # a complete file, both axes
