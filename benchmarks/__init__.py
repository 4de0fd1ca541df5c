"""Benchmarks: each measures a speed or memory goal against a baseline in the same run.

Installs as ``axisflow.benchmarks`` from the folder ``benchmarks/`` (pyproject.toml maps each top-level
folder to a sub-package of ``axisflow``; docs/architecture.md draws their imports).
"""
