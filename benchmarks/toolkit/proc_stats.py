"""What a process costs, from Linux's ``/proc``: its CPU time, each of its threads' CPU time, its
resident memory."""

from __future__ import annotations

import os
from pathlib import Path


def cpu_seconds(pid: int) -> float:
    """User + system CPU time process ``pid`` has used so far [s] (an ``OSError`` once the process is
    gone)."""
    return _cpu_of_stat(Path(f"/proc/{pid}/stat").read_text())


def cpu_seconds_or_zero(pid: int) -> float:
    """:func:`cpu_seconds`, or 0 once the process is gone."""
    try:
        return cpu_seconds(pid)
    except OSError:
        return 0.0


def _cpu_of_stat(stat: str) -> float:
    """User + system CPU time [s] in the text of a ``/proc/…/stat`` file."""
    fields = stat.rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def thread_cpu_seconds(pid: int) -> dict[int, tuple[str, float]]:
    """Per thread of process ``pid``: its name and the user + system CPU time it has used so far [s]
    (clock-tick resolution; a thread that ends meanwhile is left out)."""
    out = {}
    for tid in os.listdir(f"/proc/{pid}/task"):
        try:
            stat = Path(f"/proc/{pid}/task/{tid}/stat").read_text()
        except OSError:
            continue
        out[int(tid)] = (stat[stat.index("(") + 1 : stat.rindex(")")], _cpu_of_stat(stat))
    return out


def status_kb(pid: int, field: str = "VmRSS") -> int:
    """A memory figure of process ``pid`` from ``/proc/<pid>/status`` [kB] (``VmRSS``: resident now,
    ``VmHWM``: its peak); an ``OSError`` once the process is gone, a ``RuntimeError`` if it has no such
    figure (a process that is exiting)."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith(field + ":"):
            return int(line.split()[1])
    raise RuntimeError(f"no {field} for process {pid}")


def rss_kb(pid: int, field: str = "VmRSS") -> int:
    """:func:`status_kb`, or 0 once the process is gone."""
    try:
        return status_kb(pid, field)
    except (OSError, RuntimeError):
        return 0
