"""SIGTERM and SIGHUP as a clean unwinding of the command, like Ctrl-C.

Python's default for SIGTERM and SIGHUP ends the process on the spot: no ``finally`` runs, so a
writer's temporary file stays behind. Within :func:`signals_unwind` (the command line's whole run) the
first SIGTERM or SIGHUP raises :class:`Terminated` in the main thread instead — a
``KeyboardInterrupt``, so that every clean-up that runs for Ctrl-C runs for it too (temporary files
removed, children stopped) — and a second one, should the unwinding hang, ends the process the
default way. Commands that stop on signals by themselves (``record``, ``bridge``, ``replay``…:
:func:`axisflow.deploy.processes.stop_on_signals`) replace these handlers while they run.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager

UNWOUND_SIGNALS = (signal.SIGTERM, signal.SIGHUP)


class Terminated(KeyboardInterrupt):
    """The command was asked to stop by a signal (SIGTERM, SIGHUP)."""

    def __init__(self, signum: int) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = signum

    @property
    def exit_code(self) -> int:
        """128 + the signal's number, as a shell reports a process ended by it."""
        return 128 + self.signum


@contextmanager
def signals_unwind() -> Iterator[None]:
    """Within the block, the first SIGTERM or SIGHUP raises :class:`Terminated` (main thread only;
    the previous handlers are restored on exit)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {s: signal.getsignal(s) for s in UNWOUND_SIGNALS}
    raised: list[int] = []

    def handler(signum: int, _frame: object) -> None:
        if raised:  # the unwinding hangs: end the default way
            signal.signal(signum, signal.SIG_DFL)
            signal.raise_signal(signum)
            return
        raised.append(signum)
        raise Terminated(signum)

    for s in previous:
        signal.signal(s, handler)
    try:
        yield
    finally:
        for s, h in previous.items():
            if h is not None:
                signal.signal(s, h)
