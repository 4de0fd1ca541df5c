"""The planner node against a real bridge over real Zenoh sessions: moves back to back, plan records
published, a rejection stops the run with the bridge's reason, both back-ends."""

import numpy as np
import pytest
from axisflow.acquisition import AxisKeys, ZenohOptions, open_session
from axisflow.model import AxisflowError, default_params
from axisflow.planner import Case, make_backend

from axisflow.nodes.planner_node import NodeRun, NodeSettings, PlannerNode

WAYPOINTS = np.array([0.1, 0.55, 0.2, 0.7, 0.35, 0.6, 0.05, 0.4])


def _node(session, runs, params=None, solver="exact", lookahead_s=2.0):
    settings = NodeSettings(AxisKeys("a0"), runs, 0.9, lookahead=1, lookahead_s=lookahead_s, label="test")
    return PlannerNode(session, settings, params or default_params(), make_backend(solver))


@pytest.mark.parametrize("solver", ["exact", "ipopt"])
@pytest.mark.slow
def test_runs_both_cases_back_to_back_with_plan_records(thread_bridge, port, solver):
    runs = (NodeRun(Case.MIN_TIME, "poly5"), NodeRun(Case.MIN_TIME_ENERGY, "poly3"))
    # at 10× real time, 4 s of drive time queued is 0.4 s of wall time for a plan (IPOPT's first solve
    # alone took 75 ms on a loaded machine; at --speed 0 in-process the bridge runs ~50× real time).
    # The min-time-energy moves (3–6 s each) still run with one or two queued behind: each is planned
    # while the one before runs.
    with (
        thread_bridge(port, speed=10.0) as bridge,
        open_session(ZenohOptions.loopback(connect_port=port)) as session,
        _node(session, runs, solver=solver, lookahead_s=4.0) as node,
    ):
        reports = node.run(WAYPOINTS)
        records = bridge.plan_records()
    assert [r.run for r in reports] == list(runs)
    for report in reports:
        moves = report.experiment
        assert len(moves) == len(WAYPOINTS) - 1
        assert all(m.completed is not None for m in moves)
        assert report.idle_ticks == [0] * (len(moves) - 1)
        assert [m.command.end_position_m for m in moves] == pytest.approx(WAYPOINTS[1:].tolist())
        assert all(m.plan.solver == solver and m.plan.max_violation == 0.0 for m in moves)
    # each run first brings the axis from where it is to the first way point (not part of the run)
    first, second = reports[0].moves[0], reports[1].moves[0]
    assert first.index == second.index == 0
    assert first.command.start_position_m == 0.0 and second.command.start_position_m == WAYPOINTS[-1]
    assert first.command.end_position_m == second.command.end_position_m == WAYPOINTS[0]
    experiment = [r for r in records if r.waypoint_index > 0]
    assert len(experiment) == 2 * (len(WAYPOINTS) - 1)
    assert {(r.case, r.law, r.run) for r in experiment} == {
        ("min-time", "poly5", "test"),
        ("min-time-energy", "poly3", "test"),
    }
    by_id = {m.command.move_id: m for r in reports for m in r.moves}
    for r in records:
        assert (
            r.duration_s == by_id[r.move_id].plan.duration_s and r.sender == by_id[r.move_id].accepted.sender
        )


def test_moves_shorter_than_one_encoder_count_are_not_sent(thread_bridge, port):
    """Repeated way points and ones within a count (1.917 µm) of the one before are zero moves: nothing
    is sent or published for them, and the moves around them still run back to back."""
    points = np.array([0.1, 0.1, 0.1 + 1e-7, 0.55, 0.55, 0.2, 0.2 + 1e-310, 0.7, 0.7])
    with (
        thread_bridge(port, speed=5.0) as bridge,
        open_session(ZenohOptions.loopback(connect_port=port)) as session,
        _node(session, (NodeRun(Case.MIN_TIME, "poly5"),)) as node,
    ):
        (report,) = node.run(points)
        records = bridge.plan_records()
    assert report.zero_moves == [1, 2, 4, 6, 8]
    moves = report.experiment
    assert [m.index for m in moves] == [3, 5, 7]
    assert [m.command.end_position_m for m in moves] == pytest.approx([0.55, 0.2, 0.7])
    assert all(m.completed is not None for m in moves)
    assert report.idle_ticks == [0, 0]
    assert sorted(r.waypoint_index for r in records if r.waypoint_index > 0) == [3, 5, 7]
    assert "3 moves (+5 zero moves, not sent)" in report.summary()


def test_a_move_the_bridge_refuses_stops_the_run_with_its_reason(thread_bridge, port):
    strict = default_params().replace(tau_max=2.0)  # the bridge allows half the torque the planner plans for
    with (
        thread_bridge(port, params=strict) as _bridge,
        open_session(ZenohOptions.loopback(connect_port=port)) as session,
        _node(session, (NodeRun(Case.MIN_TIME, "poly5"),)) as node,
        pytest.raises(
            AxisflowError,
            match=r"the bridge rejected move \d+: .*peak motor torque .* exceeds tau_max = 2.0 N·m",
        ),
    ):
        node.run(WAYPOINTS)


def test_no_bridge_is_a_clear_error_not_a_hang(port):
    import axisflow.nodes.planner_node as node_module

    with open_session(ZenohOptions.loopback(listen_port=port)) as session:
        old, node_module.BRIDGE_TIMEOUT_S = node_module.BRIDGE_TIMEOUT_S, 1.0
        try:
            with pytest.raises(AxisflowError, match="no bridge for axis 'a0' answered within 1 s"):
                _node(session, (NodeRun(Case.MIN_TIME, "poly5"),)).__enter__()
        finally:
            node_module.BRIDGE_TIMEOUT_S = old
