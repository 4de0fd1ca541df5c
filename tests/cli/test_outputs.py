"""What the long-running commands print, and where: a result once, on stdout; progress and the
start-up line on stderr."""

from __future__ import annotations

import json
import os

import pytest


@pytest.mark.slow
def test_the_planner_prints_each_runs_summary_once_on_stdout(cli, tmp_path, port):
    endpoint = f"tcp/127.0.0.1:{port}"
    bridge = cli.start("bridge", "--sim", "--speed", "0", "--listen", endpoint, ready=True)
    cli.wait_ready(bridge)
    points = tmp_path / "points.txt"
    points.write_text("0.1\n0.7\n0.2\n")
    args = ("--waypoints", str(points), "--law", "poly5,poly7", "--lookahead-s", "3", "--connect", endpoint)
    done = cli.run("planner", *args, timeout=300)
    assert done.returncode == 0, done.stderr
    summaries = [line for line in done.stdout.splitlines() if line.strip()]
    assert [s.split(" (")[0] for s in summaries] == ["min-time poly5", "min-time poly7"]
    assert not any(s in done.stderr for s in summaries)  # once: not also among the progress lines
    quiet = cli.run("planner", *args, "--json", timeout=300)
    assert quiet.returncode == 0 and quiet.stderr == "", quiet.stderr
    assert [r["law"] for r in json.loads(quiet.stdout)] == ["poly5", "poly7"]
    cli.launcher.stop(bridge)


@pytest.mark.slow
def test_a_starting_bridge_says_what_it_runs_in_one_line(cli, port):
    done = cli.run(
        "bridge", "--sim", "--axis", "x7", "--duration", "0.1", "--listen", f"tcp/127.0.0.1:{port}"
    )
    assert done.returncode == 0, done.stderr
    (line,) = done.stderr.splitlines()
    pid = line.rsplit(" ", 1)[1]
    assert pid.isdigit() and int(pid) != os.getpid()
    for fragment in (
        "axisflow bridge: axis x7",
        f"listening on tcp/127.0.0.1:{port}",
        "simulated axis, plant ideal (packaged plant_ideal.toml), 1 kHz at 1× real time for 0.1 s",
        "stop it with Ctrl-C or kill -TERM",
    ):
        assert fragment in line, line
    assert done.stdout.startswith("bridge: 100 ticks")  # the report, on stdout
    quiet = cli.run("bridge", "--sim", "--duration", "0.1", "--json", "--listen", f"tcp/127.0.0.1:{port}")
    assert quiet.stderr == "" and json.loads(quiet.stdout)["ticks"] == 100
