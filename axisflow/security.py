"""Who may command an axis: a certificate authority, one certificate per role, and the Zenoh
configuration files of a secure deployment (mutual TLS plus a default-deny access-control list).

Topology: one Zenoh **router** listens on ``tls/HOST:PORT`` and is the only process that listens;
every role (planner, bridge, recorder) runs as a Zenoh **client** that connects to it. Both sides
present a certificate of the same private CA (mTLS: ``enable_mtls``); the router admits only links
whose certificate chains to that CA and applies its access-control list (ACL) to every message on
each link, keyed on the common name (CN) of the certificate — the role. The ACL is default-deny;
:data:`ROLE_GRANTS` lists everything a role may do (``ingress``: what the role sends to the router,
``egress``: what the router sends to the role).

``init_security(SecurityPlan(directory=DIR))`` writes, all at once (a temporary folder renamed into
place; nothing is left half-written on error)::

    DIR/ca.pem              the CA certificate: every host needs it
    DIR/ca.key              the CA private key (0600): keep it offline, no process needs it
    DIR/router.{pem,key,json5}
    DIR/<role>.{pem,key,json5}   per role (private keys 0600)

The ``.json5`` files are Zenoh configurations for ``--zenoh-config``; the paths in them are relative
to their folder (:func:`axisflow.acquisition.zenoh_config.build_config` resolves them there), so a
role's four files (``ca.pem``, ``<role>.pem``, ``<role>.key``, ``<role>.json5``) can be copied
together to the host that runs it. Keys are ECDSA P-256; certificates are X.509 v3 signed with
SHA-256, valid from 5 min before issue (clock skew) for ``days`` days, the CA for as long as them.
"""

from __future__ import annotations

import datetime as dt
import ipaddress
import json
import os
import re
import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from cryptography import x509
from cryptography.hazmat.primitives import hashes, serialization
from cryptography.hazmat.primitives.asymmetric import ec
from cryptography.x509.oid import ExtendedKeyUsageOID, NameOID

from .acquisition.keys import DEFAULT_PREFIX, all_keys
from .acquisition.zenoh_config import check_host
from .model import AxisflowError

ROUTER = "router"
"""the router's certificate common name and file stem (reserved: not a role name)"""
DEFAULT_PORT = 7448
"""the router's TLS port: next to 7447, which the embedded default (plain TCP peers) uses"""
DEFAULT_DAYS = 365
MAX_DAYS = 3650
DEFAULT_ROLES = ("planner", "bridge", "recorder")
DEFAULT_HOST = "127.0.0.1"
CLOCK_SKEW = dt.timedelta(minutes=5)
"""certificates are valid from this long before they are issued (hosts whose clocks lag a little)"""
PRIVATE_MODE = 0o600
PUBLIC_MODE = 0o644
DIR_MODE = 0o700


class SecurityError(AxisflowError):
    """Root of the errors of :mod:`axisflow.security`."""


class SecurityArgumentError(SecurityError, ValueError):
    """A role name, validity, host or port given to ``security init`` is invalid."""


@dataclass(frozen=True)
class Grant:
    """One ACL rule of a role: ``messages`` allowed on ``<prefix>/<suffix>`` keys in one direction.

    ``flow`` is seen from the router: ``ingress`` = sent by the role, ``egress`` = delivered to it.
    Zenoh allows a message when a granted key expression *includes* the message's key expression.
    """

    flow: str
    messages: tuple[str, ...]
    suffixes: tuple[str, ...]


ROLE_GRANTS: dict[str, tuple[Grant, ...]] = {
    # the planner commands: moves and quick stops, its sender token; it reads what MoveSender and
    # AxisState read (events, state, setpoint, the bridge's token)
    "planner": (
        Grant("ingress", ("put",), ("*/trajectory", "*/stop")),
        Grant("ingress", ("liveliness_token",), ("*/sender/*",)),
        Grant("ingress", ("declare_subscriber",), ("*/event", "*/state", "*/setpoint")),
        Grant("ingress", ("declare_liveliness_subscriber", "liveliness_query"), ("*/alive",)),
        Grant("egress", ("put",), ("*/event", "*/state", "*/setpoint")),
        Grant("egress", ("liveliness_token",), ("*/alive",)),
        Grant("egress", ("declare_subscriber",), ("**",)),  # who listens to its moves (matching)
    ),
    # the bridge publishes telemetry and events and its token; it reads moves, stops, sender tokens
    "bridge": (
        Grant("ingress", ("put",), ("*/state", "*/setpoint", "*/event")),
        Grant("ingress", ("liveliness_token",), ("*/alive",)),
        Grant("ingress", ("declare_subscriber",), ("*/trajectory", "*/stop")),
        Grant("ingress", ("declare_liveliness_subscriber", "liveliness_query"), ("*/sender/*",)),
        Grant("egress", ("put",), ("*/trajectory", "*/stop")),
        Grant("egress", ("liveliness_token",), ("*/sender/*",)),
        Grant("egress", ("declare_subscriber",), ("**",)),  # who listens to its telemetry
    ),
    # the recorder only listens: every key and token under the prefix, never a put
    "recorder": (
        Grant("ingress", ("declare_subscriber",), ("**",)),
        Grant("ingress", ("declare_liveliness_subscriber", "liveliness_query"), ("**",)),
        Grant("egress", ("put",), ("**",)),
        Grant("egress", ("liveliness_token",), ("**",)),
    ),
}
"""everything each kind of role may do; anything else is denied (``default_permission: deny``)"""

_ROLE_NAME = re.compile(r"^(?P<kind>[a-z]+)(?:-(?P<suffix>[a-z0-9][a-z0-9_-]{0,30}))?$")


def role_kind(name: str) -> str:
    """The kind of a role name: ``planner``, ``bridge``, ``recorder``, or one of them followed by
    ``-NAME`` (``planner-cell2``: another planner identity with its own certificate)."""
    m = _ROLE_NAME.match(name)
    if m is None or m["kind"] not in ROLE_GRANTS:
        raise SecurityArgumentError(
            f"role {name!r} is not one of {', '.join(ROLE_GRANTS)} (or one of them followed by -NAME of "
            "lower-case letters, digits, '-' or '_', e.g. planner-cell2)"
        )
    return m["kind"]


def parse_roles(text: str) -> tuple[str, ...]:
    """``planner,bridge,recorder`` → the role names, checked (known kind, no duplicate)."""
    names = tuple(part.strip() for part in text.split(","))
    if not any(names):
        raise SecurityArgumentError(f"--roles {text!r} names no role (e.g. {','.join(DEFAULT_ROLES)})")
    for name in names:
        role_kind(name)
    duplicates = sorted({n for n in names if names.count(n) > 1})
    if duplicates:
        raise SecurityArgumentError(f"--roles {text!r} names {', '.join(duplicates)} more than once")
    return names


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
        if not self.roles:
            raise SecurityArgumentError("no role given: at least one of planner, bridge, recorder")
        for name in self.roles:
            role_kind(name)
        if len(set(self.roles)) != len(self.roles):
            raise SecurityArgumentError(f"roles {', '.join(self.roles)} name a role more than once")
        if not 1 <= self.days <= MAX_DAYS:
            raise SecurityArgumentError(f"validity = {self.days} days must be in 1…{MAX_DAYS} days")
        if not 1 <= self.port <= 65535:
            raise SecurityArgumentError(f"router port = {self.port} must be in 1…65535")
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


# ---- the access-control list ----------------------------------------------------------------------
def acl_config(prefix: str, roles: tuple[str, ...]) -> dict[str, object]:
    """The router's ``access_control`` section: default deny, one subject per role (its certificate's
    common name), the role's kind's :data:`ROLE_GRANTS` as allow rules under ``prefix``."""
    all_keys(prefix)
    rules: list[dict[str, object]] = []
    subjects: list[dict[str, object]] = []
    policies: list[dict[str, object]] = []
    for role in roles:
        rule_ids = []
        for i, grant in enumerate(ROLE_GRANTS[role_kind(role)], start=1):
            rule_id = f"{role}-{i}"
            rule_ids.append(rule_id)
            rules.append(
                {
                    "id": rule_id,
                    "permission": "allow",
                    "flows": [grant.flow],
                    "messages": list(grant.messages),
                    "key_exprs": [f"{prefix}/{suffix}" for suffix in grant.suffixes],
                }
            )
        subjects.append({"id": role, "cert_common_names": [role]})
        policies.append({"id": role, "rules": rule_ids, "subjects": [role]})
    return {
        "enabled": True,
        "default_permission": "deny",
        "rules": rules,
        "subjects": subjects,
        "policies": policies,
    }


# ---- the Zenoh configuration files ----------------------------------------------------------------
def router_config(plan: SecurityPlan) -> dict[str, object]:
    """The router's Zenoh configuration: TLS only, mTLS, the ACL (paths relative to its folder)."""
    return {
        "mode": "router",
        "listen": {"endpoints": [plan.listen_endpoint], "exit_on_failure": True},
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
        "access_control": acl_config(plan.prefix, plan.roles),
    }


def role_config(plan: SecurityPlan, role: str) -> dict[str, object]:
    """A role's Zenoh configuration: a client of the router over TLS with its own certificate."""
    role_kind(role)
    return {
        "mode": "client",
        "connect": {"endpoints": [plan.endpoint]},
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


def _json5(config: dict[str, object], header: str) -> str:
    comment = "".join(f"// {line}\n" for line in header.splitlines())
    return comment + json.dumps(config, indent=2) + "\n"


# ---- certificates ---------------------------------------------------------------------------------
def _new_key() -> ec.EllipticCurvePrivateKey:
    return ec.generate_private_key(ec.SECP256R1())


def _key_usage(*, sign_certificates: bool) -> x509.KeyUsage:
    return x509.KeyUsage(
        digital_signature=not sign_certificates,
        content_commitment=False,
        key_encipherment=False,
        data_encipherment=False,
        key_agreement=False,
        key_cert_sign=sign_certificates,
        crl_sign=sign_certificates,
        encipher_only=False,
        decipher_only=False,
    )


@dataclass(frozen=True)
class _Issued:
    key: ec.EllipticCurvePrivateKey
    certificate: x509.Certificate


def _issue_ca(name: str, not_before: dt.datetime, not_after: dt.datetime) -> _Issued:
    key = _new_key()
    subject = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, name)])
    cert = (
        x509.CertificateBuilder()
        .subject_name(subject)
        .issuer_name(subject)
        .public_key(key.public_key())
        .serial_number(x509.random_serial_number())
        .not_valid_before(not_before)
        .not_valid_after(not_after)
        .add_extension(x509.BasicConstraints(ca=True, path_length=0), critical=True)
        .add_extension(_key_usage(sign_certificates=True), critical=True)
        .add_extension(x509.SubjectKeyIdentifier.from_public_key(key.public_key()), critical=False)
        .sign(key, hashes.SHA256())
    )
    return _Issued(key, cert)


def _issue_leaf(
    ca: _Issued,
    common_name: str,
    usage: x509.ObjectIdentifier,
    not_before: dt.datetime,
    not_after: dt.datetime,
    san: list[x509.GeneralName],
) -> _Issued:
    key = _new_key()
    builder = (
        x509.CertificateBuilder()
        .subject_name(x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, common_name)]))
        .issuer_name(ca.certificate.subject)
        .public_key(key.public_key())
        .serial_number(x509.random_serial_number())
        .not_valid_before(not_before)
        .not_valid_after(not_after)
        .add_extension(x509.BasicConstraints(ca=False, path_length=None), critical=True)
        .add_extension(_key_usage(sign_certificates=False), critical=True)
        .add_extension(x509.ExtendedKeyUsage([usage]), critical=False)
        .add_extension(x509.SubjectKeyIdentifier.from_public_key(key.public_key()), critical=False)
        .add_extension(
            x509.AuthorityKeyIdentifier.from_issuer_public_key(ca.key.public_key()), critical=False
        )
    )
    if san:
        builder = builder.add_extension(x509.SubjectAlternativeName(san), critical=False)
    return _Issued(key, builder.sign(ca.key, hashes.SHA256()))


def _san_of(host: str) -> x509.GeneralName:
    try:
        return x509.IPAddress(ipaddress.ip_address(host))
    except ValueError:
        return x509.DNSName(host)


# ---- writing the folder ---------------------------------------------------------------------------
@dataclass(frozen=True)
class WrittenFile:
    path: Path
    mode: int
    """permission bits, e.g. 0o600"""
    what: str


@dataclass
class SecurityInit:
    """What :func:`init_security` wrote."""

    directory: Path
    plan: SecurityPlan
    not_after: dt.datetime
    """end of validity of every certificate (UTC)"""
    files: list[WrittenFile] = field(default_factory=list)

    def config_of(self, role: str) -> Path:
        """The Zenoh configuration file of ``role`` (or of the router: ``"router"``)."""
        return self.directory / f"{role}.json5"

    def format(self) -> str:
        lines = [
            f"wrote {len(self.files)} files to {self.directory} (certificates valid until "
            f"{self.not_after:%Y-%m-%d %H:%M} UTC; router {self.plan.listen_endpoint}, "
            f"roles {', '.join(self.plan.roles)}, keys {self.plan.prefix}/**)",
        ]
        lines += [f"  {oct(f.mode)[2:]:>4}  {f.path.name:<18} {f.what}" for f in self.files]
        d = self.directory
        lines.append("next (each in its own terminal or service, the router first; see docs/security.md):")
        lines.append(f"  axisflow router --zenoh-config {d / 'router.json5'}")
        for role in self.plan.roles:
            config = d / f"{role}.json5"
            lines.append(
                {
                    "planner": f"  planner: open_session(ZenohOptions(config_file=Path('{config}')))",
                    "bridge": f"  axisflow bridge --sim --zenoh-config {config}",
                    "recorder": f"  axisflow record -o session.mcap --zenoh-config {config}",
                }[role_kind(role)]
            )
        return "\n".join(lines)


class _Folder:
    """Files written into a private temporary folder beside the target, renamed into place at the end."""

    def __init__(self, target: Path) -> None:
        self.target = target
        self.tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=target.parent))
        self.files: list[WrittenFile] = []

    def write(self, name: str, data: bytes, mode: int, what: str) -> None:
        path = self.tmp / name
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, mode)
        with os.fdopen(fd, "wb") as fh:
            os.fchmod(fh.fileno(), mode)  # exact, whatever the umask
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        self.files.append(WrittenFile(self.target / name, mode, what))

    def commit(self) -> None:
        os.chmod(self.tmp, DIR_MODE)
        if not self.target.exists():
            os.replace(self.tmp, self.target)
            return
        old = Path(tempfile.mkdtemp(prefix=f".{self.target.name}.old.", dir=self.target.parent))
        os.replace(self.target, old / "replaced")
        try:
            os.replace(self.tmp, self.target)
        except BaseException:
            os.replace(old / "replaced", self.target)  # put the old folder back
            raise
        finally:
            shutil.rmtree(old, ignore_errors=True)

    def discard(self) -> None:
        shutil.rmtree(self.tmp, ignore_errors=True)


def _check_target(plan: SecurityPlan) -> Path:
    target = Path(plan.directory).absolute()
    if target.exists() or target.is_symlink():
        if not target.is_dir() or target.is_symlink():
            raise SecurityError(f"{plan.directory} exists and is not a directory: not replacing it")
        if not plan.force:
            count = sum(1 for _ in target.iterdir())
            raise SecurityError(
                f"{plan.directory} exists ({count} entries): not overwriting its keys; pass --force to "
                "replace it, or choose a new folder"
            )
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise SecurityError(f"cannot create {target.parent}: {exc.strerror}") from None
    if not os.access(target.parent, os.W_OK | os.X_OK):
        raise SecurityError(f"cannot write into {target.parent}: permission denied")
    return target


def _pem_key(key: ec.EllipticCurvePrivateKey) -> bytes:
    return key.private_bytes(
        serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8, serialization.NoEncryption()
    )


def _pem_cert(cert: x509.Certificate) -> bytes:
    return cert.public_bytes(serialization.Encoding.PEM)


def _check_zenoh_config(name: str, text: str) -> None:
    import zenoh

    try:
        zenoh.Config.from_json5(text)
    except zenoh.ZError as exc:  # a bug of ours, never the user's input: say so plainly
        raise SecurityError(f"generated {name} is not a valid zenoh configuration: {exc}") from None


def init_security(plan: SecurityPlan, now: dt.datetime | None = None) -> SecurityInit:
    """Generate the CA, the router's and each role's certificate and key, and their Zenoh files."""
    target = _check_target(plan)
    issued_at = now or dt.datetime.now(dt.UTC)
    not_before = issued_at - CLOCK_SKEW
    not_after = issued_at + dt.timedelta(days=plan.days)
    stamp = f"{issued_at:%Y-%m-%d %H:%M} UTC"
    try:
        folder = _Folder(target)
    except OSError as exc:
        raise SecurityError(f"cannot create a temporary folder in {target.parent}: {exc.strerror}") from None
    try:
        ca = _issue_ca(f"axisflow CA {plan.prefix} {stamp}", not_before, not_after)
        folder.write("ca.pem", _pem_cert(ca.certificate), PUBLIC_MODE, "CA certificate (every host)")
        folder.write("ca.key", _pem_key(ca.key), PRIVATE_MODE, "CA private key (keep offline)")
        router = _issue_leaf(
            ca, ROUTER, ExtendedKeyUsageOID.SERVER_AUTH, not_before, not_after, [_san_of(plan.host)]
        )
        _write_identity(folder, ROUTER, router, router_config(plan), plan, stamp)
        for role in plan.roles:
            issued = _issue_leaf(ca, role, ExtendedKeyUsageOID.CLIENT_AUTH, not_before, not_after, [])
            _write_identity(folder, role, issued, role_config(plan, role), plan, stamp)
        folder.commit()
    except BaseException as exc:
        folder.discard()
        if isinstance(exc, OSError):
            raise SecurityError(f"cannot write {target}: {exc.strerror or exc}") from None
        raise
    return SecurityInit(target, plan, not_after, folder.files)


def _write_identity(
    folder: _Folder, name: str, issued: _Issued, config: dict[str, object], plan: SecurityPlan, stamp: str
) -> None:
    folder.write(f"{name}.pem", _pem_cert(issued.certificate), PUBLIC_MODE, f"certificate CN={name}")
    folder.write(f"{name}.key", _pem_key(issued.key), PRIVATE_MODE, f"private key of {name}")
    who = "the router (run: axisflow router --zenoh-config FILE)" if name == ROUTER else f"role {name}"
    header = (
        f"Zenoh configuration of {who}, written by `axisflow security init` on {stamp}.\n"
        f"Router {plan.endpoint}; keys {plan.prefix}/**. Paths are relative to this file's folder\n"
        "(axisflow resolves them there; for zenohd, start it in this folder)."
    )
    text = _json5(config, header)
    _check_zenoh_config(f"{name}.json5", text)
    folder.write(f"{name}.json5", text.encode(), PUBLIC_MODE, f"zenoh config of {name}")
