"""Zenoh session configuration from ``--mode``, ``--connect``, ``--listen`` and ``--zenoh-config``.

The embedded default needs no router and stays on this machine: peer mode, multicast scouting off,
every process listens on ``tcp/127.0.0.1:7447`` if that port is free and on a port of its own, and
connects to 7447 (the first process holds the port; the others connect to it, learn each other's own
ports by gossip and connect directly).

A ``--zenoh-config FILE`` (zenoh JSON5: TLS, authentication, access control…) replaces the embedded
default; ``--mode``, ``--connect`` and ``--listen`` given on the command line override the file.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import zenoh

from .errors import ZenohConfigError, zenoh_reason
from .keys import KeyExprError

DEFAULT_ENDPOINT = "tcp/127.0.0.1:7447"
LOOPBACK_ANY_PORT = "tcp/127.0.0.1:0"
MODES = ("peer", "client", "router")


@dataclass(frozen=True)
class ZenohOptions:
    """How to open a Zenoh session; empty tuples/None mean "not given"."""

    mode: str | None = None
    connect: tuple[str, ...] = ()
    listen: tuple[str, ...] = ()
    config_file: Path | None = None

    def __post_init__(self) -> None:
        if self.mode is not None and self.mode not in MODES:
            raise ZenohConfigError(f"zenoh mode {self.mode!r} is not one of {', '.join(MODES)}")
        for ep in (*self.connect, *self.listen):
            if "/" not in ep:
                raise ZenohConfigError(f"zenoh endpoint {ep!r} is not of the form <proto>/<address>")

    @classmethod
    def loopback(cls, listen_port: int | None = None, connect_port: int | None = None) -> ZenohOptions:
        """Peer on tcp/127.0.0.1 listening on and/or connecting to the given ports (for tests)."""
        return cls(
            mode="peer",
            listen=(f"tcp/127.0.0.1:{listen_port}",) if listen_port is not None else (),
            connect=(f"tcp/127.0.0.1:{connect_port}",) if connect_port is not None else (),
        )


def _insert(config: zenoh.Config, key: str, value: object) -> None:
    config.insert_json5(key, json.dumps(value))


def build_config(options: ZenohOptions) -> zenoh.Config:
    """A :class:`zenoh.Config` for ``options`` (see the module docstring for the rules)."""
    if options.config_file is not None:
        path = Path(options.config_file)
        if not path.is_file():
            raise ZenohConfigError(f"zenoh config file {path} does not exist")
        try:
            config = zenoh.Config.from_file(str(path))
        except zenoh.ZError as exc:
            raise ZenohConfigError(f"zenoh config file {path} is invalid: {zenoh_reason(exc)}") from None
    else:
        config = zenoh.Config()
        _insert(config, "mode", "peer")
        _insert(config, "scouting/multicast/enabled", False)
        if not options.connect and not options.listen:
            # the well-known port if free, and always an own port: gossip hands it to the other peers,
            # which then connect directly (a peer does not forward between two other peers)
            _insert(config, "listen/endpoints", [DEFAULT_ENDPOINT, LOOPBACK_ANY_PORT])
            _insert(config, "listen/exit_on_failure", False)
            _insert(config, "connect/endpoints", [DEFAULT_ENDPOINT])
            _insert(config, "connect/timeout_ms", 0)
            _insert(config, "connect/exit_on_failure", False)
        elif not options.listen:
            # a peer listens somewhere so others can reach it directly; never on all interfaces
            _insert(config, "listen/endpoints", [LOOPBACK_ANY_PORT])
    try:
        if options.mode is not None:
            _insert(config, "mode", options.mode)
        if options.connect:
            _insert(config, "connect/endpoints", list(options.connect))
            if options.config_file is None:
                # do not block open() forever when the other side is not up yet; retry in background
                _insert(config, "connect/timeout_ms", 10_000)
        if options.listen:
            _insert(config, "listen/endpoints", list(options.listen))
    except zenoh.ZError as exc:
        raise ZenohConfigError(f"invalid zenoh option: {zenoh_reason(exc)}") from None
    return config


def open_session(options: ZenohOptions) -> zenoh.Session:
    """Open a session (use it as a context manager so it is always closed)."""
    config = build_config(options)
    try:
        return zenoh.open(config)
    except zenoh.ZError as exc:
        raise ZenohConfigError(f"cannot open a zenoh session ({options}): {zenoh_reason(exc)}") from None


def check_key_expression(expr: str, option: str = "--keys") -> zenoh.KeyExpr:
    """``expr`` as a Zenoh key expression, or a :class:`KeyExprError` naming it."""
    try:
        return zenoh.KeyExpr(expr)
    except zenoh.ZError as exc:
        raise KeyExprError(
            f"{option} {expr!r} is not a valid Zenoh key expression: {zenoh_reason(exc)}"
        ) from None
