"""The machine reference: measured, and added to every benchmark's output."""

import argparse
import json

from axisflow.benchmarks import machine
from axisflow.benchmarks.machine import MachineReference, run_with_reference


def _bench(args: argparse.Namespace) -> int:
    print(json.dumps({"figure": 1.5}) if args.json else "a table")
    return 0


def test_a_benchmark_run_measures_the_reference_into_its_json(capsys):
    assert run_with_reference(_bench, argparse.Namespace(json=True)) == 0
    out = json.loads(capsys.readouterr().out)
    reference = MachineReference(out["machine_reference"]["python_s"], out["machine_reference"]["numpy_s"])
    assert out["figure"] == 1.5 and 0.0 < reference.python_s < 60.0 and 0.0 < reference.numpy_s < 60.0
    assert out["machine_reference"]["seconds"] == reference.seconds == reference.python_s + reference.numpy_s
    assert reference.multiple(3 * reference.seconds) == 3.0


def test_a_benchmark_table_is_followed_by_the_reference(capsys, monkeypatch):
    monkeypatch.setattr(machine, "machine_reference", lambda: MachineReference(0.1, 0.025))
    assert run_with_reference(_bench, argparse.Namespace(json=False)) == 0
    table, last = capsys.readouterr().out.splitlines()
    assert table == "a table"
    assert last.startswith("machine reference 125 ms (Python 100 ms + numpy 25 ms, fastest of 3 rounds)")
    assert "divided by 0.125 s" in last
