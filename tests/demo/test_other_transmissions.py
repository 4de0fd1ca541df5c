"""An axis of another kind through the whole loop, with real processes: the vertical ball-screw axis of
docs/axes (gravity as f0, asymmetric Coulomb and viscous friction) as the simulated plant of
`axisflow bridge --sim --plant FILE`, a few moves planned for it by `axisflow planner --params FILE`,
recorded, and `axisflow table2` of the recording: the measured energy agrees with the planned, and the
moves run back to back."""

import json
import signal
from pathlib import Path

import numpy as np
import pytest
from axisflow.model import load_params

pytestmark = [pytest.mark.slow]

AXIS = Path(__file__).parents[2] / "docs" / "axes" / "ball-screw.toml"


def _plant_file(path: Path) -> Path:
    """A plant file whose true axis is the parameter file itself (an ``[axis]`` table): the planner's
    model is the plant's, so E_th and E_exp differ only by the integration and the sensor noise."""
    lines = [
        "[axis.transmission]" if line == "[transmission]" else line for line in AXIS.read_text().splitlines()
    ]
    path.write_text('profile = "ball-screw"\n[axis]\n' + "\n".join(lines) + "\n")
    return path


def _stop(cli, proc) -> None:
    proc.send_signal(signal.SIGINT)
    _out, err = cli.finish(proc, timeout=60)
    assert proc.returncode == 0, err


def test_a_ball_screw_axis_with_gravity_and_asymmetric_friction_runs_through_bridge_planner_and_table2(
    cli, tmp_path, port
):
    params = load_params(AXIS)
    assert params.kind == "ball-screw" and params.f0 > 0 and params.da1 != 0 and params.da2 != 0
    endpoint = f"tcp/127.0.0.1:{port}"
    plant = _plant_file(tmp_path / "plant.toml")
    bridge = cli.start(
        "bridge", "--sim", "--plant", str(plant), "--params", str(AXIS), "--listen", endpoint, ready=True
    )
    cli.wait_ready(bridge)
    recording = tmp_path / "screw.mcap"
    rec = cli.start("record", "-o", str(recording), "--connect", endpoint, ready=True)
    cli.wait_ready(rec)
    planner = cli.run("planner", "--random", "4", "--params", str(AXIS), "--connect", endpoint, "--json")
    assert planner.returncode == 0, planner.stderr
    _stop(cli, rec)  # before the bridge: its stop's hello needs the bridge alive
    _stop(cli, bridge)
    done = cli.run("table2", str(recording), "--out", str(tmp_path / "t2"), "--json")
    assert done.returncode == 0, done.stderr
    (row,) = json.loads(done.stdout)["rows"]
    measured = row["measured"]
    assert measured["moves_completed"] == len(row["planned"]["durations_s"]) == 3
    assert measured["idle_ticks_total"] == 0
    assert abs(measured["energy_error_pct"]) < 1.0, measured
    assert all(s == "converged" for s in row["planned"]["statuses"])
    # the motor side of each recorded sample is the carriage's through the screw: θ = x/k, τ = F·k
    states = [d for _m, d in cli.decoded(recording, "/axisflow/a0/state")]
    position, angle = (np.array([d.position[j] for d in states]) for j in (0, 1))
    k = params.transmission.metres_per_radian
    assert angle * k == pytest.approx(position, abs=1e-9)
    assert position.min() >= -1e-4 and position.max() <= params.L + 1e-4
