"""``axisflow security init DIR``: a CA, per-role certificates and the Zenoh files of a secure set-up;
``axisflow security add DIR --roles …``: more identities with that CA."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..acquisition.wire.keys import DEFAULT_PREFIX
from ..arguments import positive_int, tcp_port
from ..deploy.security import (
    DEFAULT_DAYS,
    DEFAULT_HOST,
    DEFAULT_PORT,
    DEFAULT_ROLES,
    SecurityPlan,
    parse_roles,
)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "security",
        help="generate certificates and Zenoh configs for mTLS + access control",
        description="Secure deployments: mutual TLS and a default-deny access-control list in which "
        "only the planner may send moves and quick stops, the bridge publishes telemetry and events, "
        "a recorder only listens, and nobody else gets anything. See docs/security.md.",
    )
    actions = p.add_subparsers(dest="action", metavar="ACTION", required=True)
    init = actions.add_parser(
        "init",
        help="write a CA, per-role certificates/keys and Zenoh JSON5 files into a new folder DIR",
        description="Write into DIR (which must not exist unless --force): ca.pem, ca.key, and for the "
        "router and each role NAME.pem (certificate, CN = NAME), NAME.key (private key, mode 0600) and "
        "NAME.json5 (zenoh config for --zenoh-config). The router listens on tls/HOST:PORT and enforces "
        "the ACL; the roles connect to it as clients.",
    )
    init.add_argument("directory", metavar="DIR", help="the folder to create")
    init.add_argument(
        "--prefix", default=DEFAULT_PREFIX, help=f"key prefix the ACL covers (default: {DEFAULT_PREFIX})"
    )
    init.add_argument(
        "--roles",
        default=",".join(DEFAULT_ROLES),
        metavar="R1,R2,…",
        help="roles to issue: planner, bridge, recorder, adapter, or KIND-NAME for more identities of a kind "
        "(e.g. planner-cell2), and KIND@AXIS to limit one to an axis (bridge@a0, planner-line2@a3, "
        f"bridge-m1@a0+a1; docs/deployment.md); default: {','.join(DEFAULT_ROLES)}",
    )
    init.add_argument(
        "--days",
        type=positive_int,
        default=DEFAULT_DAYS,
        metavar="N",
        help=f"validity of the certificates [days] (default {DEFAULT_DAYS})",
    )
    init.add_argument(
        "--host",
        default=DEFAULT_HOST,
        help="the router's IP or DNS name as the roles reach it (put in its certificate; "
        f"default {DEFAULT_HOST})",
    )
    init.add_argument(
        "--listen-host",
        default=None,
        help="the address the router binds if not --host (e.g. 0.0.0.0 for every interface)",
    )
    init.add_argument(
        "--listen-port",
        type=tcp_port,
        default=DEFAULT_PORT,
        metavar="PORT",
        help=f"the router's TLS port (default {DEFAULT_PORT})",
    )
    init.add_argument("--force", action="store_true", help="replace DIR if it exists (its old keys are lost)")
    init.set_defaults(func=run_init)

    add = actions.add_parser(
        "add",
        help="issue more roles with the CA of a folder of `security init` and admit them in its router",
        description="Issue a certificate, private key and Zenoh JSON5 file for each new role with the CA "
        "of DIR (its ca.key must be there), and rewrite DIR/router.json5 so that its access-control "
        "list admits them too. Restart the router afterwards: it reads the list at start. Existing "
        "roles and files are not touched; a role already in DIR is refused.",
    )
    add.add_argument("directory", metavar="DIR", help="a folder written by `axisflow security init`")
    add.add_argument(
        "--roles",
        required=True,
        metavar="R1,R2,…",
        help="the new roles: planner, bridge, recorder, adapter, or KIND-NAME (e.g. recorder-laptop), "
        "KIND@AXIS for one limited to an axis (e.g. bridge@a4)",
    )
    add.add_argument(
        "--days",
        type=positive_int,
        default=DEFAULT_DAYS,
        metavar="N",
        help=f"validity of the new certificates [days] (default {DEFAULT_DAYS}; never past the CA's)",
    )
    add.set_defaults(func=run_add)


def run_init(args: argparse.Namespace) -> int:
    from ..deploy.security import init_security

    plan = SecurityPlan(
        directory=Path(args.directory),
        prefix=args.prefix,
        roles=parse_roles(args.roles),
        days=args.days,
        host=args.host,
        port=args.listen_port,
        listen_host=args.listen_host,
        force=args.force,
    )
    print(init_security(plan).format())
    return 0


def run_add(args: argparse.Namespace) -> int:
    from ..deploy.security import add_roles

    print(add_roles(Path(args.directory), parse_roles(args.roles), args.days).format())
    return 0
