"""The paper's Table 2 as one typed record, and its JSON.

One row per run of a case × law through the same way points. Its columns come in three groups:

* :class:`PlannedColumns` — what the planner decided for each move between consecutive way points
  (duration, model energy E_th, objective, solve time, status, worst limit violation); always there;
* :class:`MeasuredColumns` — what the axis did, from a recording (measured energy E_exp of each move,
  completed moves, samples lost, idle ticks between moves); only when the moves ran
  (``axisflow table2``, the demo), ``None`` for the offline experiment;
* :class:`LimitColumns` — each move against the physical limit (T_limit: the time-optimal duration;
  E_limit: the least energy at the planned duration); only when the offline experiment computed it.

The totals (T, E_th, E_exp, E%, t_opt, the ratios to the limits) are properties, one formula each;
the JSON file carries them beside the per-move columns for its readers, and :meth:`Table2.decode`
recomputes them rather than trusting the file (:func:`read_table2`). Its Markdown, and the two files
written together, are :mod:`.table2_markdown`'s.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

import numpy as np

from ..acquisition import PlanRecord
from ..model import AxisflowError, AxisParams, EnergyAccounting
from ..model.energy import energy_error_pct
from ..model.files import read_json
from ..model.params import FILE_KEYS, params_from_mapping
from ..planner import Case, PlanResult
from .paper import PAPER_TABLE2, PAPER_WAYPOINTS, PaperRow


class Table2Error(AxisflowError, ValueError):
    """A Table 2 record is inconsistent, or a ``table2.json`` cannot be decoded (the key named)."""


def _floats(values: Sequence[float]) -> tuple[float, ...]:
    return tuple(float(v) for v in values)


def _check_length(group: str, name: str, values: Sequence[object], moves: int) -> None:
    if len(values) != moves:
        raise Table2Error(f"{group}.{name} has {len(values)} entries for {moves} moves")


# ---- the three groups of columns --------------------------------------------------------------------
@dataclass(frozen=True)
class PlannedColumns:
    """What the planner decided, per move between consecutive way points, in order."""

    durations_s: tuple[float, ...]
    energies_j: tuple[float, ...]
    """model energy E_th of each move [J] (eq. 3, under the table's energy accounting)"""
    objectives: tuple[float, ...]
    """the objective each solve minimised (eq. 2 or 3)"""
    solve_times_s: tuple[float, ...]
    statuses: tuple[str, ...]
    """the solver's status of each move (``converged``, ``stopped-at-cap``, …)"""
    violations: tuple[float, ...]
    """worst relative excess over the velocity or torque limit at the 1 kHz execution samples"""

    def __post_init__(self) -> None:
        if not self.durations_s:
            raise Table2Error("a Table 2 row needs at least one planned move")
        for f in fields(self):
            _check_length("planned", f.name, getattr(self, f.name), len(self.durations_s))

    @classmethod
    def of_results(cls, results: Sequence[PlanResult]) -> PlannedColumns:
        """From the planner's result objects (the offline experiment)."""
        return cls(
            _floats([r.duration_s for r in results]),
            _floats([r.energy_j for r in results]),
            _floats([r.objective for r in results]),
            _floats([r.solve_time_s for r in results]),
            tuple(r.status.value for r in results),
            _floats([r.max_violation for r in results]),
        )

    @classmethod
    def of_plans(cls, plans: Sequence[PlanRecord]) -> PlannedColumns:
        """From the plan records a planner node published (a recording)."""
        return cls(
            _floats([p.duration_s for p in plans]),
            _floats([p.energy_j for p in plans]),
            _floats([p.objective for p in plans]),
            _floats([p.solve_time_s for p in plans]),
            tuple(p.status for p in plans),
            _floats([p.max_violation for p in plans]),
        )

    @property
    def moves(self) -> int:
        return len(self.durations_s)

    @property
    def total_time_s(self) -> float:
        """T: Σ planned durations [s]"""
        return math.fsum(self.durations_s)

    @property
    def energy_model_j(self) -> float:
        """E_th: Σ model energies [J]"""
        return math.fsum(self.energies_j)

    @property
    def objective_total(self) -> float:
        """Σ of each move's objective, the quantity each solve minimised"""
        return math.fsum(self.objectives)

    @property
    def t_opt_ms_mean(self) -> float:
        """mean solve time [ms]"""
        return float(np.mean(self.solve_times_s)) * 1e3

    @property
    def t_opt_ms_std(self) -> float:
        """sample standard deviation of the solve times [ms] (0 for a single move)"""
        return float(np.std(self.solve_times_s, ddof=1)) * 1e3 if self.moves > 1 else 0.0

    @property
    def max_violation(self) -> float:
        return max(self.violations)

    @property
    def status_counts(self) -> dict[str, int]:
        return dict(sorted(Counter(self.statuses).items()))

    DERIVED = (
        "moves",
        "total_time_s",
        "energy_model_j",
        "objective_total",
        "t_opt_ms_mean",
        "t_opt_ms_std",
        "max_violation",
        "status_counts",
    )


@dataclass(frozen=True)
class MeasuredColumns:
    """What the axis did with the planned moves, from a recording (see :mod:`axisflow.experiment.table2`)."""

    energies_j: tuple[float | None, ...]
    """E_exp of each move [J]: ∫ g(τ_m·ω_m) dt over its ticks; None unless the move completed and
    every one of its state samples was recorded"""
    completed: tuple[bool, ...]
    """whether the bridge reported each move completed"""
    state_samples_missing: tuple[int, ...]
    """state samples missing from the recording within each move's ticks"""
    idle_ticks: tuple[int, ...]
    """setpoint samples between consecutive moves (0: the next starts on the tick the previous ends)"""
    setpoint_samples_missing: int = 0
    """setpoint samples missing from the recording between the run's first and last tick"""

    @property
    def moves_completed(self) -> int:
        return sum(self.completed)

    @property
    def moves_measured(self) -> int:
        """moves with a measured energy (E_exp and E% are over these)"""
        return sum(e is not None for e in self.energies_j)

    @property
    def energy_measured_j(self) -> float:
        """E_exp: Σ measured energies [J] (moves without one left out)"""
        return math.fsum(e for e in self.energies_j if e is not None)

    @property
    def state_samples_missing_total(self) -> int:
        return sum(self.state_samples_missing)

    @property
    def idle_ticks_total(self) -> int:
        return sum(self.idle_ticks)

    DERIVED = (
        "moves_completed",
        "moves_measured",
        "energy_measured_j",
        "energy_error_pct",
        "state_samples_missing_total",
        "idle_ticks_total",
    )


@dataclass(frozen=True)
class LimitColumns:
    """Each move against the physical limit of the axis (planner/reference_laws.py)."""

    time_limits_s: tuple[float, ...]
    """T_limit: the time-optimal (bang–cruise–bang) duration of each move [s]"""
    energy_limits_j: tuple[float, ...]
    """E_limit: the least energy of a limit-respecting profile at each move's planned duration [J]"""

    @property
    def total_time_limit_s(self) -> float:
        return math.fsum(self.time_limits_s)

    @property
    def energy_limit_j(self) -> float:
        return math.fsum(self.energy_limits_j)

    DERIVED = ("total_time_limit_s", "energy_limit_j", "time_limit_ratio", "energy_limit_ratio")


# ---- a row ------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Table2Row:
    """One case × law run: planned columns, and measured or limit columns when there are any."""

    case: Case
    law: str
    solver: str
    omega: float | None
    """the time weight ω of the min-time-energy case; None for min-time"""
    planned: PlannedColumns
    label: str = ""
    """the run's label in a recording (a planner node's ``--label``); empty offline"""
    measured: MeasuredColumns | None = None
    limits: LimitColumns | None = None

    def __post_init__(self) -> None:
        try:
            object.__setattr__(self, "case", Case(self.case))
        except ValueError:
            raise Table2Error(
                f"case {self.case!r} is not one of {', '.join(c.value for c in Case)}"
            ) from None
        moves = self.planned.moves
        if self.measured is not None:
            for name in ("energies_j", "completed", "state_samples_missing"):
                _check_length("measured", name, getattr(self.measured, name), moves)
        if self.limits is not None:
            for name in ("time_limits_s", "energy_limits_j"):
                _check_length("limits", name, getattr(self.limits, name), moves)

    @property
    def energy_error_pct(self) -> float | None:
        """E% = (E_th − E_exp)/E_th·100 over the measured moves (the paper's definition); None when
        nothing was measured"""
        if self.measured is None:
            return None
        pairs = zip(self.planned.energies_j, self.measured.energies_j, strict=True)
        e_th = math.fsum(planned for planned, measured in pairs if measured is not None)
        return energy_error_pct(e_th, self.measured.energy_measured_j)

    @property
    def time_limit_ratio(self) -> float | None:
        """T/T_limit over the row: total planned time over total time-optimal time"""
        if self.limits is None or not self.limits.total_time_limit_s:
            return None
        return self.planned.total_time_s / self.limits.total_time_limit_s

    @property
    def energy_limit_ratio(self) -> float | None:
        """E/E_limit over the row: total model energy over total least energy at the same durations"""
        if self.limits is None or not self.limits.energy_limit_j:
            return None
        return self.planned.energy_model_j / self.limits.energy_limit_j

    @property
    def paper(self) -> PaperRow | None:
        """The paper's row of the same case and law, for a row of the paper's size (99 moves)."""
        if self.planned.moves != PAPER_WAYPOINTS - 1:
            return None
        return PAPER_TABLE2.get((self.case.value, self.law))

    def encode(self) -> dict[str, Any]:
        """The row as JSON-ready values: the fields, and each group's totals beside its columns."""
        planned = _group(self.planned, {})
        measured = None
        if self.measured is not None:
            measured = _group(self.measured, {"energy_error_pct": self.energy_error_pct})
        limits = None
        if self.limits is not None:
            limits = _group(
                self.limits,
                {"time_limit_ratio": self.time_limit_ratio, "energy_limit_ratio": self.energy_limit_ratio},
            )
        return {
            "case": self.case.value,
            "law": self.law,
            "solver": self.solver,
            "omega": self.omega,
            "label": self.label,
            "planned": planned,
            "measured": measured,
            "limits": limits,
        }

    @classmethod
    def decode(cls, data: dict[str, Any], where: str = "row") -> Table2Row:
        keys = ("case", "law", "solver", "omega", "label", "planned", "measured", "limits")
        data = _checked(data, keys, (), where)
        planned = _ungroup(PlannedColumns, data["planned"], f"{where}.planned")
        measured = (
            None
            if data["measured"] is None
            else _ungroup(MeasuredColumns, data["measured"], f"{where}.measured")
        )
        limits = None if data["limits"] is None else _ungroup(LimitColumns, data["limits"], f"{where}.limits")
        omega = None if data["omega"] is None else float(data["omega"])
        return cls(
            data["case"],
            str(data["law"]),
            str(data["solver"]),
            omega,
            planned,
            str(data["label"]),
            measured,
            limits,
        )


def _group(columns: PlannedColumns | MeasuredColumns | LimitColumns, extra: dict[str, Any]) -> dict[str, Any]:
    """A group of columns as JSON-ready values (tuples as lists), its totals after them."""
    out: dict[str, Any] = {}
    for f in fields(columns):
        value = getattr(columns, f.name)
        out[f.name] = list(value) if isinstance(value, tuple) else value
    for name in columns.DERIVED:
        out[name] = extra[name] if name in extra else getattr(columns, name)
    return out


def _checked(data: object, required: Sequence[str], ignored: Sequence[str], where: str) -> dict[str, Any]:
    """``data`` if it is an object with every ``required`` key and no key beyond ``ignored``."""
    if not isinstance(data, dict):
        raise Table2Error(f"{where} is a {type(data).__name__}, not an object")
    problems = []
    missing = [k for k in required if k not in data]
    if missing:
        problems.append(f"missing key(s) {', '.join(missing)}")
    unknown = sorted(set(data) - set(required) - set(ignored))
    if unknown:
        problems.append(f"unknown key(s) {', '.join(unknown)}")
    if problems:
        raise Table2Error(f"{where}: {'; '.join(problems)}")
    return data


def _ungroup(kind: Any, data: object, where: str) -> Any:
    """A group of columns of type ``kind`` from its JSON object (its totals ignored: recomputed)."""
    names = [f.name for f in fields(kind)]
    given = _checked(data, names, kind.DERIVED, where)
    values = {name: tuple(given[name]) if isinstance(given[name], list) else given[name] for name in names}
    try:
        return kind(**values)
    except (TypeError, ValueError) as exc:
        raise Table2Error(f"{where}: {exc}") from None


# ---- the table --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Table2:
    """Table 2 of one set of runs through the same way points."""

    title: str
    accounting: EnergyAccounting
    """the energy accounting of E_th (and of E_exp: the same)"""
    waypoints_m: tuple[float, ...]
    rows: tuple[Table2Row, ...]
    seed: int | None = None
    """the seed of the random way points (offline; None when read from a recording)"""
    source: str | None = None
    """the recording the measured columns come from"""
    params: AxisParams | None = None
    """the axis parameters the offline experiment planned with"""

    def __post_init__(self) -> None:
        object.__setattr__(self, "accounting", EnergyAccounting(self.accounting))

    def encode(self) -> dict[str, Any]:
        return {
            "title": self.title,
            "energy_accounting": self.accounting.value,
            "seed": self.seed,
            "source": self.source,
            "waypoints_m": [float(w) for w in self.waypoints_m],
            "params": None if self.params is None else self.params.to_dict(),
            "rows": [row.encode() for row in self.rows],
        }

    @classmethod
    def decode(cls, data: dict[str, Any]) -> Table2:
        keys = ("title", "energy_accounting", "seed", "source", "waypoints_m", "params", "rows")
        data = _checked(data, keys, (), "table2.json")
        params = None
        if data["params"] is not None:
            given = _checked(data["params"], (), ("M_eq", *FILE_KEYS), "table2.json params")
            params = params_from_mapping(
                {k: v for k, v in given.items() if k != "M_eq"}, "table2.json params"
            )
        try:
            accounting = EnergyAccounting(data["energy_accounting"])
        except ValueError:
            raise Table2Error(
                f"table2.json energy_accounting = {data['energy_accounting']!r} is not one of "
                f"{[e.value for e in EnergyAccounting]}"
            ) from None
        rows = tuple(Table2Row.decode(row, f"rows[{i}]") for i, row in enumerate(data["rows"]))
        return cls(
            str(data["title"]),
            accounting,
            _floats(data["waypoints_m"]),
            rows,
            data["seed"],
            data["source"],
            params,
        )


def read_table2(path: str | Path) -> Table2:
    """A ``table2.json`` written by :func:`~.table2_markdown.write_table2`."""
    return Table2.decode(read_json(path, Table2Error))
