"""The paper's figures: their data checked against the model and the planners, and the PNG files."""

from __future__ import annotations

import numpy as np
import pytest
from axisflow.model import Move, check_limits, default_params, move_energy, polynomial_law
from axisflow.planner import Case, MoveProblem, solve_exact
from axisflow.viz.energy_map_figure import energy_map
from axisflow.viz.errors import VizError
from axisflow.viz.figures import write_figures
from axisflow.viz.iteration_cap_figure import CAPS, cap_study
from axisflow.viz.trajectory_figure import planned_traces, recorded_traces

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def params():
    return default_params()


def test_energy_map_is_the_model_energy_on_feasible_durations(params):
    data = energy_map(params, grid=(5, 4))
    law = polynomial_law("poly5")
    for j, d in enumerate(data.distance_m):
        lowest = data.duration_s[0, j]
        assert check_limits(Move(0.0, d, lowest * (1 + 1e-9), law), params).max_violation <= 1e-9
        assert check_limits(Move(0.0, d, lowest * 0.99, law), params).max_violation > 0  # the limit
        for i in range(data.duration_s.shape[0]):
            assert data.energy_j[i, j] == move_energy(Move(0.0, d, data.duration_s[i, j], law), params)
    k = int(np.argmin(abs(data.curve_distance_m - 0.4)))
    d = float(data.curve_distance_m[k])
    expected = solve_exact(MoveProblem(0.0, d, law, Case.MIN_TIME_ENERGY, 0.9), params).duration_s
    assert data.t_opt_s[k] == expected


def test_the_iteration_cap_study_converges_to_the_exact_optimum(params):
    study = cap_study(params, Case.MIN_TIME_ENERGY)
    assert [r.cap for r in study.runs] == list(CAPS)
    assert not study.runs[0].converged and study.runs[-1].converged
    assert all(r.iterations <= r.cap for r in study.runs)
    assert abs(study.runs[-1].duration_s - study.exact_duration_s) <= 1e-5 * study.exact_duration_s


def test_planned_traces_run_the_moves_tick_by_tick_through_the_waypoints(params):
    waypoints = [0.1, 0.7, 0.3, 0.35]
    for trace in planned_traces(params, waypoints, Case.MIN_TIME):
        steps = np.diff(np.round(trace.t_s * 1e3).astype(int))
        assert set(steps.tolist()) == {1}  # one sample per 1 ms tick
        at = np.round(trace.waypoint_times_s * 1e3).astype(int)
        np.testing.assert_allclose(trace.position_m[at], waypoints, atol=1e-12)
        assert np.all(trace.velocity_m_s[at] == 0.0)
        assert np.max(np.abs(trace.torque_nm)) <= params.tau_max * (1 + 1e-9)
        assert np.max(np.abs(trace.velocity_m_s)) <= params.v_max * (1 + 1e-9)


def test_recorded_traces_are_the_measured_samples_of_the_runs(test_log):
    (trace,) = recorded_traces(test_log.path, Case.MIN_TIME)
    assert trace.law == "poly5"
    completed_ends = [m.end_tick for m in test_log.moves]  # accepted moves, in plan order
    assert np.allclose(trace.waypoint_times_s[1:], (np.array(completed_ends) - 200) / 1000)
    assert len(trace.t_s) == max(completed_ends) - 200 + 1
    with pytest.raises(VizError, match="no plan records of a min-time-energy run"):
        recorded_traces(test_log.path, Case.MIN_TIME_ENERGY)


@pytest.mark.slow
def test_write_figures_writes_small_pngs_and_skips_fig2_without_an_excitation(params, tmp_path):
    waypoints = np.random.default_rng(0).uniform(0.0, params.L, 25)
    written = write_figures(tmp_path / "figs", params, waypoints)
    assert [p.name for p in written] == ["fig4a.png", "fig4b.png", "fig5a.png", "fig5b.png"]
    for path in written:
        data = path.read_bytes()
        assert data.startswith(PNG_MAGIC) and 10_000 < len(data) < 200_000, (path, len(data))
    assert sorted(p.name for p in (tmp_path / "figs").iterdir()) == [p.name for p in written]
