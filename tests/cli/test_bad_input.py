"""Bad input, catalogued: every command, as a new user would get it wrong. The catalogue is
tests/bad_input/ (one module per group of commands); this runs it.

Each case must end with exit code 2 and exactly one error line on stderr that names the value (and,
where there is one, the limit and its unit); no traceback, nothing on stdout, and the output it
would have written absent or unchanged — errors found by argparse (a value that is not a number, an
unknown choice) too: the command line turns them into one line (axisflow/cli/__init__.py). The same
list is docs/refusals.md, generated from the catalogue (tests/bad_input/page.py).

Beyond the line, every case checks that the input folder is byte for byte what it was and that the
working folder holds exactly what it held: nothing written, no stray temporary (``.part``) file.

The table runs in-process (``axisflow.cli.main``); the three slips our issue found, and piping into
``head``, run as real processes.
"""

from __future__ import annotations

import json
import math
import os
import signal
import struct
import subprocess
import sys
import time
from pathlib import Path

import pytest
from axisflow.acquisition import AxisSample
from axisflow.acquisition.logs.mcap_writer import Ros2McapWriter
from axisflow.acquisition.logs.synthetic_log import SyntheticLogSpec
from axisflow.acquisition.wire.messages import JOINT_STATE_TYPE, MOVE_TYPE
from axisflow.model import default_params

from axisflow.cli import main
from axisflow.deploy.security import SecurityPlan, init_security

from ..acquisition.logs.cell_log import write_cell_log
from ..bad_input import CASES
from ..bad_input.case import LOOPBACK
from ..bad_input.fleet import write_fleet_inputs
from ..bad_input.foreign_logs import write_foreign_logs
from ..bad_input.page import REFUSALS_PAGE, refusals_page
from ..bad_input.terms import write_terms_inputs

CLI = [sys.executable, "-c", "import sys; from axisflow.cli import main; sys.exit(main())"]
T0_NS = 1_700_000_000_000_000_000


def _recording(path: Path, *, schema: str = JOINT_STATE_TYPE, nan: bool = False, finish: bool = True) -> None:
    """A 2 s recording of /axisflow/a0/state: the axis at rest (or NaN torques in every other sample)."""
    writer = Ros2McapWriter(path)
    channel = writer.channel_for("/axisflow/a0/state", schema)
    for k in range(2000):
        torque = math.nan if nan and k % 2 else 0.05
        sample = AxisSample(T0_NS + k * 1_000_000, "a0", 0.4, 0.0, 12.0, 80.0, 0.0, torque)
        writer.add(channel, T0_NS + k * 1_000_000, T0_NS + k * 1_000_000, k + 1, sample.encode())
    if finish:
        writer.finish()


def _params_file(path: Path, **changes: object) -> None:
    data = default_params().to_dict()
    data.pop("M_eq")
    data.update(changes)
    path.write_text("".join(f"{k} = {v!r}\n".replace("'", '"') for k, v in data.items()))


@pytest.fixture(scope="module")
def inputs(tmp_path_factory, damage) -> Path:
    """The bad (and a few good) input files every case may name, in one folder."""
    d = tmp_path_factory.mktemp("inputs")
    _params_file(d / "unknown.toml", foo=1)
    _params_file(d / "negative.toml", m=-3.0)
    _params_file(d / "nan.toml", a1=math.nan)
    _params_file(d / "huge-mass.toml", m=1e308)
    _params_file(d / "stroke-mm.toml", L=800.0)
    _params_file(d / "weak-motor.toml", tau_max=0.25)
    _params_file(d / "fast-motor.toml", v_max=20.0, r=0.001)
    _params_file(d / "huge-friction.toml", a1=1e6)
    (d / "heavy-plant.toml").write_text("[scale]\nm = 1000.0\n")
    (d / "tiny.txt").write_text("0.1\n0.1\n1e-310\n5e-324\n0.4\n")
    (d / "garbage.toml").write_text("m = = 3\n[[[\n")
    (d / "bad.json5").write_text("{ mode: 'peer',\n")
    (d / "notes.txt").write_text("hello\n")
    (d / "far.state").write_bytes(struct.pack("<dd", 5.0, 0.0))  # x [m], v [m/s] as a bridge writes them
    (d / "fast.state").write_bytes(struct.pack("<dd", 0.4, 100.0))
    (d / "lossy-plant.toml").write_text('base = "realistic"\n[sample_clock]\ndrop_fraction = 0.9\n')
    (d / "outside.txt").write_text("0.1\n0.9\n")
    (d / "words.txt").write_text("0.1\nabc\n")
    (d / "one.txt").write_text("0.1\n")
    (d / "empty.mcap").write_bytes(b"")
    write_foreign_logs(d)
    write_terms_inputs(d)
    (d / "full").mkdir()
    (d / "full" / "keep.txt").write_text("a session\n")
    _recording(d / "still.mcap")
    (d / "bad-cell.toml").write_text(
        'router = "tcp/127.0.0.1:7447"\nrouters = 2\n[machine.a]\nrouter = true\n'
    )
    write_cell_log(
        d / "cell.mcap", [SyntheticLogSpec(duration_s=0.2, axis=f"a{k}", seed=k) for k in range(3)]
    )
    _recording(d / "existing.mcap")
    _recording(d / "wrong-schema.mcap", schema=MOVE_TYPE)
    _recording(d / "nan-samples.mcap", nan=True)
    (d / "truncated.mcap").write_bytes((d / "still.mcap").read_bytes()[:40])  # magic and header only
    write_fleet_inputs(d)
    init_security(SecurityPlan(d / "secure", days=2))
    (d / "still-link.mcap").symlink_to("still.mcap")
    (d / "still-link.rrd").symlink_to("still.mcap")
    os.link(d / "still.mcap", d / "still-hard.mcap")
    _recording(d / "viewed.mcap")
    (d / "viewed.rrd").write_text("an earlier view\n")
    for folder, name in (("refit", "params.toml"), ("tables", "table2.md"), ("figs", "fig4a.png")):
        (d / folder).mkdir()
        (d / folder / name).write_text("an earlier result\n")
    for k in range(len(damage.chunks(d / "still.mcap"))):  # every chunk's CRC wrong
        damage.damage(d / ("still.mcap" if k == 0 else "all-damaged.mcap"), d / "all-damaged.mcap", k, "crc")
    drive = "[drive]\nnode_id = {node}\nencoder_counts_per_rev = 131072\n{extra}"
    for name, can, node, extra in (
        ("drive-unknown", 'interface = "virtual"\nchannel = "bad-1"', 5, "speed = 3\n"),
        ("drive-node200", 'interface = "virtual"\nchannel = "bad-2"', 200, ""),
        ("drive-nope", 'interface = "pcan2"\nchannel = "x"', 5, ""),
        ("drive-socketcan", 'interface = "socketcan"\nchannel = "nocan7"', 5, ""),
        ("drive-nobody", 'interface = "virtual"\nchannel = "bad-nobody"', 9, 'pacing = "lockstep"\n'),
        ("drive-wall", 'interface = "virtual"\nchannel = "bad-3"', 5, 'pacing = "wall"\n'),
        ("drive-sock", 'interface = "socketcan"\nchannel = "nocan8"', 5, ""),
    ):
        (d / f"{name}.toml").write_text(f"[can]\n{can}\n" + drive.format(node=node, extra=extra))
    return d


def _snapshot(folder: Path, names: tuple[str, ...]) -> dict[str, bytes | None]:
    """The bytes of each file (a folder: its listing), None if absent."""
    out: dict[str, bytes | None] = {}
    for name in names:
        p = folder / name
        if p.is_dir():
            out[name] = "\n".join(sorted(str(q.relative_to(p)) for q in p.rglob("*"))).encode()
        else:
            out[name] = p.read_bytes() if p.exists() else None
    return out


def _error_line(err: str, command: str) -> str:
    """The one line of stderr, an error of ``axisflow COMMAND``."""
    lines = err.strip("\n").splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"axisflow {command}") and ": error: " in lines[0], err
    return lines[0]


@pytest.mark.parametrize("bad", CASES, ids=[c.id for c in CASES])
@pytest.mark.slow
def test_a_bad_input_is_one_line_exit_2_and_nothing_written(bad, inputs, tmp_path, capfd, monkeypatch):
    work = tmp_path / "work"
    work.mkdir()
    for p in inputs.iterdir():  # what a case must not touch is a copy of its own; the rest, links
        if p.name in bad.untouched:
            _copy(p, work / p.name)
        else:
            (work / p.name).symlink_to(p)
    monkeypatch.chdir(work)
    before = _snapshot(work, bad.untouched)
    inputs_before, work_before = _tree(inputs), _tree(work)
    t0 = time.monotonic()
    try:
        code = main(list(bad.args))
    except SystemExit as exc:  # argparse
        code = exc.code
    elapsed = time.monotonic() - t0
    out, err = capfd.readouterr()
    assert code == 2, err
    assert "Traceback" not in err and out == ""
    line = _error_line(err, bad.args[0])
    for fragment in bad.says:
        assert fragment in line, line
    assert _snapshot(work, bad.untouched) == before
    assert _tree(inputs) == inputs_before  # every file that was there is byte-identical, nothing new
    assert _tree(work) == work_before  # nothing written, no stray temporary (.part) file
    assert elapsed < 10.0  # refused at once, not after the work


def _tree(folder: Path) -> dict[str, bytes | str]:
    """Every entry under ``folder``, links not followed: a file's bytes, a link's target, "/" for a
    folder."""
    out: dict[str, bytes | str] = {}
    for root, folders, files in os.walk(folder):
        for name in folders + files:
            p = Path(root) / name
            rel = str(p.relative_to(folder))
            if p.is_symlink():
                out[rel] = f"-> {os.readlink(p)}"
            elif p.is_dir():
                out[rel] = "/"
            else:
                out[rel] = p.read_bytes()
    return out


# a listen endpoint whose port another process holds: one line naming it, for every command that listens
PORT_IN_USE = [
    ("bridge", "--sim", "--duration", "1"),
    ("record", "-o", "new.mcap", "--duration", "1"),
    ("replay", "still.mcap", "--no-wait"),
    ("view", "--live", "-o", "new.rrd", "--duration", "1"),
    ("router",),
]


@pytest.mark.parametrize("args", PORT_IN_USE, ids=[a[0] for a in PORT_IN_USE])
def test_a_port_in_use_is_one_line_naming_it(args, inputs, tmp_path, capfd, monkeypatch):
    import socket

    monkeypatch.chdir(tmp_path)
    for name in ("still.mcap",):
        (tmp_path / name).symlink_to(inputs / name)
    with socket.socket() as holder:
        holder.bind(("127.0.0.1", 0))
        holder.listen()
        endpoint = f"tcp/127.0.0.1:{holder.getsockname()[1]}"
        code = main([*args, "--listen", endpoint])
    out, err = capfd.readouterr()
    assert code == 2 and out == "" and "Traceback" not in err, err
    line = _error_line(err, args[0])
    assert line == f"axisflow {args[0]}: error: {endpoint} is in use"  # no repr, no Rust source path
    assert sorted(p.name for p in tmp_path.iterdir()) == ["still.mcap"]  # nothing written


@pytest.mark.slow
def test_a_second_bridge_on_an_axis_is_refused_naming_where_the_first_runs(cli, port):
    first = cli.start("bridge", "--sim", "--listen", f"tcp/127.0.0.1:{port}", ready=True)
    cli.wait_ready(first)
    second = cli.run("bridge", "--sim", "--connect", f"tcp/127.0.0.1:{port}", "--duration", "5", timeout=60)
    assert second.returncode == 2 and second.stdout == "" and "Traceback" not in second.stderr
    line = _error_line(second.stderr, "bridge")
    for fragment in (
        "axis 'a0' already has a bridge (it holds axisflow/a0/alive)",
        f"pid {first.pid} on host ",
        f"reached at tcp/127.0.0.1:{port}",
        "give this bridge another --axis",
    ):
        assert fragment in line, line
    other_axis = cli.run(
        "bridge", "--sim", "--axis", "a1", "--connect", f"tcp/127.0.0.1:{port}", "--duration", "0.1"
    )
    assert other_axis.returncode == 0, other_axis.stderr  # another axis is free
    assert first.poll() is None  # the first runs on


def _copy(src: Path, dst: Path) -> None:
    import shutil

    if src.is_dir():
        shutil.copytree(src, dst)
    else:
        shutil.copy2(src, dst)


def test_the_catalogue_covers_every_command():
    from axisflow.cli import COMMAND_MODULES

    commands = {m.removesuffix("_cmd").replace("_", "-") for m in COMMAND_MODULES}
    assert commands <= {c.args[0] for c in CASES}
    assert len(CASES) >= 30


# ---- as real processes: the slips of the issue, and pipes --------------------------------------------


def _run(*args: str, cwd: Path, timeout: float = 60.0) -> subprocess.CompletedProcess:
    return subprocess.run([*CLI, *args], capture_output=True, text=True, timeout=timeout, cwd=cwd)


@pytest.mark.slow
def test_the_three_slips_of_the_issue_fail_at_once_as_processes(inputs, tmp_path):
    # a bridge that cannot connect used to run deaf and exit 0
    t0 = time.monotonic()
    bridge = _run("bridge", "--sim", "--connect", "tcp/999.1.1.1:1", "--duration", "1", cwd=tmp_path)
    assert bridge.returncode == 2 and bridge.stdout == "" and len(bridge.stderr.splitlines()) == 1, (
        bridge.stderr
    )
    assert "'999.1.1.1' is neither an IP address" in bridge.stderr
    # a replay of a file with no complete message used to report "replayed 0 messages", exit 0
    replay = _run("replay", str(inputs / "truncated.mcap"), "--no-wait", *LOOPBACK, cwd=tmp_path)
    assert replay.returncode == 2 and replay.stdout == "" and len(replay.stderr.splitlines()) == 1, (
        replay.stderr
    )
    assert "holds no complete message to replay" in replay.stderr
    # an experiment into /proc/x used to plan for ~20 s before failing
    t0 = time.monotonic()
    exp = _run("experiment", "--out", "/proc/x", cwd=tmp_path)
    assert exp.returncode == 2 and exp.stdout == "" and len(exp.stderr.splitlines()) == 1, exp.stderr
    assert "output directory /proc/x cannot be created: /proc is not writable" in exp.stderr
    assert time.monotonic() - t0 < 10.0  # the 100-way-point experiment takes ~20 s: it did not run
    assert not Path("/proc/x").exists()


@pytest.mark.parametrize(
    "args",
    [
        ("params",),
        ("plan", "0.1", "0.5", "--json"),
        ("--help",),
        ("excite", "--plan-only"),
        ("experiment", "--out", "exp", "--waypoints", "3", "--solver", "exact"),
    ],
    ids=["params", "plan", "help", "excite", "experiment"],
)
@pytest.mark.slow
def test_a_reader_that_goes_away_is_not_an_error(args, tmp_path):
    """``axisflow … | head -1``: the reader closes the pipe; here before the first write, so the command
    always meets the broken pipe (with head it may not, for output smaller than the pipe's buffer)."""
    proc = subprocess.Popen(
        [*CLI, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path
    )
    proc.stdout.close()
    err = proc.stderr.read()
    proc.stderr.close()
    assert proc.wait(60) == 0, err
    assert err == ""


def test_head_gets_the_first_line(tmp_path):
    done = subprocess.run(
        f"{sys.executable} -m axisflow params | head -1",
        shell=True,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.stdout.split()[:3] == ["m", "=", "90"] and done.stderr == ""


# ---- moves shorter than one encoder count: planned at once as zero moves, never a spin -------------


@pytest.mark.timeout(60)
@pytest.mark.parametrize("x1", ["1e-310", "1e-320", "5e-324", "1e-6"])
@pytest.mark.parametrize(
    ("law", "case_", "solver"),
    [
        ("poly5", "min-time", "exact"),
        ("poly3", "min-time-energy", "exact"),
        ("poly7", "min-time", "ipopt"),
        ("poly5", "min-time-energy", "ipopt"),
        ("bang", "min-time", "exact"),
        ("least-energy", "min-time-energy", "exact"),
    ],
)
def test_a_move_below_one_encoder_count_is_a_zero_move(x1, law, case_, solver, capfd):
    """The issue: ``plan 0 1e-310`` spun at 100 % CPU. One count is 2π·0.04 m/131072 = 1.917 µm."""
    code = main(["plan", "0", x1, "--law", law, "--case", case_, "--solver", solver, "--json"])
    out, err = capfd.readouterr()
    assert code == 0 and err == ""
    plan = json.loads(out)
    assert plan["duration_s"] == 0.0 and plan["energy_j"] == 0.0 and plan["objective"] == 0.0
    if law.startswith("poly"):
        assert plan["message"].startswith("zero move: |x1 - x0| = ") and "(1.917e-06 m)" in plan["message"]


@pytest.mark.timeout(60)
def test_the_issue_s_tiny_move_returns_at_once_as_a_process(tmp_path):
    done = _run("plan", "0", "1e-310", "--json", cwd=tmp_path, timeout=30)
    assert done.returncode == 0 and done.stderr == "", done.stderr
    assert json.loads(done.stdout)["duration_s"] == 0.0


@pytest.mark.timeout(120)
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
@pytest.mark.slow
@pytest.mark.heavy  # a bound in wall time: alone, not beside another test's processes
def test_the_planner_with_tiny_way_points_ends_within_2_s_of_a_signal(cli, tmp_path, sig):
    """Way points within a count of each other (zero moves, not sent) among real moves, on a bridge at
    real time: mid-run (a plan record seen), the signal ends the planner within 2 s."""
    import zenoh
    from axisflow.acquisition import AxisKeys, ZenohOptions, open_session

    port = cli.free_port()
    bridge = cli.start("bridge", "--sim", "--listen", f"tcp/127.0.0.1:{port}", "--speed", "1")
    points = tmp_path / "tiny.txt"
    points.write_text("0.1\n0.1\n0.1000000000001\n0.5\n5e-324\n1e-310\n0.6\n0.2\n0.7\n0.3\n0.7\n0.1\n")
    with open_session(ZenohOptions.loopback(connect_port=port)) as session:
        plans = session.declare_subscriber(AxisKeys("a0").plan, zenoh.handlers.FifoChannel(1000))
        planner = cli.start("planner", "--waypoints", str(points), "--connect", f"tcp/127.0.0.1:{port}")
        deadline = time.monotonic() + 60.0
        while plans.try_recv() is None:  # the fact: the planner is mid-run
            assert planner.poll() is None, cli.finish(planner)
            assert time.monotonic() < deadline, "no plan record within 60 s"
            time.sleep(0.02)
        plans.undeclare()
    t0 = time.monotonic()
    planner.send_signal(sig)
    try:
        planner.wait(timeout=2.0)
    except subprocess.TimeoutExpired:
        pytest.fail(f"the planner still ran 2 s after {sig.name}")
    elapsed = time.monotonic() - t0
    err = planner.stderr_text()
    bridge.send_signal(signal.SIGTERM)
    cli.finish(bridge)
    assert elapsed < 2.0
    assert "Traceback" not in err, err
    assert planner.returncode == 130, err


def test_the_refusals_page_is_the_catalogue():
    assert REFUSALS_PAGE.read_text(encoding="utf-8") == refusals_page(), (
        "docs/refusals.md is out of date: run python tools/write_refusals_page.py"
    )
