"""A live view: the axes' keys received over Zenoh, streamed to rerun in small batches.

A subscriber on ``--keys`` (default ``axisflow/**``) fills a Zenoh FIFO channel; this module's loop,
on the caller's thread (never in a Zenoh callback), drains it and sorts each sample by its key
``<prefix>/<axis>/<kind>``:

* ``state``, ``setpoint`` — JointState payloads, decoded in bulk per batch (:func:`.samples.decode_payloads`);
* ``event`` — :class:`~axisflow.acquisition.MoveStatus`; ``plan`` — :class:`~axisflow.acquisition.PlanRecord`;
* ``params`` — an adaptive node's :class:`~axisflow.acquisition.wire.params_estimate.ParamsEstimate`
  (its axis's column gets the views of the adapted parameters when the first one comes);
* anything else (moves, liveliness, other keys) is counted and left alone.

Every :data:`BATCH_INTERVAL_S` the batches go to each axis's :class:`.scene.AxisScene` (the same
scene as a log view, so both look alike) with ``send_columns``; each move's E% is logged as soon as
its plan and its measured samples are in (:class:`.moves.MoveLedger`). A new axis adds its column to the
layout (the blueprint is sent again). Per key and publisher, gaps in the attachment's sequence
numbers count the messages lost on the way; the latency is measured from each sample's header stamp
(drive time) to the moment its batch was handed to rerun.

The subscriber joins first (its routes proven: :mod:`~axisflow.acquisition.bus.readiness`). The loop
stops when ``stop`` is set (SIGINT/SIGTERM through :func:`axisflow.deploy.processes.stop_on_signals`) or after
``duration_s``, after one more hello and draining what the channel holds; the subscriber is undeclared
before the caller closes the session.
"""

from __future__ import annotations

import threading
import time
from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, TypeVar

import numpy as np
import zenoh

from ..acquisition.bus.readiness import JoinedSubscriber
from ..acquisition.bus.session import check_key_expression
from ..acquisition.errors import WireError
from ..acquisition.histogram import DurationHistogram, DurationStats
from ..acquisition.logs.recorded_axes import axis_label
from ..acquisition.wire.attachment import unpack_attachment
from ..acquisition.wire.move_status import MoveStatus
from ..acquisition.wire.params_estimate import ParamsEstimate
from ..acquisition.wire.plan_record import PlanRecord
from ..acquisition.wire.sequence import SequenceTracker
from ..model import AxisParams
from .blueprint import view_blueprint
from .entities import AxisEntities
from .errors import VizError
from .outputs import RerunOutput
from .samples import AxisSamples, decode_payloads
from .scene import AxisScene

BATCH_INTERVAL_S = 0.025
"""how often the received samples go to rerun [s]: the most a sample waits in this process"""
DEFAULT_QUEUE_CAPACITY = 65_536
"""samples the Zenoh FIFO channel holds (when full it applies back-pressure, it does not drop)"""
STALE_STAMP_NS = 10_000_000_000
"""a stamp further than this from the wall clock is not live (e.g. a replay): no latency for it"""
_DRAIN_BATCH = 512
_IDLE_SLEEP_S = 0.002
_KINDS = ("state", "setpoint", "event", "plan", "params")
_Record = TypeVar("_Record", MoveStatus, PlanRecord, ParamsEstimate)


@dataclass
class KeyCount:
    """Messages of one key: received, lost on the way (sequence gaps) and undecodable."""

    received: int = 0
    undecodable: int = 0
    sequences: SequenceTracker = field(default_factory=SequenceTracker)

    @property
    def missed(self) -> int:
        return self.sequences.missed

    def to_dict(self) -> dict[str, int]:
        return {"received": self.received, "missed": self.missed, "undecodable": self.undecodable}


@dataclass
class LiveReport:
    """What a live view received and how fast it passed it on."""

    keys: str
    wall_time_s: float = 0.0
    counts: dict[str, KeyCount] = field(default_factory=dict)
    ignored: int = 0
    """samples on keys that are not state, setpoint, event or plan"""
    latency: DurationStats | None = None
    """header stamp → handed to rerun, over the state and setpoint samples with live stamps"""
    stale_stamps: int = 0
    batches: int = 0

    @property
    def received(self) -> int:
        return sum(c.received for c in self.counts.values())

    @property
    def missed(self) -> int:
        return sum(c.missed for c in self.counts.values())

    def to_dict(self) -> dict[str, Any]:
        return {
            "keys": self.keys,
            "wall_time_s": self.wall_time_s,
            "received": self.received,
            "missed": self.missed,
            "ignored": self.ignored,
            "batches": self.batches,
            "per_key": {k: c.to_dict() for k, c in sorted(self.counts.items())},
            "latency": self.latency.to_dict() if self.latency and self.latency.count else None,
            "stale_stamps": self.stale_stamps,
        }

    def format(self) -> str:
        lines = [
            f"live view of {self.keys}: {self.received} messages in {self.wall_time_s:.1f} s, "
            f"missed {self.missed}, {self.batches} batches"
        ]
        for key, c in sorted(self.counts.items()):
            bad = f", undecodable {c.undecodable}" if c.undecodable else ""
            lines.append(f"  {key:<40} {c.received:>9} missed {c.missed}{bad}")
        if self.latency and self.latency.count:
            lines.append(
                f"  stamp→rerun latency: p50 {self.latency.p50_us / 1e3:.1f} ms, "
                f"p99 {self.latency.p99_us / 1e3:.1f} ms, max {self.latency.max_us / 1e3:.1f} ms"
            )
        elif self.stale_stamps:
            lines.append(f"  stamp→rerun latency: n/a (stamps not live: {self.stale_stamps} samples)")
        return "\n".join(lines)


def check_keys(keys: str) -> str:
    """``keys`` if it is a valid Zenoh key expression; else a ``KeyExprError`` naming it."""
    check_key_expression(keys)
    return keys


def route_of(key: str) -> tuple[str, str] | None:
    """(axis label, kind) of a key ``<prefix>/<axis>/<kind>``, or None for any other key."""
    parts = key.rsplit("/", 2)
    if len(parts) != 3 or parts[2] not in _KINDS or not parts[0] or not parts[1]:
        return None
    return axis_label(parts[0], parts[1]), parts[2]


class LiveView:
    """Streams the axes' keys to a :class:`RerunOutput` (see the module docstring)."""

    def __init__(
        self,
        out: RerunOutput,
        params: AxisParams,
        keys: str,
        batch_interval_s: float = BATCH_INTERVAL_S,
        queue_capacity: int = DEFAULT_QUEUE_CAPACITY,
    ) -> None:
        if not 0.0 < batch_interval_s <= 1.0:
            raise VizError(f"batch interval = {batch_interval_s} s must be in (0, 1] s")
        self.out, self.params = out, params
        self.keys = check_keys(keys)
        self.batch_interval_s = batch_interval_s
        self.queue_capacity = queue_capacity
        self.report = LiveReport(keys)
        self.ready = threading.Event()
        """set once the subscriber has joined: nothing published from then on is missed"""
        self._scenes: dict[str, AxisScene] = {}
        self._adapted: set[str] = set()
        """axes whose adaptive node has been heard (their column has its views)"""
        self._pending: dict[tuple[str, str, str], list[bytes]] = defaultdict(list)
        self._routes: dict[str, tuple[str, str] | None] = {}
        self._latency = DurationHistogram(limit_us=1_000_000)

    def run(
        self,
        session: zenoh.Session,
        stop: threading.Event,
        duration_s: float | None = None,
        on_ready: Callable[[], None] | None = None,
    ) -> LiveReport:
        """Receive and stream until ``stop`` is set or ``duration_s`` has passed (counted from the moment
        the subscriber has joined: :class:`~axisflow.acquisition.bus.readiness.JoinedSubscriber`);
        ``on_ready`` is called then."""
        t0 = time.monotonic()
        handler = lambda: zenoh.handlers.FifoChannel(self.queue_capacity)  # noqa: E731
        try:
            with JoinedSubscriber(session, self.keys, handler, stop=stop) as joined:
                sub = joined.subscriber
                if sub is None:  # stopped while joining
                    return self.report
                self.ready.set()
                if on_ready is not None:
                    on_ready()
                started = time.monotonic()
                deadline = None if duration_s is None else started + duration_s
                next_flush = started + self.batch_interval_s
                while True:
                    got = self._drain(sub)
                    now = time.monotonic()
                    if now >= next_flush:
                        self._flush()
                        next_flush = now + self.batch_interval_s
                    if stop.is_set() or (deadline is not None and now >= deadline):
                        # one hello, draining meanwhile; then what the channel holds of the time
                        # before it (at most its capacity: a fast publisher refills it as it drains)
                        joined.flush(while_waiting=lambda: self._drain(sub))
                        for _ in range(self.queue_capacity // _DRAIN_BATCH + 1):
                            if not self._drain(sub):
                                break
                        break
                    if not got:
                        time.sleep(_IDLE_SLEEP_S)
        finally:
            self._flush()
            for scene in self._scenes.values():
                scene.finish()
            self.report.wall_time_s = time.monotonic() - t0
            self.report.latency = self._latency.stats()
        return self.report

    def _drain(self, sub: zenoh.Subscriber) -> int:
        """Take up to a batch of samples off the channel; returns how many."""
        n = 0
        while n < _DRAIN_BATCH:
            sample = sub.try_recv()
            if sample is None:
                break
            self._take(sample)
            n += 1
        return n

    def _take(self, sample: zenoh.Sample) -> None:
        key = str(sample.key_expr)
        if key not in self._routes:
            self._routes[key] = route_of(key)
        route = self._routes[key]
        if route is None:
            self.report.ignored += 1
            return
        count = self.report.counts.get(key)
        if count is None:
            count = self.report.counts[key] = KeyCount()
        count.received += 1
        att = sample.attachment
        parsed = unpack_attachment(att.to_bytes()) if att is not None else None
        if parsed is not None:
            count.sequences.add(parsed[2], parsed[0])
        self._pending[(route[0], route[1], key)].append(sample.payload.to_bytes())

    def _scene(self, label: str) -> AxisScene:
        scene = self._scenes.get(label)
        if scene is None:
            scene = self._scenes[label] = AxisScene(self.out.rec, AxisEntities(label), self.params)
            self.out.send_blueprint(view_blueprint(sorted(self._scenes), self._adapted))
        return scene

    def _adapted_axis(self, label: str) -> None:
        if label not in self._adapted:
            self._adapted.add(label)
            self.out.send_blueprint(view_blueprint(sorted(self._scenes), self._adapted))

    def _flush(self) -> None:
        """Hand every pending batch to its scene: records first, then setpoints, then samples."""
        if not self._pending:
            return
        pending, self._pending = self._pending, defaultdict(list)
        order = {"plan": 0, "event": 1, "params": 2, "setpoint": 3, "state": 4}
        for (label, kind, key), payloads in sorted(pending.items(), key=lambda kv: order[kv[0][1]]):
            scene = self._scene(label)
            if kind in ("state", "setpoint"):
                samples = self._decode_samples(key, payloads)
                if samples is None:
                    continue
                (scene.add_state if kind == "state" else scene.add_setpoint)(samples)
                self._measure_latency(samples.stamp_ns)
            elif kind == "event":
                scene.add_statuses(self._decode_each(key, payloads, MoveStatus.decode))
            elif kind == "params":
                self._adapted_axis(label)
                scene.add_params(self._decode_each(key, payloads, ParamsEstimate.decode))
            else:
                scene.add_plans(self._decode_each(key, payloads, PlanRecord.decode))
        self.report.batches += 1

    def _decode_samples(self, key: str, payloads: list[bytes]) -> AxisSamples | None:
        try:
            return decode_payloads(payloads, key)
        except (WireError, VizError):  # a bad payload: keep the others
            good = []
            for payload in payloads:
                try:
                    decode_payloads([payload], key)
                except (WireError, VizError):
                    self.report.counts[key].undecodable += 1
                else:
                    good.append(payload)
            return decode_payloads(good, key) if good else None

    def _decode_each(
        self, key: str, payloads: list[bytes], decode: Callable[[bytes], _Record]
    ) -> list[_Record]:
        out = []
        for payload in payloads:
            try:
                out.append(decode(payload))
            except (WireError, VizError):
                self.report.counts[key].undecodable += 1
        return out

    def _measure_latency(self, stamp_ns: np.ndarray) -> None:
        delays = time.time_ns() - stamp_ns
        live = np.abs(delays) <= STALE_STAMP_NS
        self.report.stale_stamps += int(len(delays) - np.count_nonzero(live))
        add = self._latency.add_ns
        for d in delays[live].tolist():
            add(d)
