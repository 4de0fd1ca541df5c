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
    """Use as a context manager; :meth:`latest` is the newest sample received, or None.

    With ``follow=False`` the subscriber is declared only while :meth:`wait` waits (and by
    :meth:`latest`, until the next :meth:`wait` returns): a program that needs where the axis is only
    now and then (a planner at the start of each run) does not receive every sample of a bridge that
    runs many times faster than real time."""

    def __init__(
        self, session: zenoh.Session, keys: AxisKeys, signal: str = "state", follow: bool = True
    ) -> None:
        if signal not in ("state", "setpoint"):
            raise AcquisitionError(f"axis signal {signal!r} is not one of state, setpoint")
        self.keys = keys
        self.key = keys.state if signal == "state" else keys.setpoint
        self._session = session
        self._follow = follow
        self._sub: zenoh.Subscriber | None = None
        if follow:
            self._listen()
        self._latest: AxisSample | None = None

    def _listen(self) -> zenoh.Subscriber:
        if self._sub is None:
            self._sub = self._session.declare_subscriber(self.key, zenoh.handlers.RingChannel(1))
        return self._sub

    def latest(self) -> AxisSample | None:
        sample = self._listen().try_recv()
        if sample is not None:
            self._latest = AxisSample.decode(sample.payload.to_bytes())
        return self._latest

    def wait(self, timeout_s: float) -> AxisSample:
        """The newest sample, waiting up to ``timeout_s`` for the first; raises if none arrives. Without
        ``follow``: a sample that arrives during this call (not one kept from an earlier call)."""
        deadline = time.monotonic() + timeout_s
        if not self._follow:
            self._latest = None
        while (sample := self.latest()) is None:
            if time.monotonic() >= deadline:
                raise AcquisitionError(
                    f"no sample of axis {self.keys.axis!r} on {self.key} within {timeout_s:g} s: "
                    "is its bridge running and reachable?"
                )
            time.sleep(0.005)
        if not self._follow:
            self._unlisten()
        return sample

    def _unlisten(self) -> None:
        if self._sub is not None:
            self._sub.undeclare()
            self._sub = None

    def close(self) -> None:
        self._unlisten()

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
