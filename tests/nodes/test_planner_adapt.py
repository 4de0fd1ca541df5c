"""Hot swap: a planner node that follows an adaptive node (``adapt``) plans every move after an accepted
parameter record with it, between moves, and records its version — a real bridge, real Zenoh sessions,
the record published by another session as ``axisflow adapt`` publishes it."""

import threading
import time

import numpy as np
import pytest
from axisflow.acquisition import AxisKeys, ZenohOptions, open_session
from axisflow.acquisition.bus.publisher import SequencedPublisher, Traffic
from axisflow.acquisition.wire.params_estimate import PARAMS_ESTIMATE_TYPE, Decision, ParamsEstimate
from axisflow.model import AxisParams, default_params
from axisflow.planner import Case, ExactBackend, MoveProblem, make_backend

from axisflow.deploy.processes import wait_until
from axisflow.nodes.planner_node import NodeRun, NodeSettings, PlannerNode

KEYS = AxisKeys("a0")
WAYPOINTS = np.array([0.1, 0.55, 0.2, 0.7, 0.35, 0.6, 0.05, 0.4, 0.75, 0.3, 0.65, 0.15, 0.5, 0.25])
BASE = default_params()


def _record(params: AxisParams, version: int = 1, accepted: bool = True) -> ParamsEstimate:
    decision = Decision.ACCEPTED if accepted else Decision.NO_IMPROVEMENT
    return ParamsEstimate(
        time.time_ns(), "a0", version if accepted else version - 1, version - 1, decision, "a test's record",
        ("M_eq", "a2", "coulomb"),
        (params.M_eq, params.a1, params.a2, params.a3, params.a4, params.f0, params.da1, params.da2),
    )  # fmt: skip


def _run_with_records(thread_bridge, port, records, after_plans=4):
    """The node over WAYPOINTS (min-time poly5) on a bridge at 5× real time; once ``after_plans`` plan
    records are out, another session publishes ``records`` on the axis's params key. Returns the plan
    records (in order), the node's report and the wall clock [ns] of the publishing."""
    settings = NodeSettings(KEYS, (NodeRun(Case.MIN_TIME, "poly5"),), 0.9, 1, 2.0, "adapt", adapt=True)
    result = {}
    with (
        thread_bridge(port, speed=5.0) as bridge,
        open_session(ZenohOptions.loopback(connect_port=port)) as session,
        open_session(ZenohOptions.loopback(connect_port=port)) as adapter,
        SequencedPublisher(adapter, KEYS.params, PARAMS_ESTIMATE_TYPE, Traffic.COMMAND) as publisher,
        PlannerNode(session, settings, BASE, make_backend("exact")) as node,
    ):
        thread = threading.Thread(target=lambda: result.update(reports=node.run(WAYPOINTS)))
        thread.start()
        plans = []
        assert wait_until(lambda: len(plans.extend(bridge.plan_records()) or plans) >= after_plans, 30.0)
        published_ns = time.time_ns()
        for record in records:
            publisher.put(record.encode(), record.stamp_ns)
        thread.join(120)
        assert not thread.is_alive()
        plans += bridge.plan_records()
    return sorted(plans, key=lambda p: p.stamp_ns), result["reports"][0], published_ns


def test_every_plan_after_an_accepted_record_uses_its_version(thread_bridge, port):
    # with an offset and an asymmetry too (small enough that neither direction has less friction than
    # the bridge's model, which would hold a faster plan to its limits): a term fitted is a term planned
    colder = BASE.replace(
        a1=BASE.a1 * 1.15, a2=BASE.a2 * 1.1, a3=BASE.a3 * 1.15, m=BASE.m * 1.03, f0=5.0, da1=4.0, da2=10.0
    )
    assert min(colder.forward(s).c for s in (1, -1)) >= BASE.a1 and colder.a2 - colder.da2 >= BASE.a2
    plans, report, published_ns = _run_with_records(thread_bridge, port, [_record(colder)])
    versions = [p.params_version for p in plans]
    assert versions == sorted(versions) and set(versions) == {0, 1}  # swapped once, between two moves
    swapped = versions.index(1)
    assert swapped >= 4 and plans[swapped].stamp_ns >= published_ns
    for plan in plans:
        params = colder if plan.params_version == 1 else BASE
        problem = MoveProblem(plan.start_position_m, plan.end_position_m, "poly5", Case.MIN_TIME)
        expected = ExactBackend().solve(problem, params)
        assert plan.duration_s == pytest.approx(expected.duration_s, rel=1e-12)
        assert plan.energy_j == pytest.approx(expected.energy_j, rel=1e-12)
    assert [m.params_version for m in report.moves] == versions
    assert "parameter versions 0…1" in report.summary()
    assert all(m.completed is not None for m in report.experiment) and report.idle_ticks == [0] * (
        len(report.experiment) - 1
    )


def test_a_rejected_record_changes_nothing_and_a_faster_set_is_held_to_the_bridges_limits(
    thread_bridge, port
):
    """A turned-down estimate is ignored; an accepted set with much less friction would plan faster moves
    than the node's own parameters (the bridge's) allow: they are planned no faster than those allow."""
    warm = BASE.replace(a1=BASE.a1 * 0.7, a2=BASE.a2 * 0.7, a3=BASE.a3 * 0.7)
    records = [_record(BASE.replace(a2=BASE.a2 * 2), version=1, accepted=False), _record(warm, version=1)]
    plans, report, _published = _run_with_records(thread_bridge, port, records)
    assert {p.params_version for p in plans} == {0, 1}
    floored = 0
    for plan in (p for p in plans if p.params_version == 1):
        problem = MoveProblem(plan.start_position_m, plan.end_position_m, "poly5", Case.MIN_TIME)
        free = ExactBackend().solve(problem, warm).duration_s
        own = ExactBackend().solve(problem, BASE).duration_s
        assert plan.duration_s >= own - 1e-12  # never faster than the bridge's model allows
        floored += free < own
    assert floored > 0  # the warm set did ask for faster moves
    assert all(m.accepted is not None for m in report.moves)  # and the bridge took every one
