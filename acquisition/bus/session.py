"""Zenoh session configuration from ``--mode``, ``--connect``, ``--listen`` and ``--zenoh-config``.

The embedded default needs no router and stays on this machine: peer mode, multicast scouting off,
every process listens on ``tcp/127.0.0.1:7447`` if that port is free and on a port of its own, and
connects to 7447 (the first process holds the port; the others connect to it, learn each other's own
ports by gossip and connect directly). With ``--connect`` (a client of a cell's router, or a peer of a
named one) a lost link is retried every 0.1…1 s (:data:`RECONNECT_RETRY`).

A ``--zenoh-config FILE`` (zenoh JSON5: TLS, authentication, access control…) replaces the embedded
default; ``--mode``, ``--connect`` and ``--listen`` given on the command line override the file. A
relative certificate or key path in the file's ``transport/link/tls`` section is taken relative to the
file's folder when the file is there (else, as zenoh does, relative to the working directory), so a
folder of ``axisflow security init`` works from anywhere; a TLS file found nowhere is an error that
names it.

**A session that must connect is checked.** Zenoh's ``open()`` in peer mode returns a session even
when none of its ``connect`` endpoints can be reached (nothing listens, a TLS handshake is refused);
such a session would run deaf. :func:`open_session` therefore checks every endpoint's syntax before
opening (a bad address fails at once) and, when the configuration says the session must connect —
``--connect`` given, ``connect/endpoints`` in the file, or client mode — waits up to
:attr:`ZenohOptions.connect_wait_s` for a first router or peer (``session.info``), and otherwise closes
the session and raises :class:`ZenohConnectError` naming the endpoints and the likely causes. The
embedded default (its connection to 7447 is optional: the first process has nobody to reach) and
router mode (a router waits for others) are not checked; its handshakes are given
:data:`LOOPBACK_OPEN_TIMEOUT_MS` (zenoh's default is 10 s), so a program other than zenoh holding 7447
delays a command by about 2 s rather than 10.
"""

from __future__ import annotations

import json
import re
import time
from dataclasses import dataclass
from pathlib import Path

import zenoh

from ..errors import ZenohConfigError, ZenohConnectError, zenoh_reason
from ..wire.keys import KeyExprError
from .options import (
    CONNECT_WAIT_S,
    DEFAULT_ENDPOINT,
    LOOPBACK_ANY_PORT,
    MODES,
    RECONNECT_RETRY,
    TLS_FILE_KEYS,
    ZenohOptions,
    check_endpoint,
    check_host,
)

_ADDRESS_IN_USE = re.compile(r"bound to (?P<endpoint>\S+): .*Address already in use")
"""zenoh's error when a listen endpoint's port is taken"""

__all__ = [
    "CONNECT_WAIT_S",
    "DEFAULT_ENDPOINT",
    "LOOPBACK_ANY_PORT",
    "MODES",
    "RECONNECT_RETRY",
    "TLS_FILE_KEYS",
    "ZenohOptions",
    "build_config",
    "check_endpoint",
    "check_host",
    "check_key_expression",
    "open_session",
]


LOOPBACK_OPEN_TIMEOUT_MS = 2000
"""how long the embedded default waits for a zenoh handshake on loopback [ms]"""


def _insert(config: zenoh.Config, key: str, value: object) -> None:
    config.insert_json5(key, json.dumps(value))


def _get(config: zenoh.Config, key: str) -> object:
    try:
        return json.loads(config.get_json(key))
    except (zenoh.ZError, ValueError):
        return None


def _resolve_tls_paths(config: zenoh.Config, path: Path) -> None:
    """Relative TLS file paths of the config file ``path`` → paths in its folder where such a file
    exists there; a TLS file found nowhere is a :class:`ZenohConfigError` naming it (zenoh's own
    error does not)."""
    folder = path.absolute().parent
    for key in TLS_FILE_KEYS:
        value = _get(config, f"transport/link/tls/{key}")
        if not isinstance(value, str) or not value:
            continue
        file = Path(value)
        if not file.is_absolute() and (folder / file).is_file():
            file = folder / file
            _insert(config, f"transport/link/tls/{key}", str(file))
        if not file.is_file():
            looked = "" if file.is_absolute() else f" (looked in {folder} and the working directory)"
            raise ZenohConfigError(
                f"zenoh config file {path}: transport/link/tls/{key} {value!r} does not exist{looked}"
            )


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
        _resolve_tls_paths(config, path)
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
            # a handshake on loopback takes milliseconds; zenoh's 10 s would hold every command that long
            # when something that is not zenoh holds 7447
            _insert(config, "transport/unicast/open_timeout", LOOPBACK_OPEN_TIMEOUT_MS)
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
                _insert(config, "connect/retry", dict(RECONNECT_RETRY))
        if options.listen:
            _insert(config, "listen/endpoints", list(options.listen))
    except zenoh.ZError as exc:
        raise ZenohConfigError(f"invalid zenoh option: {zenoh_reason(exc)}") from None
    return config


def _mode_of(config: zenoh.Config) -> str:
    mode = _get(config, "mode")
    return mode if isinstance(mode, str) else "peer"


def _endpoints(config: zenoh.Config, section: str, mode: str) -> tuple[str, ...]:
    """``<section>/endpoints`` of ``mode`` (zenoh accepts a list or a list per mode)."""
    value = _get(config, f"{section}/endpoints")
    if isinstance(value, dict):
        value = value.get(mode, [])
    return tuple(str(ep) for ep in value) if isinstance(value, list) else ()


@dataclass(frozen=True)
class ConnectRequirement:
    """Whether a session must reach another router or peer, and the endpoints it was given."""

    must_connect: bool
    endpoints: tuple[str, ...]
    mode: str

    @property
    def where(self) -> str:
        return ", ".join(self.endpoints) or "a router (found by scouting: no endpoint was given)"

    def likely_causes(self) -> str:
        causes = ["nothing listens there (is the router or the other peer running?)"]
        if any(ep.startswith(("tls/", "quic/")) for ep in self.endpoints):
            causes.append(
                "the TLS handshake was refused: a certificate not signed by the CA the other side "
                "trusts (another CA, or no certificate), an expired certificate, or an address not in "
                "the other side's certificate (SAN)"
            )
        return "; or ".join(causes)

    def unreachable_message(self, wait_s: float) -> str:
        """After opening: nobody reached in ``wait_s``."""
        return (
            f"zenoh session ({self.mode} mode) reached no router or peer at {self.where} within "
            f"{wait_s:g} s; likely: {self.likely_causes()}"
        )

    def open_failed_message(self, reason: str) -> str:
        """zenoh's ``open()`` itself failed (a client that connects to nobody fails there)."""
        return (
            f"cannot open a zenoh session ({self.mode} mode, connecting to {self.where}): {reason}; if "
            f"no connection was made, likely: {self.likely_causes()}"
        )


def connect_requirement(options: ZenohOptions, config: zenoh.Config) -> ConnectRequirement:
    """What the configuration says about connecting (see the module docstring)."""
    mode = _mode_of(config)
    endpoints = _endpoints(config, "connect", mode)
    if mode == "router" or (options.config_file is None and not options.connect):
        return ConnectRequirement(False, endpoints, mode)
    return ConnectRequirement(bool(endpoints) or mode == "client", endpoints, mode)


def wait_connected(session: zenoh.Session, timeout_s: float, poll_s: float = 0.02) -> bool:
    """True once ``session`` has a router or peer (``session.info``); False after ``timeout_s``."""
    deadline = time.monotonic() + timeout_s
    while True:
        info = session.info
        if list(info.routers_zid()) or list(info.peers_zid()):
            return True
        if time.monotonic() >= deadline:
            return False
        time.sleep(poll_s)


def open_session(options: ZenohOptions) -> zenoh.Session:
    """Open a session (use it as a context manager so it is always closed).

    Raises :class:`ZenohConnectError` when the configuration must connect and no router or peer is
    reached within ``options.connect_wait_s`` (the session is closed first).
    """
    config = build_config(options)
    need = connect_requirement(options, config)
    for ep in need.endpoints:
        check_endpoint(ep)
    for ep in _endpoints(config, "listen", need.mode):
        check_endpoint(ep, listen=True)
    try:
        session = zenoh.open(config)
    except zenoh.ZError as exc:
        reason = zenoh_reason(exc)
        in_use = _ADDRESS_IN_USE.search(reason)
        if in_use:
            raise ZenohConfigError(f"{in_use['endpoint']} is in use") from None
        if need.must_connect:
            raise ZenohConnectError(need.open_failed_message(reason)) from None
        listen = ", ".join(_endpoints(config, "listen", need.mode)) or "no endpoint"
        raise ZenohConfigError(
            f"cannot open a zenoh session ({need.mode} mode, listening on {listen}): {reason}"
        ) from None
    if need.must_connect and not wait_connected(session, options.connect_wait_s):
        session.close()
        raise ZenohConnectError(need.unreachable_message(options.connect_wait_s))
    return session


def check_key_expression(expr: str, option: str = "--keys") -> zenoh.KeyExpr:
    """``expr`` as a Zenoh key expression, or a :class:`KeyExprError` naming it."""
    try:
        return zenoh.KeyExpr(expr)
    except zenoh.ZError as exc:
        raise KeyExprError(
            f"{option} {expr!r} is not a valid Zenoh key expression: {zenoh_reason(exc)}"
        ) from None
