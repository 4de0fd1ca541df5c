"""The recorder counts what no gap in the sequence numbers shows, from the publishers' own numbers:
the tail of one that closed (its receipt query says its last number), of one undeclared without
waiting for a receipt (it says its number as it goes), of one still running when the recorder stops
(its answer to the stop's hello), and the head of one that was running when the recorder joined (its
answer to the join's last hello). In-process, over real Zenoh sessions; the
messages Zenoh drops on congestion are played by numbers a publisher consumes without sending."""

import os
import socket
import threading

from axisflow.acquisition import Recorder, RecorderConfig, ZenohOptions, open_session
from axisflow.acquisition.bus.publisher import SequencedPublisher, Traffic, confirm_delivered
from axisflow.acquisition.bus.readiness import wait_for_token
from axisflow.acquisition.logs.recording_writer import LOSS_METADATA
from axisflow.acquisition.wire.keys import recorder_token
from mcap.reader import make_reader

from axisflow.deploy.processes import wait_until


def _drop(publisher: SequencedPublisher, n: int) -> None:
    """What Zenoh does to ``n`` messages it drops on congestion: numbered, never delivered."""
    publisher.sequence += n


def test_the_publishers_numbers_count_the_heads_and_tails_no_gap_shows(tmp_path, port):
    path = tmp_path / "accounted.mcap"
    recorder, stop, out = Recorder(RecorderConfig(output=path)), threading.Event(), {}
    with (
        open_session(ZenohOptions.loopback(listen_port=port)) as rec_session,
        open_session(ZenohOptions.loopback(connect_port=port)) as pub_session,
    ):
        closing, running, early, ended = (
            SequencedPublisher(
                pub_session, f"axisflow/{axis}/state", "sensor_msgs/msg/JointState", Traffic.BULK
            )
            for axis in ("a0", "a1", "a2", "a3")
        )
        for _ in range(3):  # before the recorder: to nobody, owed to nobody
            early.put(b"before")
        thread = threading.Thread(target=lambda: out.update(summary=recorder.run(rec_session, stop)))
        thread.start()
        assert recorder.ready.wait(10.0)
        assert wait_for_token(pub_session, recorder_token(socket.gethostname(), os.getpid()), 10.0)
        _drop(early, 2)  # the two after the join
        for publisher in (closing, running, early, ended):
            for _ in range(5):
                publisher.put(b"sample")
        _drop(closing, 4)
        _drop(running, 3)
        _drop(ended, 1)
        assert confirm_delivered(pub_session, [closing], 10.0) == 1
        closing.undeclare()
        ended.undeclare()
        assert wait_until(lambda: recorder.summary.messages == 20, 10.0)
        stop.set()
        thread.join(30.0)
        running.undeclare()
        early.undeclare()
    summary = out["summary"]
    topics = summary.to_dict()["topics"]
    [a0], [a1], [a2], [a3] = (topics[f"/axisflow/a{n}/state"]["publishers"] for n in range(4))
    assert (a0["messages"], a0["tail"], a0["said_last_sequence"], a0["missed"]) == (5, 4, 9, 4)
    assert (a1["messages"], a1["tail"], a1["said_last_sequence"], a1["missed"]) == (5, 3, 8, 3)
    assert (a2["first_sequence"], a2["head"], a2["tail"], a2["missed"]) == (6, 2, 0, 2)
    assert (a3["messages"], a3["tail"], a3["said_last_sequence"], a3["missed"]) == (5, 1, 6, 1)
    assert (summary.messages, summary.missed, summary.untold, summary.dropped) == (20, 10, 0, 0)
    with open(path, "rb") as fh:
        loss = next(m for m in make_reader(fh).iter_metadata() if m.name == LOSS_METADATA).metadata
    assert {k: int(v) for k, v in loss.items() if k.startswith("missed ")} == {
        "missed /axisflow/a0/state": 4, "missed /axisflow/a1/state": 3, "missed /axisflow/a2/state": 2,
        "missed /axisflow/a3/state": 1,
    }  # fmt: skip
