"""axisflow's processes: started, watched and stopped from one place.

**Launching** (the demo, the tests, the benchmarks): a :class:`Launcher` starts ``axisflow`` commands as
child processes on this machine, their output in files (a pipe nobody reads would block a chatty
child), and stops them in order — SIGINT first, so a recorder writes its summary and footer, a kill
only for one that hangs. A child can say it is ready (:func:`notify_ready`; ``start(…, ready=True)``
and :meth:`Launcher.wait_ready`): one byte on a pipe of its own, written once its work has begun (the
recorder: once its subscriber has joined), so nobody guesses with a sleep.

**Children end with their launcher, however it ends.** Every child gets the read end of a pipe whose
write end only the launcher holds (the *lifeline*). When the launcher's process ends — cleanly, by an
exception, or by SIGKILL (a supervisor's time-out, the OOM killer) — the kernel closes the write end;
the child's watcher thread (:func:`follow_launcher`, started by the command line) reads end-of-file
and sends its own process SIGTERM, which stops it cleanly as a signal from a terminal would; one that
has not ended :data:`ORPHAN_GRACE_S` later exits hard. Unlike ``PR_SET_PDEATHSIG`` this does not depend
on which thread started the child, and works wherever pipes do.

**Stopping on a signal** (every long-running command): :func:`stop_on_signals` turns SIGINT and
SIGTERM into an event the command's loop checks.

**Watching**: :func:`wait_until` polls a fact with a deadline; :func:`free_port` finds a loopback port.
"""

from __future__ import annotations

import contextlib
import json
import os
import select
import signal
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..model import AxisflowError

LIFELINE_ENV = "AXISFLOW_LIFELINE_FD"
"""the environment variable naming a child's lifeline file descriptor"""
READY_ENV = "AXISFLOW_READY_FD"
"""the environment variable naming the file descriptor a child writes its ready byte to"""
ORPHAN_GRACE_S = 10.0
"""how long a child whose launcher is gone may take to stop on its own SIGTERM before it exits hard [s]"""
STOP_TIMEOUT_S = 30.0
"""how long :meth:`Launcher.stop` waits for a child to finish after SIGINT before killing it [s]"""
READY_TIMEOUT_S = 60.0
"""how long a launched ``axisflow`` process (a bridge, a recorder, a router…) may take to say it is
ready on a loaded machine [s]"""
_READY_BYTE = b"R"
_SIGNALLED = b"S"
"""what :func:`stop_on_signals`'s handler writes to its relay"""
_RELAY_END = b"E"
"""what ends :func:`stop_on_signals`'s relay thread"""
_RELAY_JOIN_S = 1.0


class LaunchError(AxisflowError):
    """A child process exited early, or did not get ready in time."""


# ---- watching ----------------------------------------------------------------------------------------


def free_port() -> int:
    """A TCP port on 127.0.0.1 that was free a moment ago."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_until(predicate: Callable[[], object], timeout_s: float, poll_s: float = 0.01) -> bool:
    """True as soon as ``predicate()`` is true (checked at once, then every ``poll_s``); False once
    ``timeout_s`` has passed without it."""
    deadline = time.monotonic() + timeout_s
    while not predicate():
        if time.monotonic() >= deadline:
            return False
        time.sleep(poll_s)
    return True


# ---- in a command: signals, the launcher's life, readiness ------------------------------------------


@contextmanager
def stop_on_signals() -> Iterator[threading.Event]:
    """Within the block, SIGINT and SIGTERM set the yielded event instead of raising/killing.

    Only in the main thread (elsewhere the handlers are left alone); the previous handlers are
    restored on exit. The handler takes no lock: it writes a byte to a pipe, and a relay thread sets
    the event. (Python runs a handler in the main thread between two bytecodes, which may be inside
    that thread's own ``stop.wait()`` while it holds the event's lock: a handler that called
    ``stop.set()`` there would wait for that lock forever, and so would every later signal.)
    """
    stop = threading.Event()
    if threading.current_thread() is not threading.main_thread():
        yield stop
        return
    read_fd, write_fd = os.pipe()
    os.set_blocking(write_fd, False)

    def relay() -> None:
        while os.read(read_fd, 1) == _SIGNALLED:
            stop.set()

    def handler(_signum: int, _frame: object) -> None:
        with contextlib.suppress(BlockingIOError):  # a full pipe: the relay has bytes enough
            os.write(write_fd, _SIGNALLED)

    thread = threading.Thread(target=relay, name="signal-relay", daemon=True)
    thread.start()
    previous = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}
    for s in previous:
        signal.signal(s, handler)
    try:
        yield stop
    finally:
        for s, h in previous.items():
            signal.signal(s, h)
        os.set_blocking(write_fd, True)
        os.write(write_fd, _RELAY_END)
        thread.join(_RELAY_JOIN_S)
        os.close(write_fd)
        os.close(read_fd)


def _take_fd(name: str) -> int | None:
    """The file descriptor named by environment variable ``name``, removed from the environment (so
    that this process's own children never see a number that means nothing to them)."""
    value = os.environ.pop(name, None)
    if value is None or not value.isdigit():
        return None
    fd = int(value)
    try:
        os.set_inheritable(fd, False)
    except OSError:  # not open here (a stale variable): nothing to follow
        return None
    return fd


def follow_launcher() -> threading.Thread | None:
    """In a child of a :class:`Launcher`: watch the lifeline on a daemon thread; when the launcher is
    gone, SIGTERM this process (and exit hard :data:`ORPHAN_GRACE_S` later if that did not end it).
    None (nothing to watch) in a process not started by a launcher."""
    fd = _take_fd(LIFELINE_ENV)
    if fd is None:
        return None

    def watch() -> None:
        try:
            while os.read(fd, 1):  # the launcher never writes: only end-of-file comes
                pass
        except OSError:
            pass
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(ORPHAN_GRACE_S)
        os._exit(1)  # the SIGTERM did not end it: do not outlive the launcher

    thread = threading.Thread(target=watch, name="launcher lifeline", daemon=True)
    thread.start()
    return thread


def notify_ready() -> None:
    """In a child started with ``ready=True``: tell the launcher this command is ready (once; a no-op
    elsewhere)."""
    fd = _take_fd(READY_ENV)
    if fd is None:
        return
    try:
        os.write(fd, _READY_BYTE)
    except OSError:  # the launcher stopped waiting
        pass
    finally:
        os.close(fd)


# ---- launching -----------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Exited:
    """A finished child: its exit code and output."""

    name: str
    returncode: int
    stdout: str
    stderr: str
    timed_out: bool = False
    """it did not exit in time and was killed"""

    def json(self) -> Any:
        """The JSON a ``--json`` command printed (a :class:`LaunchError` with its exit code and stderr
        if it printed none: killed after a hang, or crashed)."""
        try:
            return json.loads(self.stdout)
        except json.JSONDecodeError:
            raise LaunchError(
                f"{self.name}: exit code {self.returncode}, no JSON on stdout ({self.stdout[-300:]!r}); "
                f"stderr ends: {self.stderr[-1500:]}"
            ) from None


class Child(subprocess.Popen):
    """One ``axisflow`` command started by a :class:`Launcher` (a :class:`subprocess.Popen`)."""

    name: str
    command: str
    """what it runs, as a person would type it (``axisflow record -o …``)"""
    out_path: Path
    err_path: Path
    ready_fd: int | None

    def stdout_text(self) -> str:
        return self.out_path.read_text(errors="replace")

    def stderr_text(self) -> str:
        return self.err_path.read_text(errors="replace")


COMMAND_LINE = "axisflow.cli:main"
"""the entry point a child runs unless told otherwise: the ``axisflow`` command line"""


def _command(entry: str, fsize_limit_bytes: int | None) -> list[str]:
    """``python -c`` running ``entry`` (``module:function``; its arguments follow in ``sys.argv``)."""
    module, _, function = entry.partition(":")
    if not module or not function.isidentifier():
        raise LaunchError(f"entry point {entry!r} is not of the form module:function")
    # the command line follows the lifeline itself; another entry point is made to here
    prelude = (
        ""
        if entry == COMMAND_LINE
        else "from axisflow.deploy.processes import follow_launcher; follow_launcher(); "
    )
    if fsize_limit_bytes is not None:
        # a disk that fills up: Python ignores SIGXFSZ, so a write past the limit fails with EFBIG
        limit = int(fsize_limit_bytes)
        prelude += f"import resource; resource.setrlimit(resource.RLIMIT_FSIZE, ({limit}, {limit})); "
    return [
        sys.executable,
        "-c",
        f"import sys; {prelude}from {module} import {function}; sys.exit({function}())",
    ]


class Launcher:
    """Starts ``axisflow`` commands bound to this launcher's life (see the module docstring); use as a
    context manager: leaving stops every child still running.

    ``logs``: the folder for each child's ``<name>.out`` and ``<name>.err``; ``env``: variables added to
    this process's environment (``CI=1`` and ``RUST_LOG=error`` unless set); ``cwd``: the children's
    working folder."""

    def __init__(self, logs: Path, env: Mapping[str, str] | None = None, cwd: Path | None = None) -> None:
        self.logs = Path(logs)
        self.logs.mkdir(parents=True, exist_ok=True)
        self.cwd = cwd
        inherited = {k: v for k, v in os.environ.items() if k not in (LIFELINE_ENV, READY_ENV)}
        self._env = {"CI": "1", "RUST_LOG": "error", **inherited, **(env or {})}
        self._lifeline_read, self._lifeline_write = os.pipe()  # neither is inherited unless passed
        self.children: list[Child] = []
        """the children started and not yet reaped by :meth:`stop_running`"""
        self._started: dict[str, int] = {}

    def start(
        self,
        name: str,
        *args: str,
        ready: bool = False,
        fsize_limit_bytes: int | None = None,
        entry: str = COMMAND_LINE,
    ) -> Child:
        """``axisflow ARGS`` in the background. ``ready``: the command says when it is ready
        (:meth:`wait_ready`); ``fsize_limit_bytes``: RLIMIT_FSIZE of the process (a full disk);
        ``entry``: another ``module:function`` of axisflow to run with ARGS (a benchmark's publisher)."""
        if self._lifeline_write < 0:
            raise LaunchError(f"cannot start {name}: the launcher is closed")
        name = self._unique(name)
        out_path, err_path = self.logs / f"{name}.out", self.logs / f"{name}.err"
        env = {**self._env, LIFELINE_ENV: str(self._lifeline_read)}
        fds = [self._lifeline_read]
        ready_read = ready_write = None
        if ready:
            ready_read, ready_write = os.pipe()
            env[READY_ENV] = str(ready_write)
            fds.append(ready_write)
        try:
            with open(out_path, "w") as out, open(err_path, "w") as err:
                child = Child(
                    [*_command(entry, fsize_limit_bytes), *args],
                    stdout=out,
                    stderr=err,
                    env=env,
                    cwd=self.cwd,
                    pass_fds=fds,
                    # its own process group: a Ctrl-C in the terminal reaches the launcher, which
                    # stops its children in order
                    start_new_session=True,
                )
        except BaseException:
            for fd in (ready_read, ready_write):
                if fd is not None:
                    os.close(fd)
            raise
        finally:
            if ready_write is not None:
                os.close(ready_write)
        child.name, child.out_path, child.err_path, child.ready_fd = name, out_path, err_path, ready_read
        child.command = " ".join(["axisflow" if entry == COMMAND_LINE else entry, *args])
        self.children.append(child)
        return child

    def _unique(self, name: str) -> str:
        """``name``, or ``name-2``, ``name-3``, … for the second, third child of that name."""
        n = self._started[name] = self._started.get(name, 0) + 1
        return name if n == 1 else f"{name}-{n}"

    def wait_ready(self, child: Child, timeout_s: float) -> None:
        """Return once ``child`` said it is ready; a :class:`LaunchError` (with the end of its stderr)
        if it exits first or stays silent for ``timeout_s``."""
        if child.ready_fd is None:
            raise LaunchError(f"{child.name} was not started with ready=True")
        readable, _, _ = select.select([child.ready_fd], [], [], max(timeout_s, 0.0))
        said = os.read(child.ready_fd, 1) if readable else b""
        if said == _READY_BYTE:
            os.close(child.ready_fd)
            child.ready_fd = None
            return
        if readable:  # end of file: it exited without getting ready
            child.wait()
            raise LaunchError(
                f"{child.command} exited with code {child.returncode} before it was ready: "
                f"{last_line(child.stderr_text())}"
            )
        raise LaunchError(f"{child.command} was not ready within {timeout_s:g} s")

    def check_alive(self, child: Child) -> None:
        """A :class:`LaunchError` if ``child`` has exited (naming its code and last error line)."""
        if child.poll() is not None:
            raise LaunchError(
                f"{child.command} exited early with code {child.returncode}: {last_line(child.stderr_text())}"
            )

    def wait(self, child: Child, timeout_s: float = STOP_TIMEOUT_S) -> Exited:
        """Wait for ``child`` to exit; kill it after ``timeout_s`` (a hang is a failure, not a wait)."""
        timed_out = False
        try:
            child.wait(timeout_s)
        except subprocess.TimeoutExpired:
            timed_out = True
            child.kill()
            child.wait()
        if child.ready_fd is not None:
            os.close(child.ready_fd)
            child.ready_fd = None
        return Exited(child.name, child.returncode, child.stdout_text(), child.stderr_text(), timed_out)

    def stop(
        self, child: Child, timeout_s: float = STOP_TIMEOUT_S, sig: signal.Signals = signal.SIGINT
    ) -> Exited:
        """Send ``sig`` (SIGINT: a clean stop, as Ctrl-C) and :meth:`wait`."""
        if child.poll() is None:
            child.send_signal(sig)
        return self.wait(child, timeout_s)

    def stop_running(self, timeout_s: float = STOP_TIMEOUT_S) -> list[Exited]:
        """Stop every child still running — SIGINT to all (the last started first), then wait for
        each, killing one that hangs — and forget the finished ones. Returns how the stopped ones
        ended."""
        running = [c for c in reversed(self.children) if c.poll() is None]
        for child in running:
            child.send_signal(signal.SIGINT)
        stopped = [self.wait(child, timeout_s) for child in running]
        for child in self.children:
            if child.ready_fd is not None:
                os.close(child.ready_fd)
                child.ready_fd = None
        self.children.clear()
        return stopped

    def close(self, timeout_s: float = STOP_TIMEOUT_S) -> None:
        """Stop every child still running (:meth:`stop_running`), then cut the lifeline."""
        self.stop_running(timeout_s)
        for fd in (self._lifeline_read, self._lifeline_write):
            if fd >= 0:
                os.close(fd)
        self._lifeline_read = self._lifeline_write = -1

    def __enter__(self) -> Launcher:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()


def last_line(text: str) -> str:
    """The last non-blank line of a child's output (what its failure said), for a one-line message."""
    lines = [line for line in text.strip().splitlines() if line.strip()]
    return lines[-1] if lines else "(no output on stderr)"
