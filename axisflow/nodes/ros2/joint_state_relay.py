"""The bridge's samples to ROS 2: ``<prefix>/<axis>/state`` → ``/axisflow/<axis>/joint_states``.

The payload on the Zenoh key is already a ROS 2 ``sensor_msgs/msg/JointState`` in CDR, the axis's two
joints and the drive's stamp in its header (:class:`~axisflow.acquisition.wire.messages.AxisSample`),
so the relay hands those bytes to rclpy's publisher as they are (a serialized message): no Python
message is built. It decodes each sample first, to drop anything that is not the axis's JointState
(a malformed payload would reach every ROS 2 subscriber's deserializer otherwise) and to read the
stamp that decimation needs. ``axisflow bench ros2`` measures the three ways (raw bytes after the
check, rclpy's ``deserialize_message``, a message built from the decoded sample); the raw bytes are
the cheapest.

Zenoh queues the samples in a FIFO channel (on its own thread, without Python's lock) and the relay's
thread takes them from there, one DDS publish per kept sample: a moment in which the relay cannot
run (the interpreter busy elsewhere, the process descheduled) fills the channel instead of holding
up Zenoh's reception, which would make the bridge drop samples. It joins the key as a
:class:`~axisflow.acquisition.bus.readiness.JoinedSubscriber`, so once it is entered no sample of a
running bridge is missed on the way; it counts the samples the attachments' sequence numbers say
were lost between the bridge and this node.

**Decimation** (``rate_hz``) keeps the first sample of each period 1/rate of drive time, periods
counted from the epoch: at 100 Hz the samples stamped …000, …010, … ms; at a rate that does not
divide 1 kHz the kept samples are a tick apart more or less, on average the rate.
"""

from __future__ import annotations

import threading
import time
from typing import Any

import zenoh

from ...acquisition.bus.readiness import JoinedSubscriber
from ...acquisition.errors import WireError
from ...acquisition.wire.attachment import unpack_attachment
from ...acquisition.wire.keys import AxisKeys
from ...acquisition.wire.messages import AxisSample
from ...acquisition.wire.sequence import SequenceTracker

NS_PER_S = 1_000_000_000
RELAY_BACKLOG = 10_000
"""samples the channel holds for a relay that cannot run (10 s at 1 kHz) before Zenoh waits"""


class Decimator:
    """Keeps the first sample of each period of drive time (every sample when ``rate_hz`` is None)."""

    def __init__(self, rate_hz: float | None) -> None:
        self.period_ns = None if rate_hz is None else round(NS_PER_S / rate_hz)
        self._last_period: int | None = None

    def keep(self, stamp_ns: int) -> bool:
        if self.period_ns is None:
            return True
        period = stamp_ns // self.period_ns
        if period == self._last_period:
            return False
        self._last_period = period
        return True


class JointStateRelay:
    """Relays one axis's samples to an rclpy publisher of ``sensor_msgs/msg/JointState`` (use as a
    context manager; entering waits until the subscriber has joined)."""

    def __init__(
        self,
        session: zenoh.Session,
        keys: AxisKeys,
        publisher: Any,
        rate_hz: float | None = None,
        stop: threading.Event | None = None,
    ) -> None:
        self.keys = keys
        self._publisher = publisher
        self._decimator = Decimator(rate_hz)
        channel = lambda: zenoh.handlers.FifoChannel(RELAY_BACKLOG)  # noqa: E731
        self._join = JoinedSubscriber(session, keys.state, channel, stop=stop)
        self._thread = threading.Thread(target=self._run, name=f"relay {keys.state}", daemon=True)
        self._sequences = SequenceTracker()
        self.received = 0
        """samples that arrived from Zenoh"""
        self.published = 0
        """JointState messages handed to the ROS 2 publisher"""
        self.malformed = 0
        """payloads that were not the axis's JointState (dropped)"""
        self.last_error = ""
        """why the last malformed payload was dropped"""
        self.last_arrival_s: float | None = None
        """monotonic time of the last sample's arrival"""
        self.last_stamp_ns: int | None = None
        """the drive stamp of the last sample"""

    @property
    def lost(self) -> int:
        """Samples the bridge sent that never arrived (gaps in its sequence numbers)."""
        return self._sequences.missed

    def _run(self) -> None:
        subscriber = self._join.subscriber
        if subscriber is None:  # stopped while joining
            return
        channel = subscriber.handler  # not the subscriber: its undeclaration must not wait for us
        try:
            while True:
                self._on_sample(channel.recv())
        except zenoh.ZError:  # undeclared: the channel is empty and closed
            return

    def _on_sample(self, sample: zenoh.Sample) -> None:
        data = sample.payload.to_bytes()
        self.received += 1
        self.last_arrival_s = time.monotonic()
        attachment = sample.attachment
        parsed = unpack_attachment(attachment.to_bytes()) if attachment is not None else None
        if parsed is not None:
            self._sequences.add(parsed[2], parsed[0])
        try:
            decoded = AxisSample.decode(data)
        except WireError as exc:
            self.malformed += 1
            self.last_error = str(exc)
            return
        if decoded.axis != self.keys.axis:
            self.malformed += 1
            self.last_error = f"a sample of axis {decoded.axis!r} on the key of axis {self.keys.axis!r}"
            return
        self.last_stamp_ns = decoded.stamp_ns
        if self._decimator.keep(decoded.stamp_ns):
            self._publisher.publish(data)
            self.published += 1

    def counts(self) -> tuple[tuple[str, str], ...]:
        """The counts as diagnostic key–value pairs."""
        pairs = [
            ("samples received", str(self.received)),
            ("samples published", str(self.published)),
            ("samples lost on Zenoh", str(self.lost)),
            ("samples malformed", str(self.malformed)),
        ]
        if self.last_error:
            pairs.append(("last malformed sample", self.last_error))
        return tuple(pairs)

    def __enter__(self) -> JointStateRelay:
        self._join.__enter__()
        self._thread.start()
        return self

    def __exit__(self, *_exc: object) -> None:
        self._join.__exit__()
        self._thread.join()
