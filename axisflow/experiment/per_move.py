"""Each move's planned and measured energy: the rows of ``axisflow table2 --per-move``.

Table 2 sums a run's moves; drift shows move by move. :class:`MoveEnergy` is one move of a recording:
its run (label, case, law, solver), way point index, move id, drive time of its first and last tick,
planned duration, the parameter version its plan used (``PlanRecord.params_version``), its model energy
E_th, the measured E_exp (None when the move did not complete or lost samples in the recording) and
E% = (E_th − E_exp)/E_th·100, the paper's definition per move.

:func:`write_move_energies` writes them as ``STEM.csv`` (one line per move, for a spreadsheet) and
``STEM.json`` (a list of objects), together and atomically; :func:`read_move_energies` reads the JSON
back (the round trip is tested).
"""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Any

from ..model import AxisflowError
from ..model.energy import energy_error_pct
from ..model.files import ensure_dir, read_json, write_atomic_files


class MoveEnergyError(AxisflowError, ValueError):
    """A per-move energy file cannot be decoded (the field named)."""


@dataclass(frozen=True)
class MoveEnergy:
    """One move's planned and measured energy (see the module docstring)."""

    label: str
    case: str
    law: str
    solver: str
    waypoint_index: int
    move_id: int
    start_ns: int
    """drive time of the move's first tick [ns since the Unix epoch]"""
    end_ns: int
    """drive time of its last tick [ns]"""
    duration_s: float
    params_version: int
    energy_planned_j: float
    energy_measured_j: float | None

    @property
    def energy_error_pct(self) -> float | None:
        """E% = (E_th − E_exp)/E_th·100; None without a measured energy or with no planned energy."""
        if self.energy_measured_j is None:
            return None
        return energy_error_pct(self.energy_planned_j, self.energy_measured_j)

    def encode(self) -> dict[str, Any]:
        return asdict(self) | {"energy_error_pct": self.energy_error_pct}

    @classmethod
    def decode(cls, data: object, where: str = "move") -> MoveEnergy:
        if not isinstance(data, dict):
            raise MoveEnergyError(f"{where}: not an object")
        values = {}
        for f in fields(cls):
            if f.name not in data:
                raise MoveEnergyError(f"{where}: no field {f.name!r}")
            values[f.name] = data[f.name]
        for name in ("waypoint_index", "move_id", "start_ns", "end_ns", "params_version"):
            if isinstance(values[name], bool) or not isinstance(values[name], int):
                raise MoveEnergyError(f"{where}: {name} = {values[name]!r} is not a whole number")
        for name in ("duration_s", "energy_planned_j"):
            if not isinstance(values[name], int | float) or not math.isfinite(values[name]):
                raise MoveEnergyError(f"{where}: {name} = {values[name]!r} is not a finite number")
        measured = values["energy_measured_j"]
        if measured is not None and (not isinstance(measured, int | float) or not math.isfinite(measured)):
            raise MoveEnergyError(f"{where}: energy_measured_j = {measured!r} is neither a number nor null")
        return cls(**values)


CSV_COLUMNS = (*(f.name for f in fields(MoveEnergy)), "energy_error_pct")


def move_energies_csv(moves: Sequence[MoveEnergy]) -> str:
    """One line per move under a header (:data:`CSV_COLUMNS`); an empty cell where there is no value."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(CSV_COLUMNS)
    for m in moves:
        row = m.encode()
        writer.writerow(["" if row[c] is None else row[c] for c in CSV_COLUMNS])
    return out.getvalue()


def write_move_energies(moves: Sequence[MoveEnergy], folder: str | Path, stem: str = "moves") -> list[Path]:
    """``STEM.csv`` and ``STEM.json`` in ``folder`` (created if needed), written together atomically."""
    text = json.dumps([m.encode() for m in moves], indent=1, allow_nan=False) + "\n"
    return write_atomic_files(
        ensure_dir(folder), {f"{stem}.csv": move_energies_csv(moves), f"{stem}.json": text}
    )


def read_move_energies(path: str | Path) -> list[MoveEnergy]:
    """The moves of a ``moves.json`` written by :func:`write_move_energies`."""
    data = read_json(path, MoveEnergyError)
    if not isinstance(data, list):
        raise MoveEnergyError(f"{path}: not a list of moves")
    return [MoveEnergy.decode(item, f"{path}, move {i}") for i, item in enumerate(data)]
