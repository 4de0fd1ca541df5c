"""identify on a cell's recording: the axis is chosen by name, each fit is that axis's friction."""

from __future__ import annotations

import json

import pytest
from axisflow.acquisition.logs.synthetic_log import SyntheticLogSpec
from axisflow.model import default_params

from axisflow.cli import main

from ..acquisition.logs.cell_log import write_cell_log

NOMINAL = default_params()
A1_PLANT = NOMINAL.replace(a1=NOMINAL.a1 * 1.3, a3=NOMINAL.a3 * 0.8)
"""axis a1 of the cell has 30 % more Coulomb and 20 % less viscous friction than a0 (the nominal axis)"""
FAST = ("--cogging", "none", "--stroke-terms", "0", "--json")


@pytest.fixture(scope="module")
def cell(tmp_path_factory):
    path = tmp_path_factory.mktemp("cell") / "cell.mcap"
    specs = [
        SyntheticLogSpec(duration_s=10.0, axis="a0", seed=0),
        SyntheticLogSpec(duration_s=10.0, axis="a1", seed=1, true_params=A1_PLANT),
    ]
    return write_cell_log(path, specs)


@pytest.mark.parametrize(("axis", "plant"), [("a0", NOMINAL), ("a1", A1_PLANT)])
def test_each_axis_of_a_cell_recording_is_fitted_to_its_own_friction(cell, tmp_path, capsys, axis, plant):
    assert main(["identify", str(cell), "--axis", axis, "--out", str(tmp_path / axis), *FAST]) == 0
    fitted = {name: p["value"] for name, p in json.loads(capsys.readouterr().out)["parameters"].items()}
    assert fitted["a1"] == pytest.approx(plant.a1, rel=0.02)
    assert fitted["a3"] == pytest.approx(plant.a3, rel=0.02)


def test_a_cell_recording_without_axis_is_refused_with_its_axes(cell, tmp_path, capsys):
    assert main(["identify", str(cell), "--out", str(tmp_path / "refit")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.endswith("cell.mcap holds 2 axes (a0, a1): choose one with --axis"), err
    assert not (tmp_path / "refit").exists()


def test_topic_still_names_a_topic_directly(cell, tmp_path, capsys):
    args = ["identify", str(cell), "--topic", "/axisflow/a1/state", "--out", str(tmp_path / "t"), *FAST]
    assert main(args) == 0
    fitted = json.loads(capsys.readouterr().out)["parameters"]
    assert fitted["a1"]["value"] == pytest.approx(A1_PLANT.a1, rel=0.02)
