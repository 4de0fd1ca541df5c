"""``axisflow savings`` as a library call: the moves, the plans, the runs on the axis, the report.

:func:`run_savings` takes typed :class:`SavingsSettings` and

1. reads the axis model (``--params``; its ``[baseline]`` table gives the baseline's limits unless
   ``--limits`` does; neither: the fastest the axis can follow) and refuses limits the axis cannot
   follow (:func:`~axisflow.planner.baseline_limits.check_reachable`);
2. takes the moves (:mod:`.cycle_moves`: a recording's, a way-point file's, or random ones);
3. plans the comparison on the model (:mod:`.comparison`);
4. runs the three runs through a simulated bridge and measures them from its recording
   (:mod:`.axis_run`, :mod:`.measurement`), unless ``measure`` is off;
5. writes ``savings.json``, ``savings.md`` (:mod:`.report`) and ``savings.png``
   (:mod:`axisflow.viz.savings_figure`) into the output folder, together atomically.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable, Sequence
from pathlib import Path

from ..acquisition import AxisKeys
from ..model import AxisParams
from ..planner.baseline_limits import axis_limits, baseline_limits, check_law
from ..planner.cycle_time import match_cycle_time
from .comparison import Comparison, PlannedRun, plan_comparison
from .cycle_moves import moves_of_file, moves_of_random, moves_of_recording
from .report import MoveRow, RunRow, SavingsReport, write_report
from .settings import DEFAULT_HOURS_PER_DAY, DEFAULT_LAW, SavingsSettings


def run_savings(
    settings: SavingsSettings, progress: Callable[[str], None], stop: threading.Event | None = None
) -> SavingsReport:
    """Run the comparison (see the module docstring) into ``settings.out``."""
    check_law(settings.baseline)
    params, limits = baseline_limits(settings.params_path, settings.limits)
    if settings.recording is not None:
        moves = moves_of_recording(settings.recording, params)
    elif settings.waypoints_file is not None:
        moves = moves_of_file(settings.waypoints_file, params)
    else:
        assert settings.random_waypoints is not None
        moves = moves_of_random(settings.random_waypoints, settings.seed, params)
    progress(f"{len(moves)} moves: {settings.source}; baseline {settings.baseline} under {limits.describe()}")
    comparison = plan_comparison(moves, settings.baseline, limits, settings.law, params, progress)
    measured: dict[str, dict] = {}
    plant = ""
    if settings.measure:
        from .axis_run import AxisRunSettings, run_on_axis
        from .measurement import measure

        axis = run_on_axis(
            comparison.runs,
            params,
            AxisRunSettings(settings.out, settings.plant_profile, overwrite=settings.overwrite),
            progress,
            stop,
        )
        plant = axis.plant
        measured = {run.label: measure(axis.recording, run.label) for run in comparison.runs}
    base_time = comparison.run("baseline").cycle_time_s
    per_day = settings.cycles_per_day
    if per_day is None:
        per_day = DEFAULT_HOURS_PER_DAY * 3600.0 / base_time if base_time > 0.0 else 0.0
    report = SavingsReport(
        source=settings.source,
        params_source=settings.params_path or "the packaged default parameters",
        energy_accounting=params.energy_accounting.value,
        baseline=settings.baseline,
        limits=comparison.limits.to_dict(),
        law=settings.law,
        match_status=comparison.match_status.value,
        runs=tuple(_run_row(run, measured.get(run.label, {})) for run in comparison.runs),
        front=tuple((p.omega, p.cycle_time_s, p.energy_j) for p in comparison.front),
        baseline_points={k: (p.cycle_time_s, p.energy_j) for k, p in comparison.baseline_points.items()},
        cycles_per_day=per_day,
        days_per_year=settings.days_per_year,
        price_per_kwh=settings.price_per_kwh,
        plant=plant,
    )
    write_report(report, settings.out, {"savings.png": figure(report, comparison)})
    return report


def _run_row(run: PlannedRun, measured: dict) -> RunRow:
    rows = []
    for m in run.moves:
        got = measured.get(m.index)
        rows.append(
            MoveRow(
                index=m.index,
                x0_m=m.x0_m,
                x1_m=m.x1_m,
                duration_s=m.duration_s,
                energy_model_j=m.score.energy_j,
                energy_measured_j=None if got is None else got.energy_j,
                peak_torque_model_nm=m.score.peak_torque_nm,
                peak_torque_measured_nm=None if got is None else got.peak_torque_nm,
                peak_power_model_w=m.score.peak_power_w,
                peak_power_measured_w=None if got is None else got.peak_power_w,
                torque_sq_model=m.score.torque_sq_integral,
                torque_sq_measured=None if got is None else got.torque_sq_integral,
            )
        )
    return RunRow(run.label, run.law, run.omega, tuple(rows), run.slower_moves)


def figure(report: SavingsReport, comparison: Comparison) -> bytes:
    from ..viz.savings_figure import SavingsPoint, savings_png

    points = [
        SavingsPoint(r.label, r.cycle_time_s, r.energy_model_j, r.energy_measured_j) for r in report.runs
    ]
    return savings_png(
        [(t, e) for _w, t, e in report.front],
        report.law,
        report.baseline_points,
        points,
        f"{report.law} against a {report.baseline}: energy per cycle against cycle time",
    )


def compare_on_session(
    session: object,
    moves: Sequence[tuple[float, float]],
    params: AxisParams,
    progress: Callable[[str], None],
    stop: threading.Event,
    keys: AxisKeys | None = None,
) -> Comparison:
    """The comparison against a trapezoid at the axis's own limits (:func:`axis_limits`), planned on
    ``params`` and run on the bridge of ``keys`` behind ``session``, whose recorder the caller runs (the
    demo's closing phase; :func:`measured_savings` reads it back)."""
    from .axis_run import send_runs

    comparison = plan_comparison(moves, "trapezoid", axis_limits(params), DEFAULT_LAW, params, front=False)
    send_runs(session, keys or AxisKeys(), comparison.runs, params, progress, stop)
    return comparison


def measured_savings(comparison: Comparison, recording: Path) -> dict[str, dict[str, float | None]]:
    """Per run of axisflow's law: the energy saved against the baseline [%], on the model and as
    measured from ``recording`` (None where a move was not measured)."""
    from .measurement import measure

    energy: dict[str, tuple[float, float | None]] = {}
    for run in comparison.runs:
        values = [m.energy_j for m in measure(recording, run.label).values()]
        measured = None if None in values else math.fsum(v for v in values if v is not None)
        energy[run.label] = (run.energy_j, measured)
    base_model, base_meas = energy["baseline"]
    out: dict[str, dict[str, float | None]] = {}
    for label in ("equal-time", "matched-omega"):
        model, meas = energy[label]
        out[label] = {
            "model_pct": (base_model - model) / base_model * 100.0,
            "measured_pct": None if meas is None or not base_meas else (base_meas - meas) / base_meas * 100.0,
        }
    return out


def saving_line(comparison: Comparison, savings: dict[str, dict[str, float | None]]) -> str:
    """One line of :func:`measured_savings`: measured, the model's figure in brackets."""

    def pct(label: str) -> str:
        s = savings[label]
        measured = "–" if s["measured_pct"] is None else f"{s['measured_pct']:.2f} %"
        return f"{measured} ({s['model_pct']:.2f} %)"

    base = comparison.run("baseline")
    n = sum(1 for m in base.moves if not m.zero_move)
    return (
        f"energy saved against a {comparison.baseline_law} at equal cycle time ({n} moves, "
        f"{base.cycle_time_s:.2f} s), measured (model): {comparison.law} move by move {pct('equal-time')}, "
        f"at the matched ω {pct('matched-omega')}"
    )


def equal_time_saving(
    moves: Sequence[tuple[float, float]], law: str, durations_s: Sequence[float], accurate: AxisParams
) -> dict[str, float | str]:
    """What an accurate model saves against plans made with a stale one, at equal cycle time, both
    judged by the accurate model: the stale plans' moves at their ``durations_s`` along ``law``, against
    the accurate model's plans at the ω that matches their cycle time
    (:func:`~axisflow.planner.cycle_time.match_cycle_time`)."""
    from ..planner.cycle_time import plan_at_durations

    stale = plan_at_durations(moves, law, durations_s, accurate)
    match = match_cycle_time(moves, law, stale.total_time_s, accurate)
    e_stale, e_new = stale.total_energy_j, match.plan.total_energy_j
    return {
        "law": law,
        "cycle_time_s": stale.total_time_s,
        "omega": match.omega,
        "match_status": match.status.value,
        "energy_stale_j": e_stale,
        "energy_accurate_j": e_new,
        "saving_pct": (e_stale - e_new) / e_stale * 100.0 if e_stale else 0.0,
    }
