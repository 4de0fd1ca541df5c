"""A case of the bad-input catalogue: the command line, and what the one error line must name."""

from __future__ import annotations

from dataclasses import dataclass

LOOPBACK = ("--listen", "tcp/127.0.0.1:0")  # a session that reaches for nobody else's peers
LONG = "x" * 300
"""a file name longer than any file system takes (255 bytes): ENAMETOOLONG wherever it is used"""


@dataclass(frozen=True)
class Case:
    id: str
    args: tuple[str, ...]
    says: tuple[str, ...]
    """fragments the one error line must contain: the value, the limit, the unit"""
    untouched: tuple[str, ...] = ()
    """paths (in the working folder) that must be absent afterwards, or unchanged if they existed"""


def case(name: str, *args: str, says: tuple[str, ...], untouched: tuple[str, ...] = ()) -> Case:
    return Case(name, args, says, untouched)
