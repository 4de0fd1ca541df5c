"""The loop as a new user runs it, with real processes: bridge + recorder + `axisflow excite`, then
`axisflow identify` validated on a recording of planned moves; and `axisflow demo`. One demo serves
the module: its test checks the session, and the excitation test validates its refit on the demo's
recording of the planner's moves (the same simulated plant)."""

import json
import math
import os
import signal
import subprocess
from pathlib import Path

import pytest
from axisflow.acquisition import load_plant
from axisflow.model import default_params

from axisflow.deploy.processes import Exited


@pytest.fixture(scope="module")
def demo(cli, tmp_path_factory) -> tuple[Exited, Path]:
    """One `axisflow demo` run for the module: how it ended, and its session folder. Three way points:
    two moves per row of Table 2, so each row still has a junction whose idle ticks count."""
    out = tmp_path_factory.mktemp("demo") / "session"
    return cli.run("demo", "--waypoints", "3", "--out", str(out), timeout=600), out


def _record(cli, path: Path, endpoint: str):
    rec = cli.start("record", "-o", str(path), "--connect", endpoint, ready=True)
    cli.wait_ready(rec)  # joined: its routes from the bridge are proven
    return rec


def _stop(cli, proc) -> str:
    proc.send_signal(signal.SIGINT)
    out, err = cli.finish(proc, timeout=60)
    assert proc.returncode == 0, err
    return out


@pytest.mark.slow
@pytest.mark.heavy
def test_excite_record_identify_recovers_the_plant_and_validates_on_planned_moves(cli, tmp_path, port, demo):
    endpoint = f"tcp/127.0.0.1:{port}"
    bridge = cli.start("bridge", "--sim", "--speed", "0", "--listen", endpoint, ready=True)
    cli.wait_ready(bridge)
    rec = _record(cli, tmp_path / "excite.mcap", endpoint)
    excite = cli.run("excite", "--connect", endpoint, "--json", timeout=300)
    assert excite.returncode == 0, excite.stderr
    _stop(cli, rec)
    _stop(cli, bridge)
    # validated on a separate recording: the planner's moves of the demo (both cases, every law), on
    # its own bridge of the same simulated plant
    done, session = demo
    assert done.returncode == 0, done.stderr[-3000:]
    valid = session / "experiment-refit.mcap"
    out = tmp_path / "refit"
    ident = cli.run("identify", str(tmp_path / "excite.mcap"), "--validate", str(valid),
                    "--out", str(out), "--json", timeout=300)  # fmt: skip
    assert ident.returncode == 0, ident.stderr
    report = json.loads(ident.stdout)
    truth = load_plant(None, default_params()).axis
    got = {name: p["value"] for name, p in report["parameters"].items()}
    std = {name: p["std"] for name, p in report["parameters"].items()}
    assert got["M_eq"] == pytest.approx(truth.M_eq, rel=0.02)
    combined = got["a1"] + math.pi / 2 * got["a3"]
    assert combined == pytest.approx(truth.a1 + math.pi / 2 * truth.a3, rel=0.02)
    assert got["a2"] == pytest.approx(truth.a2, rel=0.05)
    for name, true in (
        ("M_eq", truth.M_eq),
        ("a1", truth.a1),
        ("a2", truth.a2),
        ("a3", truth.a3),
        ("a4", truth.a4),
    ):
        assert abs(got[name] - true) <= 3 * std[name], (name, got[name], true, std[name])
    # the paper's 0.5 N·m maximum, beaten at least 2x on the separate recording; RMS at the noise floor
    assert report["validation"]["max_abs_nm"] < 0.25
    assert report["validation"]["rms_nm"] < 0.01  # the simulated torque sensor's noise, 0.01 N·m
    assert report["validation_nominal"]["rms_nm"] > 5 * report["validation"]["rms_nm"]
    assert {p.name for p in out.iterdir()} == {
        "params.toml",
        "report.json",
        "report.md",
        "fit.png",
        "effort.parquet",
    }


@pytest.mark.slow
@pytest.mark.heavy
def test_the_demo_closes_the_loop(tmp_path, demo):
    done, out = demo
    assert done.returncode == 0, done.stderr[-3000:]
    assert "Table 2, nominal parameters" in done.stdout and "Table 2, refit parameters" in done.stdout
    summary = json.loads((out / "demo.json").read_text())
    assert summary["idle_ticks"] == {"nominal": 0, "refit": 0}
    # it ends with the saving against a trapezoid at equal cycle time, measured beside the model's
    assert done.stdout.strip().splitlines()[-1] == summary["savings_line"]
    for run in ("equal-time", "matched-omega"):
        saved = summary["savings"][run]
        assert saved["measured_pct"] > 0.0
        assert saved["measured_pct"] == pytest.approx(saved["model_pct"], abs=0.5)  # refit: model ≈ axis
    for row, error in summary["energy_error_pct"]["refit"].items():
        assert abs(error) < 1.0, row  # the refit brings E_th and E_exp together ...
        assert abs(summary["energy_error_pct"]["nominal"][row]) > 3 * abs(error)  # ... the nominal does not
    written = ("excitation.mcap", "experiment-nominal.mcap", "experiment-refit.mcap", "table2-refit.json",
               "table2-nominal.md", "refit/params.toml", "refit/fit.png", "session.rrd", "figures/fig2.png",
               "figures/fig4a.png", "figures/fig4b.png", "figures/fig5a.png", "savings.mcap")  # fmt: skip
    for name in written:
        assert (out / name).is_file(), name
    window = json.loads((out / "refit" / "report.json").read_text())["log"]["window"]
    assert window["start_s"] == -0.2 and window["end_s"] > 100.0  # the excitation's moves, ~133 s
    from rerun.chunk import RrdReader

    paths = {str(c.entity_path) for c in RrdReader(str(out / "session.rrd")).store().stream()}
    assert any(p.startswith("/axes/a0/") for p in paths), sorted(paths)[:10]
    # the recordings open in rosbags and in rerun's MCAP importer
    from rosbags.highlevel import AnyReader

    with AnyReader([out / "experiment-refit.mcap"]) as bag:
        topics = {c.topic for c in bag.connections}
    assert {"/axisflow/a0/state", "/axisflow/a0/plan", "/axisflow/a0/event"} <= topics
    rrd = tmp_path / "refit.rrd"
    command = ["rerun", "mcap", "convert", str(out / "experiment-refit.mcap"), "-o", str(rrd)]
    conv = subprocess.run(command, capture_output=True, text=True, timeout=120, env={**os.environ, "CI": "1"})
    assert conv.returncode == 0, conv.stderr
    assert rrd.stat().st_size > 0
