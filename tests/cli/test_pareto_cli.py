"""Command-line tests of issue 3: pareto, plan with the exact solver and the reference laws,
the experiment with --solver exact, and the planner benchmark's JSON shape."""

import json

import pytest
from axisflow.planner import Case

from axisflow.cli import main
from axisflow.experiment.table2_record import read_table2


def test_pareto_writes_json_and_a_png(tmp_path, capsys):
    out = tmp_path / "pareto"
    args = ["pareto", "--waypoints", "6", "--law", "poly5", "--law", "poly3", "--out", str(out)]
    assert main([*args, "--omega", "0", "--omega", "0.9", "--omega", "1"]) == 0
    data = json.loads((out / "pareto.json").read_text())
    assert [c["law"] for c in data["curves"]] == ["poly5", "poly3"]
    for curve in data["curves"]:
        assert curve["omega"] == [0.0, 0.9, 1.0]
        assert len(curve["total_time_s"]) == len(curve["total_energy_j"]) == 3
    assert data["time_optimal"]["total_time_s"] < min(min(c["total_time_s"]) for c in data["curves"])
    png = (out / "pareto.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10_000
    assert "wrote" in capsys.readouterr().out


def test_pareto_rejects_a_bad_omega(tmp_path, capsys):
    assert main(["pareto", "--waypoints", "4", "--omega", "2", "--out", str(tmp_path)]) == 2
    assert "omega = 2.0 is outside [0, 1]" in capsys.readouterr().err
    assert not (tmp_path / "pareto.json").exists()


def test_plan_defaults_to_exact_and_reports_a_certificate(capsys):
    assert main(["plan", "0.1", "0.7", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["solver"] == "exact" and out["status"] == "converged"
    assert out["certificate"]["t_lower_s"] < out["certificate"]["t_upper_s"] == out["duration_s"]
    assert main(["plan", "0.1", "0.7", "--solver", "ipopt", "--json"]) == 0
    ipopt = json.loads(capsys.readouterr().out)
    assert out["duration_s"] <= ipopt["duration_s"]


def test_plan_with_the_reference_laws(capsys):
    assert main(["plan", "0.1", "0.7", "--law", "bang", "--json"]) == 0
    bang = json.loads(capsys.readouterr().out)
    assert main(["plan", "0.1", "0.7", "--law", "poly5", "--json"]) == 0
    poly = json.loads(capsys.readouterr().out)
    assert bang["duration_s"] < poly["duration_s"]
    assert bang["profile"]["switch_fraction"] > 0.5
    assert main(["plan", "0.1", "0.7", "--law", "bang", "--case", "min-time-energy"]) == 2
    assert "the bang law is the minimum-time law" in capsys.readouterr().err


@pytest.mark.slow
def test_experiment_with_the_exact_solver_is_no_worse_than_ipopt(tmp_path, capsys):
    rows = {}
    for solver in ("exact", "ipopt"):
        out = tmp_path / solver
        args = [
            "experiment",
            "--waypoints",
            "12",
            "--seed",
            "4",
            "--solver",
            solver,
            "--out",
            str(out),
        ]
        assert main(args) == 0
        rows[solver] = read_table2(out / "table2.json").rows
    capsys.readouterr()
    for e, i in zip(rows["exact"], rows["ipopt"], strict=True):
        assert e.solver == "exact"
        assert (e.case, e.law) == (i.case, i.law)
        assert e.planned.max_violation == 0.0 and e.planned.status_counts == {"converged": 11}
        assert e.planned.objective_total <= i.planned.objective_total * (1 + 1e-9)
        if e.case is Case.MIN_TIME:
            assert e.planned.total_time_s <= i.planned.total_time_s
        assert e.time_limit_ratio > 1.0 and e.energy_limit_ratio >= 1.0
        assert len(e.limits.time_limits_s) == len(e.limits.energy_limits_j) == 11
    md = (tmp_path / "exact" / "table2.md").read_text()
    assert "Against the physical limit" in md and "T/T_limit" in md


def test_bench_planner_json_shape(capsys):
    assert main(["bench", "planner", "--moves", "60", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert set(data) == {"moves", "exact", "ipopt", "speedup_p50", "machine_reference"}
    assert data["moves"] == 60
    for solver in ("exact", "ipopt"):
        assert set(data[solver]) == {"p50_us", "p99_us"}
        assert 0 < data[solver]["p50_us"] <= data[solver]["p99_us"]
    assert data["speedup_p50"] > 1.0


def test_pareto_with_ipopt_is_never_better_than_the_exact_sweep(tmp_path):
    args = ["pareto", "--waypoints", "6", "--law", "poly5", "--omega", "0.5", "--omega", "0.9"]
    assert main([*args, "--out", str(tmp_path / "e")]) == 0
    assert main([*args, "--solver", "ipopt", "--out", str(tmp_path / "i")]) == 0
    exact = json.loads((tmp_path / "e" / "pareto.json").read_text())
    ipopt = json.loads((tmp_path / "i" / "pareto.json").read_text())
    assert (exact["solver"], ipopt["solver"]) == ("exact", "ipopt")
    for je, ji in zip(
        exact["curves"][0]["objective_total"], ipopt["curves"][0]["objective_total"], strict=True
    ):
        assert je <= ji * (1 + 1e-9)
        assert ji <= je * 1.01  # IPOPT (cap 10) lands close to the optimum on these moves
