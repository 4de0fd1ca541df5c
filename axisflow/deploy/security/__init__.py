"""Who may command an axis: a certificate authority, one certificate per role, and the Zenoh
configuration files of a secure deployment (mutual TLS plus a default-deny access-control list).

Topology: one Zenoh **router** listens on ``tls/HOST:PORT`` and is the only process that listens;
every role (planner, bridge, recorder, adapter) runs as a Zenoh **client** that connects to it. Both sides
present a certificate of the same private CA (mTLS: ``enable_mtls``); the router admits only links
whose certificate chains to that CA and applies its access-control list (ACL) to every message on
each link, keyed on the common name (CN) of the certificate — the role.

``init_security(SecurityPlan(directory=DIR))`` writes, all at once (nothing is left half-written on
error)::

    DIR/ca.pem              the CA certificate: every host needs it
    DIR/ca.key              the CA private key (0600): keep it offline, no process needs it
    DIR/router.{pem,key,json5}
    DIR/<role>.{pem,key,json5}   per role (private keys 0600)

``add_roles(DIR, ("recorder-laptop",))`` issues more identities with the folder's CA (never valid
longer than it), writes their files beside the others and rewrites ``router.json5`` with an ACL that
admits them too; the router reads its ACL at start, so it must be restarted.

One concept per module:

* :mod:`.roles` — the roles, their kinds and what each kind may do (:data:`ROLE_GRANTS`);
* :mod:`.access_control` — the router's ACL built from the grants, and read back;
* :mod:`.certificates` — the CA, the router's and the roles' certificates and keys;
* :mod:`.validity` — how long a certificate is valid (the default and the bound, in days);
* :mod:`.zenoh_files` — the Zenoh JSON5 files of the router and of a role, written and read;
* :mod:`.folder` — the folder writer: everything or nothing, exact file modes;
* :mod:`.plan` — the validated settings of ``security init``;
* :mod:`.init`, :mod:`.add` — the two operations, ``security init`` and ``security add``;
* :mod:`.errors` — :class:`SecurityError` and :class:`SecurityArgumentError`.

Each public name is loaded with its module on first use: the command line's parser reads the
defaults without loading the certificate machinery (cryptography).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ...model import lazy_names

if TYPE_CHECKING:  # what a type checker sees; at run time __getattr__ loads each name from _HOMES
    from .access_control import acl_config  # noqa: F401
    from .add import SecurityAdd, add_roles  # noqa: F401
    from .errors import SecurityArgumentError, SecurityError  # noqa: F401
    from .init import SecurityInit, init_security  # noqa: F401
    from .plan import DEFAULT_HOST, DEFAULT_PORT, SecurityPlan  # noqa: F401
    from .roles import DEFAULT_ROLES, ROLE_GRANTS, ROUTER, Grant, parse_roles, role_kind  # noqa: F401
    from .validity import DEFAULT_DAYS, MAX_DAYS  # noqa: F401

# each public name → its module, relative to this package
_HOMES: dict[str, str] = {
    "acl_config": "access_control",
    "SecurityAdd": "add",
    "add_roles": "add",
    "DEFAULT_DAYS": "validity",
    "MAX_DAYS": "validity",
    "SecurityArgumentError": "errors",
    "SecurityError": "errors",
    "SecurityInit": "init",
    "init_security": "init",
    "DEFAULT_HOST": "plan",
    "DEFAULT_PORT": "plan",
    "SecurityPlan": "plan",
    "DEFAULT_ROLES": "roles",
    "ROLE_GRANTS": "roles",
    "ROUTER": "roles",
    "Grant": "roles",
    "parse_roles": "roles",
    "role_kind": "roles",
}


__getattr__ = lazy_names(__name__, _HOMES)


__all__ = sorted(_HOMES)
