"""The hello: a publisher's answer to a subscriber that proves its route, and says where it runs.

Every axisflow publisher answers queries on ``@axisflow/hello/<its key>/<its publisher id>`` (see
:func:`.keys.hello_key`) with a :class:`Hello`. A subscriber that must not miss a sample asks before
and after declaring itself (:mod:`axisflow.acquisition.bus.readiness` says why that proves the route);
a second bridge asks who publishes its axis's samples, to name the first one. The answer carries the
publisher's last sequence number at the moment it answered: what a recorder that joins owes from then
on, and what one that stops was sent until then (:mod:`.last_sequences`). The record is JSON (it never
lands in MCAP: the ``@axisflow`` chunk is verbatim, so no ``**`` subscription or query sees it).
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass

from ..errors import WireError

HELLO_ENCODING = "application/json"


@dataclass(frozen=True)
class Hello:
    """Who answered a hello."""

    key: str
    """the key it publishes on"""
    publisher: str
    """its publisher id (hex), as its messages' attachments carry it"""
    zid: str
    """the Zenoh id of its session"""
    host: str
    """the host name of its process"""
    pid: int
    """its process id"""
    sequence: int
    """the number of the last message it had put when it answered (0: none yet); every message up to
    it left before the answer"""

    def encode(self) -> bytes:
        return json.dumps(asdict(self), separators=(",", ":")).encode()

    @classmethod
    def decode(cls, data: bytes) -> Hello:
        try:
            fields = json.loads(data)
            hello = cls(**fields)
        except (ValueError, TypeError) as exc:  # not JSON, not an object, or other fields
            raise WireError(f"undecodable hello ({len(data)} bytes): {exc}") from None
        for name in ("key", "publisher", "zid", "host"):
            if not isinstance(getattr(hello, name), str):
                raise WireError(f"hello field {name} = {getattr(hello, name)!r} is not a string")
        if not isinstance(hello.pid, int) or isinstance(hello.pid, bool) or hello.pid < 0:
            raise WireError(f"hello field pid = {hello.pid!r} is not a process id")
        if not isinstance(hello.sequence, int) or isinstance(hello.sequence, bool) or hello.sequence < 0:
            raise WireError(f"hello field sequence = {hello.sequence!r} is not a count >= 0")
        return hello

    @property
    def publisher_id(self) -> bytes:
        return bytes.fromhex(self.publisher)

    @property
    def where(self) -> str:
        """``pid N on host H (Zenoh id Z)``"""
        return f"pid {self.pid} on host {self.host} (Zenoh id {self.zid})"
