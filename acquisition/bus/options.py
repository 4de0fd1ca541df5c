"""The connection options of a Zenoh session (``--mode``, ``--connect``, ``--listen``,
``--zenoh-config``) as validated data. No Zenoh here: the command line builds them before it loads
Zenoh; :mod:`.session` turns them into a configuration and opens the session."""

from __future__ import annotations

import ipaddress
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType

from ..errors import ZenohConfigError

DEFAULT_ENDPOINT = "tcp/127.0.0.1:7447"
LOOPBACK_ANY_PORT = "tcp/127.0.0.1:0"
MODES = ("peer", "client", "router")
MAX_TCP_PORT = 65535
"""the largest TCP port (an endpoint's, a router's, a web viewer's)"""
CONNECT_WAIT_S = 5.0
"""default of :attr:`ZenohOptions.connect_wait_s` [s]"""
RECONNECT_RETRY: Mapping[str, int] = MappingProxyType(
    {"period_init_ms": 100, "period_max_ms": 1000, "period_increase_factor": 2}
)
"""``connect/retry`` of a session that connects: a router or peer that cannot be reached, or whose link
was lost (a router restarted), is tried again after 0.1 s, then at doubling intervals up to every 1 s,
so a client is back within about a second of its router (Zenoh's own default, 1 s doubling to 4 s,
leaves it up to 4 s longer: docs/deployment.md)"""
TLS_FILE_KEYS = (
    "root_ca_certificate",
    "listen_certificate",
    "listen_private_key",
    "connect_certificate",
    "connect_private_key",
)
"""the file paths of zenoh's ``transport/link/tls`` section"""
_HOST_PORT_PROTOCOLS = ("tcp", "udp", "tls", "quic", "ws")
"""endpoint protocols whose address is ``host:port`` (others, e.g. unixsock-stream, zenoh checks)"""
_HOST_LABEL = re.compile(r"^[A-Za-z0-9_](?:[A-Za-z0-9_-]{0,61}[A-Za-z0-9_])?$")


def check_host(host: str, what: str = "host") -> str:
    """``host`` if it is an IP address (v4 or v6) or a DNS host name; else a :class:`ZenohConfigError`.

    An all-numeric dotted name must be an IPv4 address (``999.1.1.1`` is neither).
    """
    try:
        ipaddress.ip_address(host)
        return host
    except ValueError:
        pass
    labels = host.removesuffix(".").split(".")
    if (
        not host
        or len(host) > 253
        or not all(_HOST_LABEL.match(label) for label in labels)
        or labels[-1].isdigit()
    ):
        raise ZenohConfigError(f"{what} {host!r} is neither an IP address (IPv4 parts 0…255) nor a host name")
    return host


def check_endpoint(endpoint: str, listen: bool = False) -> str:
    """``endpoint`` if it reads ``<proto>/<host>:<port>`` with a valid host and port (for the
    protocols with such addresses; port 0 only for ``listen``); else a :class:`ZenohConfigError`."""
    proto, sep, rest = endpoint.partition("/")
    if not sep or not proto or not rest:
        raise ZenohConfigError(f"zenoh endpoint {endpoint!r} is not of the form <proto>/<address>")
    if proto not in _HOST_PORT_PROTOCOLS:
        return endpoint
    address = re.split(r"[?#]", rest, maxsplit=1)[0]
    if address.startswith("["):
        host, bracket, port = address[1:].partition("]:")
        if not bracket:
            host, port = "", ""
    else:
        host, _colon, port = address.rpartition(":")
    if not host or not port:
        raise ZenohConfigError(f"zenoh endpoint {endpoint!r} has no <host>:<port> after {proto}/")
    check_host(host, f"zenoh endpoint {endpoint!r}: host")
    lowest = 0 if listen else 1
    if not port.isdigit() or not lowest <= int(port) <= MAX_TCP_PORT:
        raise ZenohConfigError(
            f"zenoh endpoint {endpoint!r}: port {port!r} is not in {lowest}…{MAX_TCP_PORT}"
            + ("" if listen else " (port 0, any free port, is for --listen only)")
        )
    return endpoint


@dataclass(frozen=True)
class ZenohOptions:
    """How to open a Zenoh session; empty tuples/None mean "not given"."""

    mode: str | None = None
    connect: tuple[str, ...] = ()
    listen: tuple[str, ...] = ()
    config_file: Path | None = None
    connect_wait_s: float = CONNECT_WAIT_S
    """how long [s] :func:`open_session` waits for a first router or peer when the configuration
    must connect (see the module docstring)"""

    def __post_init__(self) -> None:
        if self.mode is not None and self.mode not in MODES:
            raise ZenohConfigError(f"zenoh mode {self.mode!r} is not one of {', '.join(MODES)}")
        for ep in self.connect:
            check_endpoint(ep)
        for ep in self.listen:
            check_endpoint(ep, listen=True)
        if not 0.0 <= self.connect_wait_s <= 3600.0:
            raise ZenohConfigError(f"zenoh connect wait = {self.connect_wait_s} s must be in 0…3600 s")

    @classmethod
    def loopback(cls, listen_port: int | None = None, connect_port: int | None = None) -> ZenohOptions:
        """Peer on tcp/127.0.0.1 listening on and/or connecting to the given ports (for tests)."""
        return cls(
            mode="peer",
            listen=(f"tcp/127.0.0.1:{listen_port}",) if listen_port is not None else (),
            connect=(f"tcp/127.0.0.1:{connect_port}",) if connect_port is not None else (),
        )
