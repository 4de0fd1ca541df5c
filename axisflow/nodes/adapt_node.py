"""The adaptive node: an axis's friction (and M_eq) refit from its live samples while it works, every
accepted estimate published for the planner (docs/adaptation.md).

The node subscribes to ``<prefix>/<axis>/state`` once the routes from the bridge are proven
(:class:`~axisflow.acquisition.bus.readiness.JoinedSubscriber`: it misses nothing from then on), takes
the samples off the Zenoh channel in batches on its own thread, decodes each batch at once (fixed
offsets of the JointState layout, :class:`~axisflow.acquisition.logs.joint_state_layout.JointStateLayout`)
and hands the motor joint's columns to an :class:`~axisflow.identification.online.Adapter` (a ring of
numpy arrays). Whenever a step is due (every ``every_s`` of drive time), the adapter fits the newest
window and decides; the node publishes the decision — accepted or not, with the reason — as a
:class:`~axisflow.acquisition.wire.params_estimate.ParamsEstimate` on ``<prefix>/<axis>/params``
(command priority, never dropped), and version 0, its starting set, when it starts. A fit takes tens of
milliseconds; meanwhile the channel holds the samples (at ``--speed 0`` a full channel holds the bridge
back, as any consumer does).

The node stops when ``stop`` is set (SIGINT/SIGTERM) or after ``duration_s`` of wall time.
"""

from __future__ import annotations

import threading
import time
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import zenoh

from ..acquisition.bus.publisher import SequencedPublisher, Traffic
from ..acquisition.bus.readiness import JoinedSubscriber
from ..acquisition.errors import WireError
from ..acquisition.logs.joint_state_layout import JointStateLayout
from ..acquisition.wire.keys import AxisKeys
from ..acquisition.wire.messages import MOTOR_JOINT, JointState
from ..acquisition.wire.params_estimate import PARAMS_ESTIMATE_TYPE, ParamsEstimate
from ..identification.online import Adapter

QUEUE_CAPACITY = 65_536
"""samples the Zenoh channel holds (65 s of a 1 kHz axis; when full it holds the publisher back)"""
JOIN_TIMEOUT_S = 30.0
"""how long the publishers on the state key may take to answer the join's hellos [s] (a bridge on a
loaded machine answers late; the node has nothing to do before it has joined)"""
_BATCH = 2048
"""samples taken off the channel before they are decoded and handed on"""
_IDLE_S = 0.002


@dataclass
class AdaptReport:
    """What a node run did."""

    axis: str
    samples: int = 0
    undecodable: int = 0
    decisions: Counter[str] = field(default_factory=Counter)
    records: list[ParamsEstimate] = field(default_factory=list)
    """every record published (version 0 first)"""
    wall_time_s: float = 0.0
    delay: str = ""
    """the torque/position offset the fits used, in words"""

    @property
    def version(self) -> int:
        return self.records[-1].version if self.records else 0

    def summary(self) -> str:
        steps = sum(self.decisions.values())
        counts = ", ".join(f"{n} {d}" for d, n in sorted(self.decisions.items())) or "none"
        text = (
            f"adapt {self.axis}: {self.samples} samples, {steps} windows fitted ({counts}); version "
            f"{self.version} in force"
        )
        if self.delay:
            text += f"; torque delay {self.delay}"
        if self.undecodable:
            text += f"; {self.undecodable} undecodable samples"
        return text

    def to_dict(self) -> dict[str, object]:
        return {
            "axis": self.axis,
            "samples": self.samples,
            "undecodable": self.undecodable,
            "decisions": dict(self.decisions),
            "version": self.version,
            "wall_time_s": self.wall_time_s,
            "torque_delay": self.delay,
        }


class AdaptNode:
    """The node for one axis on one session (see the module docstring)."""

    def __init__(
        self,
        session: zenoh.Session,
        keys: AxisKeys,
        adapter: Adapter,
        progress: Callable[[ParamsEstimate], None] | None = None,
        stop: threading.Event | None = None,
    ) -> None:
        self.keys, self.adapter = keys, adapter
        self._session = session
        self._say = progress or (lambda _record: None)
        self._stop = stop or threading.Event()
        self.report = AdaptReport(keys.axis)
        self.ready = threading.Event()
        """set once the subscriber has joined and version 0 is published"""
        self._layout: tuple[int, JointStateLayout, np.ndarray, int] | None = None

    def run(self, duration_s: float | None = None, on_ready: Callable[[], None] | None = None) -> AdaptReport:
        """Adapt until stopped (or ``duration_s`` of wall time after joining)."""
        t0 = time.monotonic()

        def handler() -> zenoh.handlers.FifoChannel:
            return zenoh.handlers.FifoChannel(QUEUE_CAPACITY)

        publisher = SequencedPublisher(self._session, self.keys.params, PARAMS_ESTIMATE_TYPE, Traffic.COMMAND)
        try:
            with JoinedSubscriber(
                self._session, self.keys.state, handler, JOIN_TIMEOUT_S, stop=self._stop
            ) as joined:
                sub = joined.subscriber
                if sub is None:  # stopped while joining
                    return self.report
                self._publish(publisher, self.adapter.initial_record(time.time_ns()))
                self.ready.set()
                if on_ready is not None:
                    on_ready()
                deadline = None if duration_s is None else time.monotonic() + duration_s
                while not self._stop.is_set() and (deadline is None or time.monotonic() < deadline):
                    payloads: list[bytes] = []
                    while len(payloads) < _BATCH and (sample := sub.try_recv()) is not None:
                        payloads.append(sample.payload.to_bytes())
                    if payloads:
                        self._take(payloads)
                    if self.adapter.due():
                        self._publish(publisher, self.adapter.step())
                    elif not payloads:
                        time.sleep(_IDLE_S)
        finally:
            publisher.undeclare()
            self.report.wall_time_s = time.monotonic() - t0
            delay = self.adapter.delay
            self.report.delay = (
                f"{self.adapter.delay_s * 1e3:.3f} ms (fixed)"
                if self.adapter.settings.torque_delay_s is not None
                else (delay.describe() if delay is not None else "")
            )
        return self.report

    def _publish(self, publisher: SequencedPublisher, record: ParamsEstimate) -> None:
        publisher.put(record.encode(), record.stamp_ns)
        self.report.records.append(record)
        if record.decision != "initial":
            self.report.decisions[record.decision.value] += 1
        self._say(record)

    def _take(self, payloads: list[bytes]) -> None:
        try:
            stamp, angle, torque = self._decode(payloads)
        except WireError:
            stamp, angle, torque = self._decode_each(payloads)
        self.report.samples += stamp.size
        self.adapter.add(stamp, angle, torque)

    def _decode(self, payloads: Sequence[bytes]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The motor joint's stamps, angles and torques of payloads of one layout, at fixed offsets (a
        :class:`WireError` when they are not all of it: then :meth:`_decode_each`)."""
        size = len(payloads[0])
        if any(len(p) != size for p in payloads):
            raise WireError("payloads of several sizes")
        if self._layout is None or self._layout[0] != size:
            layout = JointStateLayout.of(payloads[0])
            if layout is None or MOTOR_JOINT not in layout.joint_names or layout.array_offsets[2] is None:
                raise WireError("no fixed layout with a motor joint")
            reference = np.frombuffer(payloads[0], dtype=np.uint8)
            self._layout = (size, layout, reference, layout.joint_names.index(MOTOR_JOINT))
        _size, layout, reference, motor = self._layout
        rows = np.frombuffer(b"".join(payloads), dtype=np.uint8).reshape(len(payloads), size)
        if not layout.matches(rows, reference):
            raise WireError("payloads of another layout")
        decoded = layout.decode(rows)
        return decoded.stamp_ns, decoded.position[:, motor].copy(), decoded.effort[:, motor].copy()

    def _decode_each(self, payloads: Sequence[bytes]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """One by one: the payloads that decode and carry a motor joint (the rest counted)."""
        stamp, angle, torque = [], [], []
        for payload in payloads:
            try:
                message = JointState.decode(payload)
                j = message.name.index(MOTOR_JOINT)
                stamp.append(message.stamp_ns)
                angle.append(message.position[j])
                torque.append(message.effort[j])
            except (WireError, ValueError, IndexError):
                self.report.undecodable += 1
        return np.array(stamp, dtype=np.int64), np.array(angle), np.array(torque)
