"""What ``axisflow security init`` generates: a validated plan (folder, key prefix, roles, validity,
the router's address)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ...acquisition.bus.options import MAX_TCP_PORT, check_host
from ...acquisition.wire.keys import DEFAULT_PREFIX, all_keys
from .errors import SecurityArgumentError
from .roles import DEFAULT_ROLES, check_roles
from .validity import DEFAULT_DAYS, check_days

DEFAULT_PORT = 7448
"""the router's TLS port: next to 7447, which the embedded default (plain TCP peers) uses"""
DEFAULT_HOST = "127.0.0.1"


@dataclass(frozen=True)
class SecurityPlan:
    """What ``axisflow security init`` generates (validated on construction)."""

    directory: Path
    prefix: str = DEFAULT_PREFIX
    roles: tuple[str, ...] = DEFAULT_ROLES
    days: int = DEFAULT_DAYS
    """validity of every certificate [days]"""
    host: str = DEFAULT_HOST
    """the router's address as the roles reach it (an IP or a DNS name: the router certificate's SAN)"""
    port: int = DEFAULT_PORT
    """the router's TLS port"""
    listen_host: str | None = None
    """the address the router binds (default: ``host``; e.g. ``0.0.0.0`` for every interface)"""
    force: bool = False
    """replace an existing ``directory``"""

    def __post_init__(self) -> None:
        all_keys(self.prefix)  # a KeyExprError naming the prefix
        check_roles(self.roles)
        check_days(self.days)
        if not 1 <= self.port <= MAX_TCP_PORT:
            raise SecurityArgumentError(f"router port = {self.port} must be in 1…{MAX_TCP_PORT}")
        check_host(self.host, "router host")
        if self.listen_host is not None:
            check_host(self.listen_host, "router listen host")

    @property
    def endpoint(self) -> str:
        """The endpoint the roles connect to."""
        return f"tls/{_host_port(self.host, self.port)}"

    @property
    def listen_endpoint(self) -> str:
        """The endpoint the router listens on."""
        return f"tls/{_host_port(self.listen_host or self.host, self.port)}"


def _host_port(host: str, port: int) -> str:
    return f"[{host}]:{port}" if ":" in host else f"{host}:{port}"
