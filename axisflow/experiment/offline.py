"""The paper's 100-way-point experiment (Sect. 3–4, Table 2), offline.

Way points are drawn uniformly in [0, L] with a recorded seed; the same way points serve every case
and law. Each of the 99 consecutive moves is planned as the paper did (one solve per move); each row
of the resulting :class:`~axisflow.experiment.table2_record.Table2` holds the planned columns and, with
``limits``, each move against the physical limit. The measured columns stay empty: the moves run on
an axis with ``axisflow planner`` and are measured from the recording by ``axisflow table2``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from itertools import pairwise

import numpy as np

from ..model import AxisParams, MoveError, polynomial_law
from ..planner import DEFAULT_OMEGA, Case, MoveProblem, PlannerBackend, PlanResult
from ..planner.reference_laws import least_energy, time_optimal
from .paper import LAWS, PAPER_WAYPOINTS
from .table2_record import LimitColumns, PlannedColumns, Table2, Table2Row
from .waypoints import random_waypoints

CASES: tuple[Case, ...] = (Case.MIN_TIME, Case.MIN_TIME_ENERGY)


def plan_moves(
    waypoints_m: np.ndarray, case: Case, law: str, backend: PlannerBackend, params: AxisParams, omega: float
) -> tuple[PlanResult, ...]:
    """Plan every move between consecutive way points, one solve per move."""
    problems = [
        MoveProblem(float(a), float(b), polynomial_law(law), case, omega=omega)
        for a, b in pairwise(waypoints_m)
    ]
    for problem in problems:
        problem.check_stroke(params)
    backend.prepare(problems[0], params)
    return tuple(backend.solve(problem, params) for problem in problems)


def move_limits(results: Sequence[PlanResult], params: AxisParams) -> LimitColumns:
    """Each planned move against the physical limit: T_limit (bang–cruise–bang) and E_limit (least
    energy at the move's planned duration, under the parameters' accounting)."""
    times, energies = [], []
    for r in results:
        d = r.problem.distance_m
        t_lim = time_optimal(d, params).duration_s
        times.append(t_lim)
        energies.append(least_energy(d, max(r.duration_s, t_lim), params).energy(params.energy_accounting))
    return LimitColumns(tuple(times), tuple(energies))


def plan_row(
    waypoints_m: np.ndarray,
    case: Case,
    law: str,
    backend: PlannerBackend,
    params: AxisParams,
    omega: float,
    limits: bool = True,
) -> Table2Row:
    """The Table 2 row of one case × law through ``waypoints_m`` (with ``limits``: against the
    physical limit too)."""
    results = plan_moves(waypoints_m, case, law, backend, params, omega)
    return Table2Row(
        case,
        law,
        backend.name,
        omega if case is Case.MIN_TIME_ENERGY else None,
        PlannedColumns.of_results(results),
        limits=move_limits(results, params) if limits else None,
    )


def run_offline(
    params: AxisParams,
    backend: PlannerBackend,
    *,
    seed: int = 0,
    waypoints: int = PAPER_WAYPOINTS,
    omega: float = DEFAULT_OMEGA,
    laws: Sequence[str] = LAWS,
    cases: Sequence[Case] = CASES,
    limits: bool = True,
) -> Table2:
    """Table 2 of the experiment's moves for each case × law on the same way points (and, with
    ``limits``, each move against the physical limit)."""
    if not 0.0 <= omega <= 1.0 or not math.isfinite(omega):
        raise MoveError(f"omega = {omega} is outside [0, 1]")
    points = random_waypoints(waypoints, seed, params)
    rows = tuple(
        plan_row(points, case, law, backend, params, omega, limits) for case in cases for law in laws
    )
    return Table2(
        "Table 2, offline",
        params.energy_accounting,
        tuple(float(w) for w in points),
        rows,
        seed=seed,
        params=params,
    )
