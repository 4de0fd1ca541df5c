"""The Zenoh configuration files of a secure deployment, and reading them back.

The router's file: router mode, TLS only, mutual TLS, the access-control list. A role's file: a
client of the router over TLS with its own certificate, the router's name verified, a lost router
tried again every 0.1…1 s (:data:`~axisflow.acquisition.bus.options.RECONNECT_RETRY`). Paths in them
are relative to their folder (:func:`axisflow.acquisition.bus.session.build_config` resolves them
there), so a role's four files can be copied together to the host that runs it.

The files are JSON5, the format Zenoh reads: written and read with the ``json5`` library (comments,
unquoted keys and trailing commas, as Zenoh's own parser takes them; duplicate keys refused, as Zenoh
refuses them), each checked to load in Zenoh before it is written.
"""

from __future__ import annotations

from pathlib import Path

import json5

from ...acquisition.bus.options import RECONNECT_RETRY
from .access_control import acl_config
from .errors import SecurityError
from .roles import ROUTER, role_kind


def router_config(listen_endpoint: str, prefix: str, roles: tuple[str, ...]) -> dict[str, object]:
    """The router's Zenoh configuration: listens on ``listen_endpoint`` only, TLS only, mTLS, the ACL
    of ``roles`` under ``prefix`` (paths relative to its folder)."""
    return {
        "mode": "router",
        "listen": {"endpoints": [listen_endpoint], "exit_on_failure": True},
        "connect": {"endpoints": []},
        "scouting": {"multicast": {"enabled": False}, "gossip": {"enabled": False}},
        "transport": {
            "link": {
                "protocols": ["tls"],
                "tls": {
                    "root_ca_certificate": "ca.pem",
                    "listen_certificate": f"{ROUTER}.pem",
                    "listen_private_key": f"{ROUTER}.key",
                    "enable_mtls": True,
                    "close_link_on_expiration": True,
                },
            }
        },
        "access_control": acl_config(prefix, roles),
    }


def client_config(endpoint: str, role: str) -> dict[str, object]:
    """A role's Zenoh configuration: a client of the router at ``endpoint`` over TLS with its own
    certificate (paths relative to its folder)."""
    role_kind(role)
    return {
        "mode": "client",
        # a lost router (restarted, or the link down) is tried again every 0.1…1 s
        "connect": {"endpoints": [endpoint], "retry": dict(RECONNECT_RETRY)},
        "scouting": {"multicast": {"enabled": False}},
        "transport": {
            "link": {
                "protocols": ["tls"],
                "tls": {
                    "root_ca_certificate": "ca.pem",
                    "connect_certificate": f"{role}.pem",
                    "connect_private_key": f"{role}.key",
                    "enable_mtls": True,
                    "verify_name_on_connect": True,
                    "close_link_on_expiration": True,
                },
            }
        },
    }


def to_json5(config: dict[str, object], header: str) -> str:
    """``config`` as a JSON5 text with ``header`` as ``//`` comment lines above it."""
    comment = "".join(f"// {line}\n" for line in header.splitlines())
    return comment + json5.dumps(config, indent=2) + "\n"


def check_loads_in_zenoh(name: str, text: str) -> None:
    """Raise a :class:`SecurityError` if Zenoh does not take ``text`` as a configuration (a bug of
    ours, never the user's input: said plainly)."""
    import zenoh

    try:
        zenoh.Config.from_json5(text)
    except zenoh.ZError as exc:
        raise SecurityError(f"generated {name} is not a valid zenoh configuration: {exc}") from None


def read_json5(path: Path) -> dict[str, object]:
    """The configuration in a ``.json5`` file of a folder of ``security init``; a
    :class:`SecurityError` naming the file and the reason if it is missing, unreadable, or not a JSON5
    object that Zenoh would read."""
    try:
        text = path.read_text("utf-8")
    except FileNotFoundError:
        raise SecurityError(f"{path} is missing: not a folder written by `axisflow security init`") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise SecurityError(f"cannot read {path}: {getattr(exc, 'strerror', None) or exc}") from None
    try:
        data = json5.loads(text, allow_duplicate_keys=False)
    except ValueError as exc:
        where = str(exc).replace("<string>:", "line ", 1)
        raise SecurityError(
            f"{path} is not the JSON5 that `axisflow security init` writes ({where}): edited by hand? "
            "not rewriting it"
        ) from None
    if not isinstance(data, dict):
        raise SecurityError(f"{path} holds a JSON5 {type(data).__name__}, not a zenoh configuration object")
    return data


def client_endpoint(path: Path) -> str:
    """The router endpoint a role's file connects to."""
    try:
        return str(read_json5(path)["connect"]["endpoints"][0])  # type: ignore[index]
    except (KeyError, IndexError, TypeError):
        raise SecurityError(f"{path} names no router endpoint: not a role file of `security init`") from None
