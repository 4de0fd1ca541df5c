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

A state sample belongs to the tick whose drive time is nearest its stamp (a realistic drive stamps its
samples with the jitter of its host's clock, tens of µs either way). Samples missing from a move are
counted. A drive that lost one now and then (the realistic plants lose 0.1 %) leaves isolated holes: a
move whose holes are each at most :data:`MAX_BRIDGED_HOLE_TICKS` ticks long, with its first and last
tick present, is integrated over the samples it has (the trapezoid across each hole, an error of the
order of P''·Δt³ per hole); a longer hole (a recording that lost a stretch) is never integrated over:
such a move has no E_exp and is left out of the row's E_exp and E% (with its E_th). A run whose
setpoint samples are incomplete between its first and last tick is flagged (its idle ticks are those
recorded). The table names both below it.

The result is the one Table 2 record of :mod:`axisflow.experiment.table2_record` (its measured columns
filled), written by its writer; :func:`move_energies` gives the same moves one by one
(:class:`~axisflow.experiment.per_move.MoveEnergy`: E_th, E_exp and E% per move, the parameter version
each plan used), what ``axisflow table2 --per-move`` writes.
"""

from __future__ import annotations

import math
from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..acquisition import (
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
from ..model import (
    EXECUTION_PERIOD_NS,
    EXECUTION_PERIOD_S,
    AxisflowError,
    EnergyAccounting,
    trace_energy,
    trace_energy_at,
)
from ..planner import Case
from .per_move import MoveEnergy
from .table2_record import MeasuredColumns, PlannedColumns, Table2, Table2Row

MAX_BRIDGED_HOLE_TICKS = 2
"""the longest run of missing state samples a move's measured energy is integrated across [ticks]"""


@dataclass
class RecordedMove:
    plan: PlanRecord
    accepted: MoveStatus | None = None
    completed: MoveStatus | None = None
    energy_measured_j: float = math.nan
    """NaN unless completed and its state samples recorded, but for isolated holes (module docstring)"""
    samples_missing: int = 0
    """state samples missing from the recording within the move's ticks"""


@dataclass
class RecordedRun:
    """One run of the planner as it is read from the recording: its moves in order, with their
    statuses and measurements (see the module docstring); :meth:`row` is its Table 2 row."""

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

    def row(self) -> Table2Row:
        """The run's Table 2 row: the plans' columns and what was measured."""
        measured = MeasuredColumns(
            tuple(m.energy_measured_j if math.isfinite(m.energy_measured_j) else None for m in self.moves),
            tuple(m.completed is not None for m in self.moves),
            tuple(m.samples_missing for m in self.moves),
            tuple(self.idle_ticks),
            self.setpoint_samples_missing,
        )
        case = Case(self.case)
        omega = self.omega if case is Case.MIN_TIME_ENERGY else None
        planned = PlannedColumns.of_plans([m.plan for m in self.moves])
        return Table2Row(case, self.law, self.solver, omega, planned, self.label, measured)


def table_from_recording(
    path: str | Path,
    keys: AxisKeys | None = None,
    label: str | None = None,
    title: str = "Table 2, on the axis",
) -> Table2:
    """Table 2 of the runs recorded in ``path`` (those with ``label``, or all), titled ``title``."""
    rows, accounting = recorded_runs(path, keys, label)
    return table_of_runs(rows, accounting, title, str(path))


def table_of_runs(runs: list[RecordedRun], accounting: EnergyAccounting, title: str, source: str) -> Table2:
    """Table 2 of recorded runs (:func:`recorded_runs`)."""
    first = runs[0].moves
    waypoints = (first[0].plan.start_position_m, *(m.plan.end_position_m for m in first))
    return Table2(title, accounting, waypoints, tuple(run.row() for run in runs), source=source)


def move_energies(runs: list[RecordedRun]) -> list[MoveEnergy]:
    """Every move of ``runs`` (:func:`recorded_runs`) with its planned and measured energy, in the order
    the moves started (moves that never started last, in plan order)."""
    out = []
    for run in runs:
        for m in run.moves:
            acc = m.accepted
            start = acc.stamp_of(acc.start_tick) if acc is not None else -1
            end = acc.stamp_of(acc.end_tick) if acc is not None else -1
            measured = m.energy_measured_j if math.isfinite(m.energy_measured_j) else None
            p = m.plan
            out.append(
                MoveEnergy(
                    label=run.label,
                    case=run.case,
                    law=run.law,
                    solver=run.solver,
                    waypoint_index=p.waypoint_index,
                    move_id=p.move_id,
                    start_ns=start,
                    end_ns=end,
                    duration_s=p.duration_s,
                    params_version=p.params_version,
                    energy_planned_j=p.energy_j,
                    energy_measured_j=measured,
                )
            )
    return sorted(out, key=lambda e: (e.start_ns < 0, e.start_ns))


def recorded_runs(
    path: str | Path, keys: AxisKeys | None = None, label: str | None = None
) -> tuple[list[RecordedRun], EnergyAccounting]:
    """The runs recorded in ``path`` (those with ``label``, or all), each move measured (see the module
    docstring), and the plans' energy accounting."""
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
    return rows, accounting


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
) -> list[RecordedRun]:
    """Group the plans into runs (label, case, law, solver, sender), in recording order."""
    rows: dict[tuple[str, str, str, str, str], RecordedRun] = {}
    for plan in sorted(plans, key=lambda p: p.stamp_ns):
        key = (plan.run, plan.case, plan.law, plan.solver, plan.sender)
        row = rows.get(key)
        if row is None:
            row = rows[key] = RecordedRun(plan.run, plan.case, plan.law, plan.solver, plan.omega)
        life = statuses.get((plan.sender, plan.move_id), {})
        row.moves.append(RecordedMove(plan, life.get(MoveState.ACCEPTED), life.get(MoveState.COMPLETED)))
    return list(rows.values())


def _measure(row: RecordedRun, signals: _Signals, accounting: EnergyAccounting) -> None:
    """E_exp of each completed move: ∫ g(τ_m·ω_m) dt over its ticks [start, end] (both ends included),
    across isolated holes (see the module docstring)."""
    stamps, speed, torque = signals.stamp_ns, signals.speed, signals.torque
    half = EXECUTION_PERIOD_NS // 2
    for move in row.completed:
        acc = move.accepted
        if acc is None:
            continue
        start = acc.stamp_of(acc.start_tick)
        lo = np.searchsorted(stamps, start - half, "left")
        hi = np.searchsorted(stamps, acc.stamp_of(acc.end_tick) + half, "left")
        ticks = acc.end_tick - acc.start_tick + 1
        move.samples_missing = ticks - int(hi - lo)
        if move.samples_missing == 0:
            move.energy_measured_j = trace_energy(speed[lo:hi], torque[lo:hi], EXECUTION_PERIOD_S, accounting)
            continue
        k = np.rint((stamps[lo:hi] - start) / EXECUTION_PERIOD_NS).astype(np.int64)
        ends = k.size >= 2 and k[0] == 0 and k[-1] == ticks - 1
        if not ends or int(np.diff(k).max()) > MAX_BRIDGED_HOLE_TICKS + 1:
            continue
        t = k * EXECUTION_PERIOD_S
        move.energy_measured_j = trace_energy_at(t, speed[lo:hi], torque[lo:hi], accounting)


def _idle_ticks(row: RecordedRun, signals: _Signals) -> list[int]:
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


def _setpoints_missing(row: RecordedRun, signals: _Signals) -> int:
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
