"""Replaying a recording over Zenoh at its recorded pace.

Each message goes back out on key = its topic without the leading ``/``, with the recorded payload
bytes and encoding ``application/cdr;<schema name>``, at ``first_publish + (log_time − first_log)/speed``
(``speed`` 0: as fast as the consumers allow). The replay numbers its messages afresh per key
(a recorder of the replay counts gaps as usual); the attachment's source stamp is the recorded
``publish_time``.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass
from pathlib import Path

import zenoh

from .errors import AcquisitionError
from .keys import key_for_topic
from .publisher import SequencedPublisher, Traffic, wait_for_subscribers
from .recording import iter_recording


@dataclass(frozen=True)
class ReplayReport:
    messages: int
    topics: int
    wall_time_s: float
    recorded_span_s: float

    def format(self) -> str:
        return (
            f"replayed {self.messages} messages on {self.topics} keys: {self.recorded_span_s:.3f} s "
            f"of recording in {self.wall_time_s:.3f} s"
        )


def replay(
    session: zenoh.Session,
    path: str | Path,
    speed: float = 1.0,
    stop: threading.Event | None = None,
    wait_subscribers_s: float = 0.0,
) -> ReplayReport:
    """Publish the messages of ``path`` (complete or truncated) back over Zenoh."""
    if not speed >= 0.0:
        raise AcquisitionError(f"replay speed = {speed} must be >= 0 (0 = as fast as possible)")
    stop = stop or threading.Event()
    traffic = Traffic.BULK if speed == 0 else Traffic.TELEMETRY
    publishers: dict[str, SequencedPublisher] = {}
    n = 0
    first_log = last_log = 0
    t0 = time.monotonic_ns()
    waited = False
    try:
        for rec in iter_recording(path):
            if stop.is_set():
                break
            topic = rec.channel.topic
            pub = publishers.get(topic)
            if pub is None:
                type_name = rec.schema.name if rec.schema is not None else "unknown"
                pub = publishers[topic] = SequencedPublisher(
                    session, key_for_topic(topic), type_name, traffic
                )
            m = rec.message
            if n == 0:
                first_log = m.log_time
                if wait_subscribers_s > 0 and not waited:
                    wait_for_subscribers([pub], wait_subscribers_s)
                    waited = True
                t0 = time.monotonic_ns()
            if speed > 0:
                due = t0 + int((m.log_time - first_log) / speed)
                delay = due - time.monotonic_ns()
                if delay > 0:
                    time.sleep(delay * 1e-9)
            pub.put(m.data, m.publish_time)
            last_log = max(last_log, m.log_time)
            n += 1
    finally:
        for pub in publishers.values():
            pub.undeclare()
    return ReplayReport(n, len(publishers), (time.monotonic_ns() - t0) * 1e-9, (last_log - first_log) * 1e-9)
