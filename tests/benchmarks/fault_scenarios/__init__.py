"""The fault suite: real processes killed, fuzzed, flooded and starved (docs/trust.md).

Each test runs a scenario of :mod:`axisflow.benchmarks.fault_scenarios` — the same code ``axisflow
bench faults`` measures with — and asserts its outcome. Fault 3 (the planner killed with moves queued,
then restarted) is tests/nodes/test_planner_restart.py; run the whole suite with

    python -m pytest tests/benchmarks/fault_scenarios tests/nodes/test_planner_restart.py
"""
