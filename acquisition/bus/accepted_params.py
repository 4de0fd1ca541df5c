"""The newest accepted parameter set of an axis, as an adaptive node publishes it.

A planner that follows an adaptive node (``axisflow planner --adapt``) subscribes to
``<prefix>/<axis>/params`` (joined: its routes proven, nothing published afterwards is missed) and, before
each plan, asks :meth:`AcceptedParams.newest` for an accepted
:class:`~axisflow.acquisition.wire.params_estimate.ParamsEstimate` newer than the version it plans with.
Rejected estimates (the node's reasons for keeping a set), records of other axes and undecodable
payloads are counted and passed over. A planner that starts after the node has accepted versions waits
for the next accepted one.
"""

from __future__ import annotations

import logging
import threading

import zenoh

from ..errors import WireError
from ..wire.keys import AxisKeys
from ..wire.params_estimate import ParamsEstimate
from .readiness import JoinedSubscriber

log = logging.getLogger(__name__)

JOIN_TIMEOUT_S = 30.0
"""how long an adaptive node may take to answer the join's hellos [s] (a loaded machine answers late)"""
QUEUE_CAPACITY = 1024
"""records the channel holds between two plans (a node publishes one every few seconds of drive time)"""


class AcceptedParams:
    """Follows the parameter estimates of one axis (use as a context manager; see the module docstring)."""

    def __init__(self, session: zenoh.Session, keys: AxisKeys, stop: threading.Event | None = None) -> None:
        self.keys = keys

        def handler() -> zenoh.handlers.FifoChannel:
            return zenoh.handlers.FifoChannel(QUEUE_CAPACITY)

        self._joined = JoinedSubscriber(session, keys.params, handler, JOIN_TIMEOUT_S, stop=stop)
        self._newest: ParamsEstimate | None = None
        self.received = 0
        self.rejected = 0
        """estimates the node turned down (their reasons are in the records)"""
        self.ignored = 0
        """records of another axis, or that did not decode"""

    def __enter__(self) -> AcceptedParams:
        self._joined.__enter__()
        return self

    def __exit__(self, *_exc: object) -> None:
        self._joined.__exit__()

    def newest(self, after_version: int) -> ParamsEstimate | None:
        """The newest accepted record received so far with a version above ``after_version`` (None if
        there is none)."""
        sub = self._joined.subscriber
        while sub is not None and (sample := sub.try_recv()) is not None:
            self.received += 1
            try:
                record = ParamsEstimate.decode(sample.payload.to_bytes())
            except WireError as exc:
                log.warning("ignoring a parameter record on %s: %s", self.keys.params, exc)
                self.ignored += 1
                continue
            if record.axis != self.keys.axis:
                self.ignored += 1
            elif not record.accepted:
                self.rejected += 1
            elif self._newest is None or record.version > self._newest.version:
                self._newest = record
        if self._newest is not None and self._newest.version > after_version:
            return self._newest
        return None
