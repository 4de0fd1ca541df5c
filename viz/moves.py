"""What the moves of an axis did, from the typed records of the wire contract: where they ended (the
way points), what they were planned to cost and what they cost.

* The bridge's :class:`~axisflow.acquisition.MoveStatus` gives a move's tick span: an ``accepted``
  status carries ``start_tick`` and ``end_tick``, and the drive time of tick k is
  ``stamp_ns + (k − tick)·1 ms`` (a status is stamped with the drive time of its own ``tick``).
* The planner's :class:`~axisflow.acquisition.PlanRecord` of the same (sender, move_id) gives the move's
  end position — a way point, drawn at the end tick — and its model energy E_th.
* The measured energy of a move is E = ∫ g(τ_m·ω_m) dt over its ticks [start, end], both included,
  by the trapezoidal rule at 1 kHz (:func:`axisflow.model.trace_energy`), g the energy accounting of
  the parameters — what ``axisflow table2`` reports as E_exp per move. A move that was dropped,
  rejected or stopped early gets none.
* Once both are known, the move's E% = (E_th − E_exp)/E_th·100 (the paper's definition, per move: what
  ``axisflow table2 --per-move`` writes), at the move's end tick.

:class:`MoveLedger` takes the records and the measured samples in any order and in batches (a log at
once, the network as it comes) and hands back each point once it is known.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..acquisition.wire.move_status import MoveState, MoveStatus
from ..acquisition.wire.plan_record import PlanRecord
from ..model import EXECUTION_PERIOD_S, EnergyAccounting, trace_energy
from ..model.energy import energy_error_pct
from .samples import AxisSamples

SAMPLE_HISTORY_NS = 2_000_000_000
"""measured samples kept [ns] behind the newest one while no move is open: a move accepted to start
on the current tick may be announced after that tick's sample arrived"""
_ENDED = (MoveState.REJECTED, MoveState.DROPPED, MoveState.STOPPED)


@dataclass(frozen=True)
class MovePoint:
    """One point of a per-move plot: at drive time ``stamp_ns`` (the move's end tick), ``value`` (a
    position [m] or an energy [J])."""

    stamp_ns: int
    value: float
    move_id: int


@dataclass
class MovePoints:
    """What one call of :class:`MoveLedger` made known."""

    waypoints: list[MovePoint] = field(default_factory=list)
    planned_energy: list[MovePoint] = field(default_factory=list)
    measured_energy: list[MovePoint] = field(default_factory=list)
    energy_error: list[MovePoint] = field(default_factory=list)
    """E% of each move [%]"""

    def extend(self, other: MovePoints) -> None:
        self.waypoints += other.waypoints
        self.planned_energy += other.planned_energy
        self.measured_energy += other.measured_energy
        self.energy_error += other.energy_error


@dataclass(frozen=True)
class _Span:
    move_id: int
    start_ns: int
    end_ns: int


class MoveLedger:
    """The moves of one axis (see the module docstring)."""

    def __init__(self, accounting: EnergyAccounting) -> None:
        self.accounting = accounting
        self._plans: dict[tuple[str, int], PlanRecord] = {}
        self._spans: dict[tuple[str, int], _Span] = {}
        self._planned_done: set[tuple[str, int]] = set()
        self._open: dict[tuple[str, int], _Span] = {}
        """spans whose measured energy is still to come"""
        self._measured: dict[tuple[str, int], float] = {}
        """measured energies of the moves whose plan has not come yet"""
        self._samples: list[AxisSamples] = []
        self._newest_ns: int | None = None
        self.unmeasured = 0
        """moves whose samples did not cover their span (begun before the view started)"""

    def add_plan(self, plan: PlanRecord) -> MovePoints:
        key = (plan.sender, plan.move_id)
        self._plans.setdefault(key, plan)
        return self._planned(key)

    def add_status(self, status: MoveStatus) -> MovePoints:
        key = (status.sender, status.move_id)
        if status.state is MoveState.ACCEPTED and key not in self._spans:
            span = _Span(
                status.move_id,
                status.stamp_of(status.start_tick),
                status.stamp_of(status.end_tick),
            )
            self._spans[key] = self._open[key] = span
            return self._planned(key)
        if status.state in _ENDED:
            self._open.pop(key, None)
        return MovePoints()

    def add_samples(self, samples: AxisSamples) -> MovePoints:
        """Measured state samples (any batch, sorted or not); returns the energies of the moves whose
        end tick they reach."""
        if len(samples):
            self._samples.append(samples.sorted())
            newest = int(samples.stamp_ns.max())
            self._newest_ns = newest if self._newest_ns is None else max(self._newest_ns, newest)
        points = MovePoints()
        if self._newest_ns is None:
            return points
        due = [k for k, s in self._open.items() if s.end_ns <= self._newest_ns]
        if due:
            held = AxisSamples.concatenate(self._samples).sorted()
            self._samples = [held]
            for key in due:
                span = self._open.pop(key)
                point = self._measure(span, held)
                if point is None:
                    self.unmeasured += 1
                else:
                    points.measured_energy.append(point)
                    self._measured[key] = point.value
                    points.energy_error += self._error(key)
        self._trim()
        return points

    def _measure(self, span: _Span, held: AxisSamples) -> MovePoint | None:
        stamps = held.stamp_ns
        if not len(stamps) or stamps[0] > span.start_ns:
            return None
        lo = int(np.searchsorted(stamps, span.start_ns, "left"))
        hi = int(np.searchsorted(stamps, span.end_ns, "right"))
        energy = trace_energy(
            held.motor_speed_rad_s[lo:hi], held.torque_nm[lo:hi], EXECUTION_PERIOD_S, self.accounting
        )
        return MovePoint(span.end_ns, energy, span.move_id)

    def _trim(self) -> None:
        """Drop the sample batches that no open move and no late announcement can need."""
        assert self._newest_ns is not None
        keep_from = self._newest_ns - SAMPLE_HISTORY_NS
        if self._open:
            keep_from = min(keep_from, min(s.start_ns for s in self._open.values()))
        done = 0  # batches come in time order: the old ones are at the front
        while done < len(self._samples) and (
            not len(self._samples[done]) or int(self._samples[done].stamp_ns[-1]) < keep_from
        ):
            done += 1
        del self._samples[:done]

    def _planned(self, key: tuple[str, int]) -> MovePoints:
        points = MovePoints()
        plan, span = self._plans.get(key), self._spans.get(key)
        if plan is None or span is None or key in self._planned_done:
            return points
        self._planned_done.add(key)
        points.waypoints.append(MovePoint(span.end_ns, plan.end_position_m, plan.move_id))
        points.planned_energy.append(MovePoint(span.end_ns, plan.energy_j, plan.move_id))
        points.energy_error += self._error(key)
        return points

    def _error(self, key: tuple[str, int]) -> list[MovePoint]:
        """The move's E% once its plan, span and measured energy are all known (once)."""
        plan, span, measured = self._plans.get(key), self._spans.get(key), self._measured.get(key)
        if plan is None or span is None or measured is None or key not in self._planned_done:
            return []
        del self._measured[key]
        error = energy_error_pct(plan.energy_j, measured)
        return [] if error is None else [MovePoint(span.end_ns, error, plan.move_id)]
