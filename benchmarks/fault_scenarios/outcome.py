"""What a fault scenario measured: one row of the fault table per contract it checks."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any


@dataclass(frozen=True)
class Outcome:
    """One row of the fault table."""

    fault: str
    passed: bool
    outcome: str
    """what happened, with the measured numbers"""
    command: str
    """how to reproduce it"""
    measured: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        return {
            "fault": self.fault,
            "passed": self.passed,
            "outcome": self.outcome,
            "command": self.command,
            "measured": self.measured,
        }


class FaultResult:
    """What a scenario measured; :meth:`outcomes` are its rows of the fault table."""

    def outcome(self) -> Outcome:
        raise NotImplementedError

    def outcomes(self) -> list[Outcome]:
        return [self.outcome()]
