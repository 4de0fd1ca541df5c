"""The per-move energy record: its E%, its files, their round trip and refusals."""

import json

import pytest

from axisflow.experiment.per_move import (
    CSV_COLUMNS,
    MoveEnergy,
    MoveEnergyError,
    read_move_energies,
    write_move_energies,
)

MOVE = MoveEnergy(
    "adapt", "min-time", "poly5", "exact", 7, 42, 10**18, 10**18 + 5 * 10**8, 0.5, 3, 100.0, 98.0
)


def test_e_percent_is_the_papers_per_move():
    assert MOVE.energy_error_pct == pytest.approx(2.0)
    unmeasured = MoveEnergy(**{**MOVE.__dict__, "energy_measured_j": None})
    assert unmeasured.energy_error_pct is None


def test_the_files_round_trip(tmp_path):
    unmeasured = MoveEnergy(**{**MOVE.__dict__, "move_id": 43, "energy_measured_j": None})
    paths = write_move_energies([MOVE, unmeasured], tmp_path)
    assert [p.name for p in paths] == ["moves.csv", "moves.json"]
    assert read_move_energies(tmp_path / "moves.json") == [MOVE, unmeasured]
    header, first, second = (tmp_path / "moves.csv").read_text().splitlines()
    assert header.split(",") == list(CSV_COLUMNS)
    assert first.split(",")[-3:] == ["100.0", "98.0", "2.0"] and second.endswith(",100.0,,")


@pytest.mark.parametrize(
    ("change", "match"),
    [
        ({"move_id": 1.5}, "move_id = 1.5 is not a whole number"),
        ({"energy_planned_j": "x"}, "energy_planned_j = 'x' is not a finite number"),
        ({"energy_measured_j": "nan"}, "energy_measured_j = 'nan' is neither a number nor null"),
    ],
)
def test_a_bad_field_is_named(tmp_path, change, match):
    data = [MOVE.encode() | change]
    (tmp_path / "moves.json").write_text(json.dumps(data))
    with pytest.raises(MoveEnergyError, match=match):
        read_move_energies(tmp_path / "moves.json")


def test_a_missing_field_is_named(tmp_path):
    data = MOVE.encode()
    del data["params_version"]
    (tmp_path / "moves.json").write_text(json.dumps([data]))
    with pytest.raises(MoveEnergyError, match="move 0: no field 'params_version'"):
        read_move_energies(tmp_path / "moves.json")
