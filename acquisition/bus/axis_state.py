"""The latest sample of an axis, for programs that must know where the axis is (a planner that starts
or restarts, the excitation run): a Zenoh subscriber on ``<prefix>/<axis>/state`` (measured) or
``setpoint`` (commanded: at rest, exactly the position a new move must start from) that keeps only the
newest sample (a ring of one: nothing queues up behind a slow reader)."""

from __future__ import annotations

import time

import zenoh

from ..errors import AcquisitionError
from ..wire.keys import AxisKeys
from ..wire.messages import AxisSample


class AxisState:
    """Use as a context manager; :meth:`latest` is the newest sample received, or None."""

    def __init__(self, session: zenoh.Session, keys: AxisKeys, signal: str = "state") -> None:
        if signal not in ("state", "setpoint"):
            raise AcquisitionError(f"axis signal {signal!r} is not one of state, setpoint")
        self.keys = keys
        self.key = keys.state if signal == "state" else keys.setpoint
        self._sub = session.declare_subscriber(self.key, zenoh.handlers.RingChannel(1))
        self._latest: AxisSample | None = None

    def latest(self) -> AxisSample | None:
        sample = self._sub.try_recv()
        if sample is not None:
            self._latest = AxisSample.decode(sample.payload.to_bytes())
        return self._latest

    def wait(self, timeout_s: float) -> AxisSample:
        """The newest sample, waiting up to ``timeout_s`` for the first; raises if none arrives."""
        deadline = time.monotonic() + timeout_s
        while (sample := self.latest()) is None:
            if time.monotonic() >= deadline:
                raise AcquisitionError(
                    f"no sample of axis {self.keys.axis!r} on {self.key} within {timeout_s:g} s: "
                    "is its bridge running and reachable?"
                )
            time.sleep(0.005)
        return sample

    def close(self) -> None:
        self._sub.undeclare()

    def __enter__(self) -> AxisState:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()
