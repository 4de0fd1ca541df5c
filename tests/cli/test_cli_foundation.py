import json
import os
import subprocess
import sys

import pytest
from axisflow.model import default_params
from axisflow.planner import DEFAULT_OMEGA, Case

from axisflow.cli import main
from axisflow.experiment.paper import PAPER_TABLE2
from axisflow.experiment.table2_record import Table2, read_table2

PARAM_KEYS = [
    "m",
    "J_m",
    "J_g",
    "J_p",
    "r",
    "i_r",
    "L",
    "a1",
    "a2",
    "a3",
    "a4",
    "v_max",
    "tau_max",
    "M_eq",
    "energy_accounting",
]


def test_params_json_has_exactly_the_documented_keys(capsys):
    assert main(["params", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert list(data) == PARAM_KEYS
    assert data["i_r"] == 10.0 and data["L"] == 0.8


def test_params_from_a_file(tmp_path, capsys):
    main(["params", "--json"])
    data = json.loads(capsys.readouterr().out)
    data.pop("M_eq")
    data["a1"] = 42.0
    f = tmp_path / "axis.toml"
    f.write_text("\n".join(f'{k} = "{v}"' if isinstance(v, str) else f"{k} = {v!r}" for k, v in data.items()))
    assert main(["params", "--params", str(f), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["a1"] == 42.0


def test_bad_parameter_file_is_a_one_line_error_without_traceback(tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text("m = -3.0\n")
    proc = subprocess.run(
        [sys.executable, "-m", "axisflow", "params", "--params", str(f), "--json"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr
    assert "missing key(s)" in proc.stderr and str(f) in proc.stderr
    assert proc.stdout == ""


def test_plan_rejects_a_move_outside_the_stroke(capsys):
    assert main(["plan", "0.1", "0.95", "--json"]) == 2
    err = capsys.readouterr().err
    assert "x1_m = 0.95 m is outside the stroke [0, 0.8] m" in err


def test_plan_rejects_omega_outside_0_1(capsys):
    assert main(["plan", "0.1", "0.5", "--case", "min-time-energy", "--omega", "1.2"]) == 2
    assert "omega = 1.2 is outside [0, 1]" in capsys.readouterr().err


def test_plan_prints_a_result_object(capsys):
    assert main(["plan", "0.1", "0.5", "--law", "poly7", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["status"] in {"converged", "stopped-at-cap"}
    assert 0.1 <= out["duration_s"] <= 3.0
    assert out["iterations"] <= 10


def test_experiment_writes_a_table2_json_that_decodes_to_the_record(tmp_path, capsys):
    out = tmp_path / "run"
    assert main(["experiment", "--out", str(out), "--waypoints", "7", "--seed", "3"]) == 0
    data = json.loads((out / "table2.json").read_text())
    table = Table2.decode(data)
    assert table.encode() == data  # the file holds the record and nothing else
    assert table.seed == 3 and len(table.waypoints_m) == 7 and table.source is None
    assert table.params == default_params()
    assert [(row.case.value, row.law) for row in table.rows] == list(PAPER_TABLE2)
    for row in table.rows:
        assert row.planned.moves == 6 and row.measured is None and row.energy_error_pct is None
        assert row.omega == (DEFAULT_OMEGA if row.case is Case.MIN_TIME_ENERGY else None)
        assert row.limits is not None and row.time_limit_ratio > 1.0
    assert "| min-time | poly3 | ipopt | 6 |" in (out / "table2.md").read_text()
    assert not (out / "limits.json").exists()  # the comparison with the limit is in the rows now
    umask = os.umask(0)
    os.umask(umask)
    assert (out / "table2.json").stat().st_mode & 0o777 == 0o666 & ~umask  # not mkstemp's private 0600


def test_one_waypoint_is_refused(tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["experiment", "--out", str(tmp_path / "x"), "--waypoints", "1"])
    assert exc.value.code == 2
    assert "at least 2 are needed" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()


def test_same_seed_same_waypoints(tmp_path):
    for name in ("a", "b"):
        assert main(["experiment", "--out", str(tmp_path / name), "--waypoints", "3"]) == 0
    a = json.loads((tmp_path / "a" / "table2.json").read_text())
    b = json.loads((tmp_path / "b" / "table2.json").read_text())
    assert a["waypoints_m"] == b["waypoints_m"]


@pytest.mark.slow
def test_the_old_offline_flag_runs_the_same_experiment_with_a_note(tmp_path, capsys):
    assert main(["experiment", "--out", str(tmp_path / "a"), "--waypoints", "3", "--solver", "exact"]) == 0
    assert capsys.readouterr().err == ""
    args = ["experiment", "--offline", "--out", str(tmp_path / "b"), "--waypoints", "3", "--solver", "exact"]
    assert main(args) == 0
    assert "--offline is no longer needed" in capsys.readouterr().err
    a, b = (read_table2(tmp_path / name / "table2.json") for name in "ab")
    assert [r.planned.durations_s for r in a.rows] == [r.planned.durations_s for r in b.rows]


def test_experiment_into_a_file_path_fails_cleanly_and_writes_nothing(tmp_path, capsys, monkeypatch):
    def not_before_the_output_is_checked(*_args, **_kwargs):
        raise AssertionError("the experiment ran before its --out was checked")

    monkeypatch.setattr("axisflow.experiment.offline.run_offline", not_before_the_output_is_checked)
    target = tmp_path / "file"
    target.write_text("keep me")
    assert main(["experiment", "--out", str(target), "--waypoints", "3"]) == 2
    assert "exists and is not a directory" in capsys.readouterr().err
    assert target.read_text() == "keep me"
    assert main(["experiment", "--out", str(target / "below"), "--waypoints", "3"]) == 2
    assert f"{target} is not a directory" in capsys.readouterr().err


def _commands(parser=None, prefix=()):
    """(command words, parser) of every command and sub-command (e.g. ("bench", "planner"))."""
    import argparse

    from axisflow.cli import build_parser
    from axisflow.cli.bench_cmd import BENCHMARKS, add_benchmark

    parser = parser or build_parser()
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                if prefix == ("bench",):  # a benchmark's options load when it is named on the command line
                    add_benchmark(sub, BENCHMARKS[name])
                yield (*prefix, name), sub
                yield from _commands(sub, (*prefix, name))


def test_every_command_has_help_with_a_description_and_every_option_explained(capsys):
    commands = dict(_commands())
    assert {"params", "plan", "experiment", "pareto", "bench", "bridge", "record", "replay", "recover"} <= {
        words[0] for words in commands
    }
    assert ("bench", "planner") in commands and ("bench", "pipeline") in commands
    for words, parser in commands.items():
        with pytest.raises(SystemExit) as exc:
            main([*words, "--help"])
        assert exc.value.code == 0, words
        out = capsys.readouterr().out
        assert out.startswith(f"usage: axisflow {' '.join(words)}"), words
        # a bare % in a help text is a format directive: "E% and" printed argparse's internals
        assert "option_strings" not in out, words
        assert parser.description, f"axisflow {' '.join(words)} has no description"
        unexplained = [
            a.option_strings or a.dest
            for a in parser._actions
            if not a.help and not isinstance(a, __import__("argparse")._SubParsersAction)
        ]
        assert not unexplained, f"axisflow {' '.join(words)}: options without help: {unexplained}"


@pytest.mark.slow
def test_offline_table2_lands_within_ten_percent_of_the_paper(tmp_path):
    """The default parameters were calibrated so that all twelve T and E_th figures land within ±10 %.
    (The planned columns only: the comparison with the physical limit, ~85 % of a full run's time, is
    checked by test_experiment_writes_a_table2_json_that_decodes_to_the_record.)"""
    assert main(["experiment", "--out", str(tmp_path), "--no-limits"]) == 0
    for row in read_table2(tmp_path / "table2.json").rows:
        assert row.paper is not None
        assert row.planned.total_time_s == pytest.approx(row.paper.total_time_s, rel=0.10), row.law
        assert row.planned.energy_model_j == pytest.approx(row.paper.energy_model_j, rel=0.10), row.law


def test_params_help_shows_every_physical_range(capsys):
    from axisflow.model.parameter_ranges import ranges_table

    with pytest.raises(SystemExit):
        main(["params", "--help"])
    shown = capsys.readouterr().out
    for key, text, why in ranges_table():
        assert f"{key:<8} {text:<22} {why}" in shown, key


def test_an_experiment_row_with_zero_moves_compares_the_rest_with_the_limit():
    import numpy as np
    from axisflow.planner import make_backend

    from axisflow.experiment.offline import plan_row

    params = default_params()
    points = np.array([0.1, 0.1, 0.1 + 1e-7, 0.5])  # two zero moves, then 0.4 m
    row = plan_row(points, Case.MIN_TIME_ENERGY, "poly5", make_backend("exact"), params, DEFAULT_OMEGA)
    assert row.planned.durations_s[:2] == (0.0, 0.0)
    assert row.planned.total_time_s == row.planned.durations_s[2]
    assert row.limits is not None and row.limits.time_limits_s[:2] == (0.0, 0.0)
    assert row.time_limit_ratio is not None and row.time_limit_ratio > 1.0


def test_warnings_from_many_threads_each_arrive_as_one_line(capfd):
    """Readers warn from several threads at once; no two warnings may run together into one line."""
    import threading
    import warnings

    from axisflow.model.errors import AxisflowWarning

    from axisflow.cli import _warning_printer

    show = _warning_printer("view", warnings.showwarning)
    start = threading.Barrier(8)

    def warn(thread: int) -> None:
        start.wait()
        for k in range(300):
            show(AxisflowWarning(f"thread {thread} warning {k} {'x' * 200}"), AxisflowWarning, "f.py", 1)

    threads = [threading.Thread(target=warn, args=(n,)) for n in range(8)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    lines = capfd.readouterr().err.splitlines()
    tail = " " + "x" * 200
    expected = {f"axisflow view: warning: thread {n} warning {k}{tail}" for n in range(8) for k in range(300)}
    assert len(lines) == len(expected) and set(lines) == expected
