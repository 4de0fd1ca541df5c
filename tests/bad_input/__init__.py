"""The catalogue of bad input: every command, as a new user would get it wrong, one module per group
of commands. Each :class:`~.case.Case` is a command line and the fragments its one error line must
name (the value, the limit, the unit); tests/cli/test_bad_input.py runs them all through the real
command line, and docs/refusals.md is generated from them (:mod:`.page`). A new refusal is a new case
in the module of its command."""

from __future__ import annotations

from . import (
    axis,
    deployment,
    files,
    fleet,
    foreign_logs,
    identification,
    logs,
    nodes,
    planning,
    savings,
    terms,
)
from .case import Case

CASES: list[Case] = [
    *planning.CASES,
    *savings.CASES,
    *axis.CASES,
    *terms.CASES,
    *identification.CASES,
    *nodes.CASES,
    *logs.CASES,
    *deployment.CASES,
    *files.CASES,
    *foreign_logs.CASES,
    *fleet.CASES,
]
"""every case, in the order the page lists them within a command"""
