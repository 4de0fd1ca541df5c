"""The paper's Table 2 from a recording: planned and measured energy of the moves the axis ran.

A recording of a planner node's runs holds, for every move, its plan record (``…/plan``: duration,
model energy E_th, solve time), the bridge's move status (``…/event``: the ticks it ran), the measured
samples (``…/state``: motor speed ω_m and torque τ_m at 1 kHz) and the setpoints (``…/setpoint``).
From these, per run (label, case, law, solver) over its moves between way points (the move to the
first way point is left out):

* T = Σ planned durations; E_th = Σ model energies of the plans;
* E_exp = Σ over the moves of ∫ g(τ_m·ω_m) dt over the move's ticks [start, end] (trapezoid at
  1 kHz), g the energy accounting of the plans (positive: max(P, 0), as E_th counts it);
* E% = (E_th − E_exp)/E_th·100, the paper's definition;
* t_opt: mean ± std of the solve times; idle ticks between consecutive moves, counted from the
  recorded setpoints: samples stamped from the end tick of a move up to the start tick of the next
  (0 when the next starts on the tick the previous ends).

Samples lost by the recording are counted, never integrated over: a move missing any of its state
samples has no E_exp and is left out of the row's E_exp and E% (with its E_th), and a run whose
setpoint samples are incomplete between its first and last tick is flagged (its idle ticks are those
recorded). The table names both below it.
"""

from __future__ import annotations

import json
import math
from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .acquisition import (
    MOVE_STATUS_TYPE,
    PLAN_TYPE,
    AxisKeys,
    JointStateColumns,
    MoveState,
    MoveStatus,
    PlanRecord,
    read_joint_states,
    read_messages,
    topic_for_key,
)
from .model import EXECUTION_PERIOD_S, AxisflowError, EnergyAccounting, trace_energy
from .model.files import ensure_dir, write_atomic
from .paper import PAPER_TABLE2, PAPER_WAYPOINTS


@dataclass
class RecordedMove:
    plan: PlanRecord
    accepted: MoveStatus | None = None
    completed: MoveStatus | None = None
    energy_measured_j: float = math.nan
    """NaN unless completed and every one of its state samples was recorded"""
    samples_missing: int = 0
    """state samples missing from the recording within the move's ticks"""


@dataclass
class RecordedRow:
    """One run of the planner as recorded (see the module docstring)."""

    label: str
    case: str
    law: str
    solver: str
    omega: float
    moves: list[RecordedMove] = field(default_factory=list)
    idle_ticks: list[int] = field(default_factory=list)
    setpoint_samples_missing: int = 0
    """setpoint samples missing from the recording between the run's first and last tick"""

    @property
    def completed(self) -> list[RecordedMove]:
        return [m for m in self.moves if m.completed is not None]

    @property
    def measured(self) -> list[RecordedMove]:
        """the completed moves whose every state sample was recorded: E_exp and E% are over these"""
        return [m for m in self.completed if math.isfinite(m.energy_measured_j)]

    @property
    def state_samples_missing(self) -> int:
        return sum(m.samples_missing for m in self.moves)

    @property
    def total_time_s(self) -> float:
        return math.fsum(m.plan.duration_s for m in self.moves)

    @property
    def energy_model_j(self) -> float:
        return math.fsum(m.plan.energy_j for m in self.moves)

    @property
    def energy_measured_j(self) -> float:
        return math.fsum(m.energy_measured_j for m in self.measured)

    @property
    def energy_error_pct(self) -> float:
        e_th = math.fsum(m.plan.energy_j for m in self.measured)
        return (e_th - self.energy_measured_j) / e_th * 100.0 if e_th else math.nan

    @property
    def solve_times_ms(self) -> np.ndarray:
        return np.array([m.plan.solve_time_s * 1e3 for m in self.moves])

    def to_json(self) -> dict[str, Any]:
        """The offline experiment's row keys, with the measured energy and idle ticks filled in."""
        t = self.solve_times_ms
        return {
            "case": self.case,
            "law": self.law,
            "solver": self.solver,
            "omega": self.omega if self.case == "min-time-energy" else None,
            "durations_s": [m.plan.duration_s for m in self.moves],
            "total_time_s": self.total_time_s,
            "energy_model_j": self.energy_model_j,
            "energy_measured_j": self.energy_measured_j,
            "energy_error_pct": _finite_or_none(self.energy_error_pct),
            "t_opt_ms_mean": float(t.mean()) if t.size else math.nan,
            "t_opt_ms_std": float(t.std(ddof=1)) if t.size > 1 else 0.0,
            "max_violation": max((m.plan.max_violation for m in self.moves), default=0.0),
            "idle_ticks": self.idle_ticks,
            "label": self.label,
            "moves": len(self.moves),
            "moves_completed": len(self.completed),
            "moves_measured": len(self.measured),
            "state_samples_missing": self.state_samples_missing,
            "setpoint_samples_missing": self.setpoint_samples_missing,
            "energy_measured_per_move_j": [_finite_or_none(m.energy_measured_j) for m in self.moves],
        }


def _finite_or_none(value: float) -> float | None:
    """JSON has no NaN: an unknown figure is null"""
    return value if math.isfinite(value) else None


@dataclass
class RecordedTable:
    source: Path
    accounting: EnergyAccounting
    rows: list[RecordedRow]

    def to_json(self) -> dict[str, Any]:
        first = self.rows[0].moves if self.rows else []
        waypoints = [first[0].plan.start_position_m, *(m.plan.end_position_m for m in first)] if first else []
        return {
            "source": str(self.source),
            "energy_accounting": self.accounting.value,
            "waypoints_m": waypoints,
            "rows": [row.to_json() for row in self.rows],
        }


def table_from_recording(
    path: str | Path, keys: AxisKeys | None = None, label: str | None = None
) -> RecordedTable:
    """Table 2 of the runs recorded in ``path`` (those with ``label``, or all)."""
    keys = keys or AxisKeys()
    plans = [PlanRecord.decode(m.data) for m in read_messages(path, topic_for_key(keys.plan), PLAN_TYPE)]
    plans = [p for p in plans if p.waypoint_index > 0 and (label is None or p.run == label)]
    if not plans:
        raise AxisflowError(
            f"{path} holds no plan records on {topic_for_key(keys.plan)}"
            + (f" labelled {label!r}" if label else "")
            + ": record while `axisflow planner` runs (it publishes one per move)"
        )
    accountings = {p.energy_accounting for p in plans}
    if len(accountings) != 1:
        raise AxisflowError(f"{path}: the plans mix energy accountings {sorted(accountings)}")
    accounting = EnergyAccounting(accountings.pop())
    statuses: dict[tuple[str, int], dict[MoveState, MoveStatus]] = defaultdict(dict)
    for m in read_messages(path, topic_for_key(keys.event), MOVE_STATUS_TYPE):
        st = MoveStatus.decode(m.data)
        statuses[st.sender, st.move_id].setdefault(st.state, st)
    rows = _rows(plans, statuses)
    state = read_joint_states(path, topic_for_key(keys.state))
    signals = _Signals.of(state, read_joint_states(path, topic_for_key(keys.setpoint)))
    for row in rows:
        _measure(row, signals, accounting)
        row.idle_ticks = _idle_ticks(row, signals)
        row.setpoint_samples_missing = _setpoints_missing(row, signals)
    return RecordedTable(Path(path), accounting, rows)


@dataclass(frozen=True)
class _Signals:
    """The recorded columns every row is measured from, sorted by stamp once."""

    stamp_ns: np.ndarray
    """motor samples' stamps [ns], ascending"""
    speed: np.ndarray
    """motor speed ω_m [rad/s], in the order of ``stamp_ns``"""
    torque: np.ndarray
    """motor torque τ_m [N·m], in the order of ``stamp_ns``"""
    setpoint_ns: np.ndarray
    """setpoint samples' stamps [ns], ascending, repeats kept (each is a sample)"""
    setpoint_ticks_ns: np.ndarray
    """the distinct setpoint stamps [ns], ascending (each is a tick)"""

    @classmethod
    def of(cls, state: JointStateColumns, setpoint: JointStateColumns) -> _Signals:
        motor = state.joint("motor")
        order = np.argsort(motor.stamp_ns, kind="stable")
        stamps = np.sort(setpoint.stamp_ns)
        return cls(
            motor.stamp_ns[order], motor.velocity[order], motor.effort[order], stamps, np.unique(stamps)
        )


def _rows(
    plans: list[PlanRecord], statuses: dict[tuple[str, int], dict[MoveState, MoveStatus]]
) -> list[RecordedRow]:
    """Group the plans into runs (label, case, law, solver, sender), in recording order."""
    rows: dict[tuple[str, str, str, str, str], RecordedRow] = {}
    for plan in sorted(plans, key=lambda p: p.stamp_ns):
        key = (plan.run, plan.case, plan.law, plan.solver, plan.sender)
        row = rows.get(key)
        if row is None:
            row = rows[key] = RecordedRow(plan.run, plan.case, plan.law, plan.solver, plan.omega)
        life = statuses.get((plan.sender, plan.move_id), {})
        row.moves.append(RecordedMove(plan, life.get(MoveState.ACCEPTED), life.get(MoveState.COMPLETED)))
    return list(rows.values())


def _measure(row: RecordedRow, signals: _Signals, accounting: EnergyAccounting) -> None:
    """E_exp of each completed move: ∫ g(τ_m·ω_m) dt over its ticks [start, end] (both ends included)."""
    stamps, speed, torque = signals.stamp_ns, signals.speed, signals.torque
    for move in row.completed:
        acc = move.accepted
        if acc is None:
            continue
        lo = np.searchsorted(stamps, acc.stamp_of(acc.start_tick), "left")
        hi = np.searchsorted(stamps, acc.stamp_of(acc.end_tick), "right")
        move.samples_missing = (acc.end_tick - acc.start_tick + 1) - int(hi - lo)
        if move.samples_missing == 0:
            move.energy_measured_j = trace_energy(speed[lo:hi], torque[lo:hi], EXECUTION_PERIOD_S, accounting)


def _idle_ticks(row: RecordedRow, signals: _Signals) -> list[int]:
    """Setpoint samples stamped in [end of move k, start of move k + 1) for consecutive moves."""
    stamps = signals.setpoint_ns
    idle = []
    for a, b in zip(row.moves, row.moves[1:], strict=False):
        if a.accepted is None or b.accepted is None:
            continue
        end = a.accepted.stamp_of(a.accepted.end_tick)
        start = b.accepted.stamp_of(b.accepted.start_tick)
        idle.append(int(np.searchsorted(stamps, start, "left") - np.searchsorted(stamps, end, "left")))
    return idle


def _setpoints_missing(row: RecordedRow, signals: _Signals) -> int:
    """Setpoint ticks from the run's first start to its last end with no recorded sample."""
    spans = [(m.accepted.start_tick, m.accepted.end_tick, m.accepted) for m in row.moves if m.accepted]
    if not spans:
        return 0
    first = min(spans, key=lambda s: s[0])
    last = max(spans, key=lambda s: s[1])
    lo, hi = first[2].stamp_of(first[0]), last[2].stamp_of(last[1])
    stamps = signals.setpoint_ticks_ns
    found = int(np.searchsorted(stamps, hi, "right") - np.searchsorted(stamps, lo, "left"))
    return (last[1] - first[0] + 1) - found


def write_table(
    table: RecordedTable, folder: Path, stem: str = "table2", title: str = ""
) -> tuple[Path, Path]:
    """``table`` as ``STEM.json`` (the offline experiment's schema, measured columns filled) and
    ``STEM.md`` (:func:`table_markdown` with ``title``) in ``folder``, created if needed, each written
    atomically; returns the two paths."""
    folder = ensure_dir(folder)
    return (
        write_atomic(folder / f"{stem}.json", json.dumps(table.to_json(), indent=1) + "\n"),
        write_atomic(folder / f"{stem}.md", table_markdown(table, title)),
    )


def table_markdown(table: RecordedTable, title: str = "") -> str:
    """The table with the paper's figures beside it."""
    lines = [
        f"# {title or 'Table 2, on the axis'} (energy accounting: {table.accounting.value})",
        "",
        f"Recording: {table.source}",
        "",
        "| case | law | solver | moves | T [s] | E_th [J] | E_exp [J] | E% | t_opt [ms] | idle ticks "
        "| paper T [s] | paper E_th [J] | paper E_exp [J] | paper E% |",
        "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for row in table.rows:
        # the paper's figures beside a row of the same size only (99 moves between 100 way points)
        paper = PAPER_TABLE2.get((row.case, row.law)) if len(row.moves) == PAPER_WAYPOINTS - 1 else None
        t = row.solve_times_ms
        std = t.std(ddof=1) if t.size > 1 else 0.0
        ref = (
            f"{paper.total_time_s:.2f} | {paper.energy_model_j:.0f} | {paper.energy_measured_j:.0f} "
            f"| {paper.energy_error_pct:+.2f}"
            if paper
            else "– | – | – | –"
        )
        lines.append(
            f"| {row.case} | {row.law} | {row.solver} | {len(row.completed)}/{len(row.moves)} "
            f"| {row.total_time_s:.2f} | {row.energy_model_j:.0f} | {row.energy_measured_j:.0f} "
            f"| {row.energy_error_pct:+.2f} | {t.mean():.3f} ± {std:.3f} | {sum(row.idle_ticks)} | {ref} |"
        )
    lines += [
        "",
        "T: Σ planned durations; E_th: Σ model energy of the plans; E_exp: Σ ∫ g(τ_m·ω_m) dt of the measured "
        "motor torque and speed over each move's ticks, g the same accounting; E% = (E_th − E_exp)/E_th; "
        "t_opt: solve time per move, mean ± std; idle ticks: setpoint samples between consecutive moves. "
        f"The paper's figures are shown for runs of {PAPER_WAYPOINTS} way points.",
    ]
    for row in table.rows:
        left_out = len(row.completed) - len(row.measured)
        if left_out or row.setpoint_samples_missing:
            lines += [
                "",
                f"**Samples lost by the recording** in {row.case} {row.law}: "
                f"{row.state_samples_missing} state samples within {left_out} moves (left out of E_exp and "
                "E%, with their E_th), "
                f"{row.setpoint_samples_missing} setpoint samples (idle ticks counted from those recorded).",
            ]
    return "\n".join(lines) + "\n"
