"""The fault suite: real processes killed, fuzzed, flooded and starved (docs/trust.md).

Each test runs a scenario of :mod:`axisflow.faults` — the same code ``axisflow bench faults``
measures with — and asserts its outcome. Fault 3 (the planner killed with moves queued, then restarted)
is tests/nodes/test_planner_restart.py; run the whole suite with

    python -m pytest tests/faults tests/nodes/test_planner_restart.py
"""
