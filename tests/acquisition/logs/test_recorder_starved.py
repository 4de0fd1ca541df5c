"""A recorder starved of CPU (stopped outright, SIGSTOP) while a fast publisher floods it and ends: its
memory stays within its configured bounds, and every message sent is either in the file, counted as
dropped by the recorder, or counted as missed — in its summary and in the file's metadata. The
starvation lasts until the publisher has put its last message, so what Zenoh dropped on the
publisher's side while the recorder could not take it may include the flood's tail, which no gap in
the sequence numbers shows: the publisher's last numbers, carried by its receipt query, count it."""

import json
import os
import signal

import pytest
from axisflow.acquisition.logs.recording_writer import LOSS_METADATA
from axisflow.benchmarks.toolkit import synthetic_publisher
from axisflow.benchmarks.toolkit.proc_stats import status_kb
from mcap.reader import make_reader

from axisflow.deploy.processes import wait_until

AXES, SECONDS = 32, 8.0
BACKLOG_MB = 8
QUEUE = 4096


@pytest.mark.slow
def test_a_starved_recorder_stays_bounded_and_accounts_for_every_message(cli, tmp_path):
    port = cli.free_port()
    out = tmp_path / "starved.mcap"
    rec = cli.start(
        "record", "-o", str(out), "--listen", f"tcp/127.0.0.1:{port}", "--backlog-mb", str(BACKLOG_MB),
        "--queue", str(QUEUE), "--json", ready=True,
    )  # fmt: skip
    cli.wait_ready(rec)
    rss_before_mb = status_kb(rec.pid, "VmRSS") / 1024
    args = synthetic_publisher.arguments(f"tcp/127.0.0.1:{port}", AXES, SECONDS)
    pub = cli.launcher.start("publisher", *args, entry=synthetic_publisher.ENTRY, ready=True)
    # the flood is being written; the starvation then takes most of it, far more than the socket
    # buffers and Zenoh's queues hold, whatever the speed of the machine
    assert wait_until(lambda: cli.on_disk(out) > AXES * 100, 60.0)
    os.kill(rec.pid, signal.SIGSTOP)
    try:
        cli.wait_ready(pub, 60.0)  # it has put its last message: the starvation spans the flood's end
    finally:
        os.kill(rec.pid, signal.SIGCONT)
    published = cli.finish_exited(pub, 120.0)
    assert published.returncode == 0, published.stderr
    sent = json.loads(published.stdout.strip().splitlines()[-1])
    assert sent["confirmed"] == 1  # the recorder answered the receipt query that carried the last numbers
    peak_mb = status_kb(rec.pid, "VmHWM") / 1024
    stopped = cli.launcher.stop(rec, 60.0)  # SIGINT: the recorder finishes its file
    rec_err = stopped.stderr
    summary = json.loads(stopped.stdout)
    total = sent["ticks"] * sent["axes"]
    assert summary["messages"] + summary["dropped"] + summary["missed"] == total, (summary, rec_err)
    publishers = [p for t in summary["topics"].values() for p in t["publishers"]]
    assert len(publishers) == AXES and summary["untold_publishers"] == 0
    assert all(p["said_last_sequence"] == sent["ticks"] for p in publishers)
    assert summary["missed"] > 0  # the starvation did cost messages: the test exercised something
    # the backlog and the receive channel (~0.5 kB a sample), over what the recorder held before
    assert peak_mb - rss_before_mb < BACKLOG_MB + QUEUE * 0.5 / 1024 + 64, (rss_before_mb, peak_mb)
    with open(out, "rb") as fh:
        reader = make_reader(fh)
        loss = next(m for m in reader.iter_metadata() if m.name == LOSS_METADATA).metadata
        assert reader.get_summary().statistics.message_count == summary["messages"]
    assert int(loss["dropped_messages"]) == summary["dropped"]
    assert sum(int(v) for k, v in loss.items() if k.startswith("missed ")) == summary["missed"]
