"""The recorder in-process over real Zenoh sessions: payloads that are not ROS 2 CDR keep their own
encoding, a failing disk is a RecordingError (not a traceback), an empty session says why."""

import os
import socket
import threading
from pathlib import Path

import pytest
from axisflow.acquisition import Recorder, RecorderConfig, RecordingError, ZenohOptions, open_session
from axisflow.acquisition.bus.readiness import wait_for_token
from axisflow.acquisition.wire.keys import recorder_token
from mcap.reader import make_reader

from axisflow.deploy.processes import wait_until


def _record_while(
    port: int, config: RecorderConfig, publish, expect: int = 0, stop_within_s: float = 30.0
) -> tuple[object, BaseException | None]:
    """Run a recorder on its own thread; once it is ready and a second session knows its subscriber
    (its token), call ``publish(session)`` there; stop it once it has written ``expect`` messages (or
    failed). The summary is None if it has not stopped ``stop_within_s`` after the stop."""
    stop = threading.Event()
    recorder = Recorder(config)
    out: dict[str, object] = {}

    def run(session) -> None:
        try:
            out["summary"] = recorder.run(session, stop)
        except BaseException as exc:  # re-raised in the test
            out["error"] = exc

    with (
        open_session(ZenohOptions.loopback(listen_port=port)) as rec_session,
        open_session(ZenohOptions.loopback(connect_port=port)) as pub_session,
    ):
        thread = threading.Thread(target=run, args=(rec_session,))
        thread.start()
        assert recorder.ready.wait(10.0)
        assert wait_for_token(pub_session, recorder_token(socket.gethostname(), os.getpid()), 10.0)
        publish(pub_session)
        assert wait_until(lambda: recorder.summary.messages >= expect or "error" in out, 10.0)
        stop.set()
        thread.join(timeout=stop_within_s)
    return out.get("summary"), out.get("error")


def test_payloads_that_are_not_cdr_keep_their_encoding(tmp_path, port):
    path = tmp_path / "mixed.mcap"

    def publish(session) -> None:
        session.put("axisflow/a0/note", "hello")
        session.put("axisflow/a0/config", '{"a": 1}', encoding="application/json")

    summary, error = _record_while(port, RecorderConfig(output=path), publish, expect=2)
    assert error is None
    assert summary.messages == 2
    with open(path, "rb") as fh:
        channels = {c.topic: c for c in make_reader(fh).get_summary().channels.values()}
    assert channels["/axisflow/a0/note"].message_encoding == "zenoh/bytes"
    assert channels["/axisflow/a0/config"].message_encoding == "json"
    assert all(c.schema_id == 0 for c in channels.values())


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
def test_a_full_disk_is_a_recording_error_naming_the_file(tmp_path, port):
    path = tmp_path / "full.mcap"
    os.symlink("/dev/full", path)

    def publish(session) -> None:
        for k in range(100):
            session.put(f"axisflow/a0/x{k % 3}", bytes(2000))

    config = RecorderConfig(output=path, overwrite=True, flush_interval_s=0.05)
    _summary, error = _record_while(port, config, publish, expect=100)
    assert isinstance(error, RecordingError)
    assert f"writing {path} failed: No space left on device" in str(error)


def test_an_empty_recording_says_that_nothing_matched(tmp_path, port):
    summary, error = _record_while(port, RecorderConfig(output=tmp_path / "e.mcap"), lambda _s: None)
    assert error is None
    assert "no message matched axisflow/**: is a publisher running" in summary.format()


@pytest.mark.parametrize("keys", ["axisflow/**", "axisflow/a0/state"], ids=["waker", "one-key"])
def test_an_idle_recorder_flushes_on_time_stops_at_once_and_records_no_wake_up(tmp_path, port, keys):
    """While nothing comes, the loop waits in the channel's receive; the waker's samples (on a key of
    the expression) still let it flush and stop, and never reach the file. A subscription on one key
    has no such key: it polls."""
    path = tmp_path / "idle.mcap"

    def publish(session) -> None:
        session.put("axisflow/a0/state", b"one")
        # the message reaches the disk only through a flush after it, which the idle loop does when
        # something wakes its receive
        assert wait_until(lambda: b"one" in path.read_bytes(), 10.0)

    config = RecorderConfig(keys=keys, output=path, flush_interval_s=0.05)
    summary, error = _record_while(port, config, publish, expect=1, stop_within_s=10.0)
    assert error is None and summary is not None  # it stopped within 10 s
    with open(path, "rb") as fh:
        reader = make_reader(fh)
        topics = [c.topic for c in reader.get_summary().channels.values()]
        assert [m.data for _s, _c, m in reader.iter_messages()] == [b"one"]
    assert topics == ["/axisflow/a0/state"] and list(summary.topics) == topics
