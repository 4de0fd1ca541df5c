"""`axisflow view` and `axisflow figures` as a user runs them: outputs, and bad input as one line, exit
code 2 and nothing half-written."""

from __future__ import annotations

import json
import os
import re
import shutil
import signal

import pytest
from axisflow.acquisition.logs.mcap_writer import Ros2McapWriter

from axisflow.cli import main


@pytest.fixture
def no_axis_log(tmp_path):
    path = tmp_path / "other.mcap"
    writer = Ros2McapWriter(path)
    channel = writer.channel_for("/camera/info", None, "json")
    writer.add(channel, 1, 1, 1, b"{}")
    writer.finish()
    return path


def test_a_log_view_is_saved_beside_the_log_by_default(cli, test_log, tmp_path, rrd_reader):
    log = tmp_path / "s.mcap"
    shutil.copy(test_log.path, log)
    done = cli.run("view", str(log))
    assert done.returncode == 0, done.stderr
    assert f"wrote {tmp_path / 's.rrd'}" in done.stdout
    assert len(rrd_reader(tmp_path / "s.rrd")["/axes/a0/position/measured"].stamp_ns) == test_log.ticks


def _listening_on(port: int) -> list[str]:
    """The local addresses (hex, as in /proc/net/tcp) of the sockets listening on ``port``."""
    found = []
    for table in ("/proc/net/tcp", "/proc/net/tcp6"):
        with open(table) as fh:
            for line in fh.readlines()[1:]:
                local, state = line.split()[1], line.split()[3]
                if state == "0A" and int(local.rsplit(":", 1)[1], 16) == port:
                    found.append(local.rsplit(":", 1)[0])
    return found


@pytest.mark.skipif(not os.path.exists("/proc/net/tcp"), reason="reads the Linux socket table")
def test_serve_binds_the_web_viewer_to_loopback_and_stops_it(cli, test_log, eventually):
    proc = cli.start("view", str(test_log.path), "--serve")
    eventually(lambda: "serving the view at" in proc.stdout_text(), 60, "the view serving its URL")
    line = proc.stdout_text()
    match = re.search(r"http://127\.0\.0\.1:(\d+)/\?url=rerun%2Bhttp%3A%2F%2F127\.0\.0\.1%3A(\d+)", line)
    assert match, line
    web, grpc = int(match[1]), int(match[2])
    for port in (web, grpc):
        assert _listening_on(port) == ["0100007F"], port  # 127.0.0.1 only
    proc.send_signal(signal.SIGINT)
    cli.finish(proc)
    assert proc.returncode == 0
    # the server stopped with the command
    eventually(lambda: not _listening_on(web) and not _listening_on(grpc), 10, "the ports closing")


def _bad_view_inputs(tmp_path, test_log, no_axis_log):
    not_mcap = tmp_path / "notes.mcap"
    not_mcap.write_text("not a recording\n")
    (tmp_path / "folder.rrd").mkdir()
    out = str(tmp_path / "out.rrd")
    return [
        (["view", str(tmp_path / "missing.mcap"), "-o", out], "does not exist"),
        (["view", str(not_mcap), "-o", out], "is not an MCAP file"),
        (["view", str(no_axis_log), "-o", out], r"holds no axis.*/camera/info"),
        (["view", str(test_log.path), "-o", str(tmp_path / "nowhere" / "x.rrd")], "does not exist"),
        (["view", str(test_log.path), "-o", str(tmp_path / "folder.rrd")], "is a directory"),
        (["view", "--live", "--keys", "axisflow/**/a**", "-o", out], "not a valid Zenoh key expression"),
        (["view", "--live"], "give -o FILE.rrd, --spawn or --serve"),
        (["view", str(test_log.path), "--live", "-o", out], "give no LOG.mcap"),
        (["view", str(test_log.path), "--duration", "3", "-o", out], "--live only"),
        (["view"], "nothing to view"),
        *(
            [(["view", str(test_log.path), "--spawn"], "--spawn needs a display")]
            if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))
            else []
        ),
    ]


def test_bad_view_input_is_one_line_exit_2_and_writes_nothing(tmp_path, test_log, no_axis_log, capsys):
    for args, message in _bad_view_inputs(tmp_path, test_log, no_axis_log):
        before = sorted(os.listdir(tmp_path))
        assert main(args) == 2, args
        lines = capsys.readouterr().err.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("axisflow view: error:"), (args, lines)
        assert re.search(message, lines[0]), (args, lines[0])
        assert sorted(os.listdir(tmp_path)) == before, args


def test_bad_figure_input_is_one_line_exit_2_and_writes_nothing(tmp_path, capsys):
    (tmp_path / "file").write_text("x")
    for args, message in (
        (["figures", "--out", str(tmp_path / "file")], "exists and is not a directory"),
        # refused before drawing (os.access says yes to root on /proc: the folder is tried, not asked)
        (
            ["figures", "--out", "/proc/x"],
            "output directory /proc/x cannot be created: /proc is not writable",
        ),
        (
            ["figures", "--out", str(tmp_path / "figs"), "--excitation", str(tmp_path / "no.mcap")],
            "does not exist",
        ),
        (
            ["figures", "--out", str(tmp_path / "figs"), "--recording", str(tmp_path / "file")],
            "not an MCAP file",
        ),
    ):
        assert main(args) == 2, args
        lines = capsys.readouterr().err.strip().splitlines()
        assert len(lines) == 1 and message in lines[0], (args, lines)
    assert sorted(os.listdir(tmp_path)) == ["file"]


def _view_under_a_file_size_limit(log, rrd, limit: int, precheck: bool = True):
    """``axisflow view LOG -o RRD`` in a process whose file-size limit is ``limit`` bytes (RLIMIT_FSIZE:
    what a full disk does to a writer, EFBIG); ``precheck=False`` turns the room check off, so that
    rerun's writer meets the limit."""
    import subprocess
    import sys

    code = (
        "import resource, sys; "
        f"resource.setrlimit(resource.RLIMIT_FSIZE, ({limit}, {limit})); "
        + (
            ""
            if precheck
            # the flush's timeout shortened too: now and then rerun's writer stops without an answer
            else "import axisflow.viz.outputs as o; o.MIN_FREE_BYTES = o.RRD_BYTES_PER_LOG_BYTE = 0; "
            "o.FLUSH_TIMEOUT_S = 5.0; "
        )
        + "from axisflow.cli import main; sys.exit(main())"
    )
    return subprocess.run(
        [sys.executable, "-c", code, "view", str(log), "-o", str(rrd)],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "CI": "1"},
    )


def _our_error_line(stderr: str) -> str:
    ours = [line for line in stderr.splitlines() if line.startswith("axisflow view: error:")]
    assert len(ours) == 1 and "Traceback" not in stderr, stderr
    return ours[0]


def test_a_view_without_room_for_its_rrd_is_refused_before_it_starts(test_log, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    done = _view_under_a_file_size_limit(test_log.path, out / "v.rrd", 200_000)
    assert done.returncode == 2, done.stderr
    line = _our_error_line(done.stderr)
    assert "0.2 MB of room (the process's file-size limit (ulimit -f)), the view needs about 17 MB" in line
    assert done.stdout == "" and list(out.iterdir()) == []


def test_a_view_whose_writer_fails_is_one_line_exit_2_and_leaves_no_file(test_log, tmp_path):
    """The 3 s log's .rrd (~0.7 MB) meets a 200 kB limit: rerun's writer stops, the final flush raises,
    and the command says so in one line of its own, leaving neither the .rrd nor a part file."""
    out = tmp_path / "out"
    out.mkdir()
    done = _view_under_a_file_size_limit(test_log.path, out / "v.rrd", 200_000, precheck=False)
    assert done.returncode == 2, done.stderr
    line = _our_error_line(done.stderr)
    # the writer's death, or (now and then, on a loaded machine) its silence
    assert re.search(
        "rerun could not finish the view: (File-writer thread shut down prematurely|Flush timed out)", line
    )
    assert "v.rrd was not written" in line
    assert list(out.iterdir()) == []


def test_a_view_of_a_log_with_a_damaged_chunk_says_what_it_skipped_and_goes_on(
    cli, damage, tmp_path, rrd_reader
):
    from axisflow.acquisition import read_joint_states
    from axisflow.acquisition.logs.synthetic_log import SyntheticLogSpec, write_synthetic_log

    whole, log = tmp_path / "whole.mcap", tmp_path / "damaged.mcap"
    write_synthetic_log(whole, SyntheticLogSpec(duration_s=3.0, chunk_size=64 * 1024))
    chunks = damage.chunks(whole)
    offset = damage.damage(whole, log, len(chunks) // 2, "flip")
    done = cli.run("view", str(log), "-o", str(tmp_path / "v.rrd"))
    assert done.returncode == 0, done.stderr
    lines = done.stderr.strip().splitlines()
    chunk = f"{log}: chunk {len(chunks) // 2 + 1} at byte {offset} cannot be read"
    assert len(lines) == 2 and all(line.startswith(f"axisflow view: warning: {chunk}") for line in lines)
    assert {line.rsplit(" messages of ", 1)[1].split()[0] for line in lines} == {
        "/axisflow/a0/state",
        "/axisflow/a0/setpoint",
    }
    kept = (
        len(read_joint_states(whole, "/axisflow/a0/state"))
        - read_joint_states(log, "/axisflow/a0/state", on_skip=lambda _s: None).holes[0].messages
    )
    assert len(rrd_reader(tmp_path / "v.rrd")["/axes/a0/position/measured"].stamp_ns) == kept < 3000


def test_view_of_a_cell_recording_shows_every_axis_or_the_ones_asked_for(tmp_path, capsys, rrd_reader):
    from axisflow.acquisition.logs.synthetic_log import SyntheticLogSpec

    from ..acquisition.logs.cell_log import write_cell_log

    log = write_cell_log(
        tmp_path / "cell.mcap", [SyntheticLogSpec(duration_s=0.3, axis=f"a{k}", seed=k) for k in range(3)]
    )
    assert main(["view", str(log), "-o", str(tmp_path / "all.rrd"), "--json"]) == 0
    assert [a["label"] for a in json.loads(capsys.readouterr().out)["axes"]] == ["a0", "a1", "a2"]
    args = ["view", str(log), "--axis", "a2", "--axis", "a0", "-o", str(tmp_path / "two.rrd"), "--json"]
    assert main(args) == 0
    assert [a["label"] for a in json.loads(capsys.readouterr().out)["axes"]] == ["a0", "a2"]
    entities = rrd_reader(tmp_path / "two.rrd")
    assert len(entities["/axes/a2/position/measured"].stamp_ns) == 300
    assert not any(path.startswith("/axes/a1/") for path in entities)
