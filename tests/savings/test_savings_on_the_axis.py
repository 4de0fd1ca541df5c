"""``axisflow savings`` end to end on a few way points: a real bridge, a real recorder, real MCAP."""

import itertools
import json

import numpy as np
import pytest
from axisflow.model import default_params

from axisflow.cli import main
from axisflow.savings.cycle_moves import moves_of_recording
from axisflow.savings.report import read_report

WAYPOINTS = (0.1, 0.62, 0.3, 0.75)


@pytest.mark.slow
def test_savings_runs_the_three_runs_through_the_bridge_and_reads_the_moves_back(tmp_path, capsys):
    points = tmp_path / "points.txt"
    points.write_text("".join(f"{x}\n" for x in WAYPOINTS))
    out = tmp_path / "sv"
    assert main(["savings", "--waypoints", str(points), "--out", str(out), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)["runs"]
    report = read_report(out / "savings.json")
    base = report.run("baseline")
    for label in ("equal-time", "matched-omega"):
        run = report.run(label)
        assert run.cycle_time_s == pytest.approx(base.cycle_time_s, rel=1e-6)  # equal cycle time
        assert summary[label]["saving_model_pct"] == pytest.approx(report.saving_pct(label, False))
    for run in report.runs:
        # every move measured from the recording; the nominal model misses the simulated plant's extra
        # friction (docs/plant.md): the measurement is above the model, by less than 10 %
        assert run.measured
        assert 1.0 < run.energy_measured_j / run.energy_model_j < 1.10
        assert all(m.peak_torque_measured_nm > 0.0 for m in run.moves)
    # the matched ω is the least energy the law spends on the cycle time: below the move-by-move plan
    assert report.run("matched-omega").energy_model_j < report.run("equal-time").energy_model_j
    assert (out / "savings.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # the recording's moves, in the order they ran: each run's three, after a positioning move
    ran = np.array(moves_of_recording(out / "savings.mcap", default_params()))
    cycle = np.array(list(itertools.pairwise(WAYPOINTS)))
    found = [k for k in range(len(ran) - 2) if np.allclose(ran[k : k + 3], cycle, atol=1e-9)]
    assert len(found) == 3
