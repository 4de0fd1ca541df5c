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
* :mod:`.zenoh_files` — the Zenoh JSON5 files of the router and of a role, written and read;
* :mod:`.folder` — the folder writer: everything or nothing, exact file modes;
* :mod:`.plan` — the validated settings of ``security init``;
* :mod:`.init`, :mod:`.add` — the two operations, ``security init`` and ``security add``;
* :mod:`.errors` — :class:`SecurityError` and :class:`SecurityArgumentError`.
"""

from .access_control import acl_config
from .add import SecurityAdd, add_roles
from .certificates import DEFAULT_DAYS, MAX_DAYS
from .errors import SecurityArgumentError, SecurityError
from .init import SecurityInit, init_security
from .plan import DEFAULT_HOST, DEFAULT_PORT, SecurityPlan
from .roles import DEFAULT_ROLES, ROLE_GRANTS, ROUTER, Grant, parse_roles, role_kind

__all__ = [
    "DEFAULT_DAYS",
    "DEFAULT_HOST",
    "DEFAULT_PORT",
    "DEFAULT_ROLES",
    "MAX_DAYS",
    "ROLE_GRANTS",
    "ROUTER",
    "Grant",
    "SecurityAdd",
    "SecurityArgumentError",
    "SecurityError",
    "SecurityInit",
    "SecurityPlan",
    "acl_config",
    "add_roles",
    "init_security",
    "parse_roles",
    "role_kind",
]
