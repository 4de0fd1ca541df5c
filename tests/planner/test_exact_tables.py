"""The exact solver's tables: built ahead by set-up, immutable, shared, and never built by a solve."""

import dataclasses

import pytest
from axisflow.model import default_params, polynomial_law
from axisflow.planner import Case, MoveProblem, make_backend
from axisflow.planner.exact import law_model, solve_exact
from axisflow.planner.exact import objective as objective_module
from axisflow.planner.exact.start_table import START_TABLES, StartTable, build_start_table
from axisflow.planner.exact.torque_limit import TorqueRootTable, torque_limit


def _count_braking_evaluations(monkeypatch):
    calls = []
    real = objective_module.braking_energy_and_slope

    def counted(*args):
        calls.append(args[2])
        return real(*args)

    monkeypatch.setattr(objective_module, "braking_energy_and_slope", counted)
    return calls


def test_a_solve_reads_the_start_table_and_never_builds_one(monkeypatch):
    p = default_params().replace(energy_accounting="absolute", a4=13.0)  # an axis no other test prepares
    law = polynomial_law("poly3")
    problem = MoveProblem(0.30, 0.33, law, Case.MIN_TIME_ENERGY)
    calls = _count_braking_evaluations(monkeypatch)
    builds = build_start_table.cache_info().misses
    unguided = solve_exact(problem, p)
    assert build_start_table.cache_info().misses == builds  # no hidden set-up cost in a solve
    assert START_TABLES.get(law, p, problem.omega, 2.0) is None
    unguided_evaluations = len(calls)

    make_backend("exact").prepare(problem, p)
    assert isinstance(START_TABLES.get(law, p, problem.omega, 2.0), StartTable)
    calls.clear()
    guided = solve_exact(problem, p)
    assert 0 < len(calls) < unguided_evaluations  # the table shortens the path ...
    a, b = guided.certificate.t_lower_s, guided.certificate.t_upper_s
    a0, b0 = unguided.certificate.t_lower_s, unguided.certificate.t_upper_s
    assert max(a, a0) <= min(b, b0) * (1 + 1e-10)  # ... not the answer: the proved brackets overlap
    assert guided.objective == pytest.approx(unguided.objective, rel=1e-12)


def test_the_shared_law_model_and_torque_limit_are_built_whole_and_never_change():
    p = default_params()
    law = polynomial_law("poly7")
    limit = torque_limit(law, p)
    assert limit.model is law_model(law, p)
    assert isinstance(limit.table, TorqueRootTable)
    assert all(isinstance(col, tuple) and len(col) == 160 for col in dataclasses.astuple(limit.table))
    table = limit.table
    make_backend("exact").prepare(MoveProblem(0.1, 0.12, law, Case.MIN_TIME_ENERGY), p)
    solve_exact(MoveProblem(0.1, 0.12, law, Case.MIN_TIME_ENERGY), p)
    assert torque_limit(law, p) is limit and limit.table is table
    with pytest.raises(dataclasses.FrozenInstanceError):
        limit.table = None
    with pytest.raises(dataclasses.FrozenInstanceError):
        limit.model.M = 1.0
