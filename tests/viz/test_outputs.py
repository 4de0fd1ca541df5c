"""viz/outputs.py beyond what the view commands show: what a stop at a bad moment leaves on stderr."""

import subprocess
import sys

HALF_BUILT = """
import rerun as rr
{imports}
half_built = rr.RecordingStream.__new__(rr.RecordingStream)  # a signal landed before `inner` was set
del half_built


class Other:
    def __del__(self):
        raise AttributeError("inner")


other = Other()
del other
"""


def _stderr_of(imports: str) -> str:
    code = HALF_BUILT.format(imports=imports)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    return done.stderr


def test_a_half_built_rerun_stream_leaves_no_traceback_and_other_ones_still_show():
    assert "RecordingStream.__del__" in _stderr_of("")  # rerun's own behaviour, which the hook quiets
    stderr = _stderr_of("import axisflow.viz.outputs")
    assert "RecordingStream" not in stderr
    assert "Exception ignored in: <function Other.__del__" in stderr  # nothing else is swallowed


STOP_IN_DEL = """
import signal
import sys
import time
import rerun as rr
import axisflow.viz.outputs

# Ctrl-C as a terminal's program has it (a test run started in the background of a script ignores
# SIGINT, and its children inherit that)
signal.signal(signal.SIGINT, signal.default_int_handler)
signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
print(open("/proc/self/status").read(), file=sys.stderr)  # (what the process's signals were, if it fails)


def interrupted(**_kwargs):
    raise KeyboardInterrupt  # as a Ctrl-C landing in the stream's flush at its end


stream = rr.RecordingStream("axisflow_test")
stream._flush = interrupted
try:
    del stream
    time.sleep(10)
    print("not stopped")
except KeyboardInterrupt:
    print("stopped")
"""


def test_a_stop_that_lands_in_a_streams_end_is_not_lost():
    done = subprocess.run([sys.executable, "-c", STOP_IN_DEL], capture_output=True, text=True, timeout=60)
    assert done.stdout.strip() == "stopped" and "Exception ignored" not in done.stderr, done.stderr[-3000:]
