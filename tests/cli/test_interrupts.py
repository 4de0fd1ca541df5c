"""SIGTERM and SIGINT mid-work to the commands that write files (real processes): each ends within
2 s with the signal's exit code and one line, writes nothing, and leaves no temporary file behind.

"Mid-work" is a fact the test waits for: the writer's temporary file has appeared (view, recover), or
the process has its log open (identify, which writes only at the end). The work left after that fact
takes seconds, so the signal always lands in it.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest
from axisflow.acquisition.logs.synthetic_log import SyntheticLogSpec, write_synthetic_log

pytestmark = pytest.mark.slow  # a module fixture of several seconds: the whole module is in the slow tier

CLI = [sys.executable, "-c", "import sys; from axisflow.cli import main; sys.exit(main())"]
ENV = {**os.environ, "CI": "1", "RUST_LOG": "error"}
SIGNALS = [signal.SIGTERM, signal.SIGINT]
EXIT_CODES = {signal.SIGTERM: 143, signal.SIGINT: 130}
STOPPED = {signal.SIGTERM: "stopped by SIGTERM", signal.SIGINT: "interrupted"}
END_WITHIN_S = 2.0


@pytest.fixture(scope="module")
def logs(tmp_path_factory) -> tuple[Path, Path]:
    """Two distinct 5-minute recordings of one axis (600 000 messages, 44 MB each)."""
    folder = tmp_path_factory.mktemp("logs")
    first = write_synthetic_log(folder / "a.mcap", SyntheticLogSpec(duration_s=300.0)).path
    shutil.copy(first, folder / "b.mcap")
    return first, folder / "b.mcap"


def _terminal_sigint() -> None:
    """In the child before it runs: SIGINT as a program started from a terminal has it. A test run
    started in the background of a script ignores SIGINT, and a child inherits that (Python then
    installs no KeyboardInterrupt for it): the SIGINT cases would measure how the tests were started."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _start(*args: str | Path, cwd: Path) -> subprocess.Popen:
    return subprocess.Popen(
        [*CLI, *map(str, args)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=ENV,
        cwd=cwd,
        preexec_fn=_terminal_sigint,
    )


def _wait_for(fact: Callable[[], bool], proc: subprocess.Popen, what: str, timeout: float = 60.0) -> None:
    """Poll ``fact`` until it holds; fail if the process ends first or the deadline passes."""
    deadline = time.monotonic() + timeout
    while not fact():
        if proc.poll() is not None:
            pytest.fail(f"the process ended (exit {proc.returncode}) before {what}: {proc.stderr.read()}")
        if time.monotonic() > deadline:
            proc.kill()
            pytest.fail(f"no sign within {timeout} s that {what}")
        time.sleep(0.002)


def _part_in(folder: Path) -> Callable[[], bool]:
    """True once a temporary file of an atomic writer is in ``folder`` (the work is writing)."""
    return lambda: any(p.name.endswith(".part") for p in folder.iterdir())


def _reading(proc: subprocess.Popen, paths: tuple[Path, ...]) -> Callable[[], bool]:
    """True while the process has one of ``paths`` open (the work is reading)."""
    wanted = {str(p) for p in paths}
    fds = Path(f"/proc/{proc.pid}/fd")

    def fact() -> bool:
        try:
            return any(os.readlink(fd) in wanted for fd in fds.iterdir())
        except (FileNotFoundError, ProcessLookupError):
            return False

    return fact


def _stop(proc: subprocess.Popen, sig: signal.Signals) -> tuple[int, str]:
    """Send ``sig``; the process must end within :data:`END_WITHIN_S`. Returns its exit code and
    stderr."""
    proc.send_signal(sig)
    sent = time.monotonic()
    try:
        proc.wait(END_WITHIN_S)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
        pytest.fail(f"still running {END_WITHIN_S} s after {sig.name}")
    took = time.monotonic() - sent
    assert took <= END_WITHIN_S
    return proc.returncode, proc.stderr.read()


def _check_stopped(code: int, err: str, sig: signal.Signals, command: str) -> None:
    """The signal stopped the command: its exit code, its last line, no traceback."""
    assert "Traceback" not in err, err
    assert code == EXIT_CODES[sig], err
    assert err.strip().splitlines()[-1] == f"axisflow {command}: {STOPPED[sig]}", err


@pytest.mark.parametrize("sig", SIGNALS, ids=lambda s: s.name)
def test_view(sig, logs, tmp_path):
    out = tmp_path / "view.rrd"
    proc = _start("view", *logs, "-o", out, cwd=tmp_path)
    _wait_for(_part_in(tmp_path), proc, "the view started writing")
    _check_stopped(*_stop(proc, sig), sig, "view")
    assert os.listdir(tmp_path) == []  # no .rrd, no temporary file


@pytest.mark.parametrize("sig", SIGNALS, ids=lambda s: s.name)
def test_recover(sig, logs, tmp_path):
    out = tmp_path / "fixed.mcap"
    proc = _start("recover", logs[0], "-o", out, cwd=tmp_path)
    _wait_for(_part_in(tmp_path), proc, "recover started writing")
    _check_stopped(*_stop(proc, sig), sig, "recover")
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("sig", SIGNALS, ids=lambda s: s.name)
def test_identify(sig, logs, tmp_path):
    out = tmp_path / "refit"
    proc = _start("identify", *logs, "--out", out, "--json", cwd=tmp_path)
    _wait_for(_reading(proc, logs), proc, "identify started reading its logs")
    _check_stopped(*_stop(proc, sig), sig, "identify")
    assert os.listdir(tmp_path) == []  # the output folder is made only to write the refit into
