"""axisflow's launcher with real processes: a child says when it is ready, one that fails is named
with its error, and the children of a launcher that is SIGKILLed end on their own (the demo's
bridge and recorder)."""

import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from axisflow.acquisition import is_complete

from axisflow.deploy.processes import Launcher, LaunchError, free_port, wait_until


def test_a_child_says_when_it_is_ready_and_stops_cleanly_on_sigint(tmp_path):
    out = tmp_path / "r.mcap"
    with Launcher(tmp_path / "logs") as launcher:
        rec = launcher.start("recorder", "record", "-o", str(out), "--listen", f"tcp/127.0.0.1:{free_port()}",
                             ready=True)  # fmt: skip
        launcher.wait_ready(rec, 30.0)
        assert out.exists()  # ready: its file is there and its subscriber has joined
        end = launcher.stop(rec)
    assert (end.returncode, end.timed_out) == (0, False)
    assert "recorded 0 messages" in end.stdout
    assert is_complete(out)
    assert (tmp_path / "logs" / "recorder.out").read_text() == end.stdout


def test_a_child_that_fails_before_it_is_ready_is_named_with_its_error(tmp_path):
    with Launcher(tmp_path / "logs") as launcher:
        rec = launcher.start("recorder", "record", "-o", str(tmp_path / "x.txt"), ready=True)
        with pytest.raises(LaunchError) as failed:
            launcher.wait_ready(rec, 30.0)
    message = str(failed.value)
    assert "axisflow record" in message and "exited with code 2" in message
    assert "must end in .mcap" in message


def test_the_same_name_twice_gets_two_logs(tmp_path):
    with Launcher(tmp_path / "logs") as launcher:
        first = launcher.wait(launcher.start("params", "params"))
        second = launcher.wait(launcher.start("params", "params"))
    assert (first.name, second.name) == ("params", "params-2")
    assert first.returncode == second.returncode == 0 and first.stdout == second.stdout != ""


def _children(pid: int) -> set[int]:
    """The child processes of ``pid`` (Linux /proc)."""
    found: set[int] = set()
    for task in Path(f"/proc/{pid}/task").iterdir():
        try:
            found |= {int(c) for c in (task / "children").read_text().split()}
        except FileNotFoundError:  # a thread that ended since the listing: it has no children left
            continue
    return found


def _gone(pid: int) -> bool:
    """The process has exited (it may linger as a zombie until someone reaps it)."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except FileNotFoundError:
        return True
    return state in ("Z", "X")


def _command_line(pid: int) -> list[str]:
    return Path(f"/proc/{pid}/cmdline").read_bytes().decode().split("\0")


@pytest.mark.slow
@pytest.mark.skipif(not Path("/proc/self/task").exists(), reason="reads the Linux process table")
def test_the_demos_children_end_when_the_demo_is_sigkilled(cli, tmp_path):
    """`axisflow demo` SIGKILLed while its bridge and recorder run: both follow it within seconds (their
    lifeline closes; each stops itself as on SIGTERM), and the recording is complete."""
    out = tmp_path / "session"
    demo = cli.start("demo", "--waypoints", "2", "--out", str(out))
    recording = out / "excitation.mcap"
    assert wait_until(lambda: recording.exists() or demo.poll() is not None, 120.0)
    assert demo.poll() is None, cli.finish(demo)
    children = _children(demo.pid)
    commands = sorted(_command_line(pid)[3] for pid in children)  # python -c CODE <command> …
    assert commands == ["bridge", "record"], commands
    os.kill(demo.pid, signal.SIGKILL)
    demo.wait()
    assert wait_until(lambda: all(_gone(pid) for pid in children), 10.0), {
        pid: _command_line(pid) for pid in children if not _gone(pid)
    }
    assert wait_until(lambda: is_complete(recording), 5.0)  # the recorder stopped cleanly


_SIGNAL_INSIDE_WAIT = """
import os, signal, sys
from axisflow.deploy.processes import stop_on_signals

with stop_on_signals() as stop:
    # the signal lands while the main thread holds the event's lock, as it does inside stop.wait()
    with stop._cond:
        os.kill(os.getpid(), signal.SIGINT)
        for _ in range(1000):  # bytecodes: Python runs the handler here, the lock still held
            pass
    print("set" if stop.wait(5.0) else "not set", flush=True)
sys.exit(0)
"""


def test_a_stop_signal_that_lands_inside_the_events_own_wait_still_stops():
    # a handler that set the event itself would wait for the lock its own thread holds: a hang
    done = subprocess.run(
        [sys.executable, "-c", _SIGNAL_INSIDE_WAIT], capture_output=True, text=True, timeout=30
    )
    assert (done.returncode, done.stdout.strip(), done.stderr) == (0, "set", "")


def _thread_state(tid: int) -> str:
    """The scheduler state of a thread (R running, S sleeping, …)."""
    stat = Path(f"/proc/{tid}/stat").read_text()
    return stat[stat.rindex(")") + 2]


_SIGNAL_WHILE_BLOCKED_IN_ZENOH = """
import sys, threading, zenoh
from axisflow.acquisition import ZenohOptions, open_session
from axisflow.deploy.processes import stop_on_signals

with stop_on_signals() as stop, open_session(ZenohOptions.loopback()) as session:
    sub = session.declare_subscriber("wake/**", zenoh.handlers.FifoChannel(4))
    waker = session.declare_publisher("wake/up", allowed_destination=zenoh.Locality.SESSION_LOCAL)
    threading.Thread(target=lambda: stop.wait() and waker.put(b"stop"), daemon=True).start()
    print("blocked", flush=True)
    sample = sub.recv()  # native code, which lets Python run the signal handler while it waits
    print(sample.payload.to_bytes().decode(), flush=True)
    sub.undeclare()
    waker.undeclare()
sys.exit(0)
"""


def test_a_stop_signal_sets_the_event_while_the_main_thread_waits_in_a_zenoh_recv():
    # the recorder waits in recv() for its next sample and relies on this to stop at once
    pipes = {"stdout": subprocess.PIPE, "stderr": subprocess.PIPE, "text": True}
    child = subprocess.Popen([sys.executable, "-c", _SIGNAL_WHILE_BLOCKED_IN_ZENOH], **pipes)
    try:
        assert child.stdout.readline().strip() == "blocked"
        assert wait_until(lambda: _thread_state(child.pid) == "S", 10.0)  # its main thread waits in recv()
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=30)
    finally:
        child.kill()
    assert (child.returncode, out.strip(), err) == (0, "stop", "")
