"""``axisflow plan --law trapezoid|scurve``: the baseline laws from the command line."""

import json

import pytest
from axisflow.model import default_params, params_to_toml
from ruckig import InputParameter, Ruckig, Trajectory

from axisflow.cli import main


def _plan(capsys, *args):
    assert main(["plan", *args, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_scurve_takes_exactly_ruckigs_duration(capsys):
    out = _plan(capsys, "0.65", "0.12", "--law", "scurve", "--limits", "1.1,2.7,18")
    inp = InputParameter(1)
    inp.current_position, inp.target_position = [0.65], [0.12]
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = [1.1], [2.7], [18.0]
    traj = Trajectory(1)
    Ruckig(1).calculate(inp, traj)
    assert out["duration_s"] == traj.duration
    assert out["solver"] == "ruckig" and out["max_violation"] == 0.0
    assert out["energy_j"] > 0.0 and 0.0 < out["peak_torque_nm"] <= default_params().tau_max


def test_limits_from_the_parameter_files_baseline_table_and_a_stretch(tmp_path, capsys):
    path = tmp_path / "axis.toml"
    path.write_text(
        params_to_toml(default_params()) + "[baseline]\nvelocity_m_s = 1.0\nacceleration_m_s2 = 2.0\n"
    )
    fast = _plan(capsys, "0.1", "0.7", "--law", "trapezoid", "--params", str(path))
    assert fast["duration_s"] == pytest.approx(0.6 / 1.0 + 1.0 / 2.0, rel=1e-12)  # D/v + v/a
    slow = _plan(capsys, "0.1", "0.7", "--law", "trapezoid", "--params", str(path), "--t-min", "2")
    assert (
        slow["duration_s"] == pytest.approx(2.0, rel=1e-12) and slow["min_duration_s"] == fast["duration_s"]
    )
    assert slow["energy_j"] < fast["energy_j"]  # slower: less viscous friction, less kinetic energy
