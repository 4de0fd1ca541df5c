"""The latest sample of an axis, for programs that must know where the axis is (a planner that starts
or restarts, the excitation run): a Zenoh subscriber on ``<prefix>/<axis>/state`` (measured) or
``setpoint`` (commanded: at rest, exactly the position a new move must start from) that keeps only the
newest sample (a ring of one: nothing queues up behind a slow reader); and what drives the axis
(:class:`DriveWatch`: the bridge's DriveInfo records)."""

from __future__ import annotations

import contextlib
import time

import zenoh

from ..errors import AcquisitionError, WireError
from ..wire.drive_info import DriveInfo
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


class DriveWatch:
    """The newest :class:`~axisflow.acquisition.wire.drive_info.DriveInfo` of an axis (its bridge sends
    one a second of drive time): open it early, read :meth:`latest` when it matters. A context manager."""

    def __init__(self, session: zenoh.Session, keys: AxisKeys) -> None:
        self._sub = session.declare_subscriber(keys.drive, zenoh.handlers.RingChannel(1))
        self._latest: DriveInfo | None = None

    def latest(self) -> DriveInfo | None:
        sample = self._sub.try_recv()
        if sample is not None:
            with contextlib.suppress(WireError):  # an undecodable record: keep what was understood
                self._latest = DriveInfo.decode(sample.payload.to_bytes())
        return self._latest

    def wait(self, timeout_s: float) -> DriveInfo | None:
        """The newest record, waiting up to ``timeout_s`` for the first (None: none came)."""
        deadline = time.monotonic() + timeout_s
        while (info := self.latest()) is None and time.monotonic() < deadline:
            time.sleep(0.01)
        return info

    def close(self) -> None:
        self._sub.undeclare()

    def __enter__(self) -> DriveWatch:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()
