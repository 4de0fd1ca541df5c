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
to their folder (:func:`axisflow.acquisition.bus.session.build_config` resolves them there), so a
role's four files (``ca.pem``, ``<role>.pem``, ``<role>.key``, ``<role>.json5``) can be copied
together to the host that runs it. Keys are ECDSA P-256; certificates are X.509 v3 signed with
SHA-256, valid from 5 min before issue (clock skew) for ``days`` days, the CA for as long as them.

``add_roles(DIR, ("recorder-laptop",))`` issues more identities with the folder's CA (never valid
longer than it), writes their files beside the others and rewrites ``router.json5`` with an ACL that
admits them too; the router reads its ACL at start, so it must be restarted.
"""

from __future__ import annotations

import datetime as dt
import ipaddress
import json
import os
import re
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

from cryptography import x509
from cryptography.hazmat.primitives import hashes, serialization
from cryptography.hazmat.primitives.asymmetric import ec
from cryptography.x509.oid import ExtendedKeyUsageOID, NameOID

from .acquisition.bus.session import check_host
from .acquisition.wire.keys import DEFAULT_PREFIX, all_keys
from .model import AxisflowError
from .model.files import check_writable

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
        Grant("ingress", ("declare_subscriber",), ("*/event", "*/state", "*/setpoint", "*/drive")),
        Grant("ingress", ("declare_liveliness_subscriber", "liveliness_query"), ("*/alive",)),
        Grant("egress", ("put",), ("*/event", "*/state", "*/setpoint", "*/drive")),
        Grant("egress", ("liveliness_token",), ("*/alive",)),
        Grant("egress", ("declare_subscriber",), ("**",)),  # who listens to its moves (matching)
    ),
    # the bridge publishes telemetry and events and its token; it reads moves, stops, sender tokens
    "bridge": (
        Grant("ingress", ("put",), ("*/state", "*/setpoint", "*/event", "*/drive")),
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


def _check_roles(roles: tuple[str, ...]) -> None:
    """At least one role, each of a known kind, none twice; else a :class:`SecurityArgumentError`."""
    if not roles:
        raise SecurityArgumentError("no role given: at least one of planner, bridge, recorder")
    for name in roles:
        role_kind(name)
    if len(set(roles)) != len(roles):
        raise SecurityArgumentError(f"roles {', '.join(roles)} name a role more than once")


def _check_days(days: int) -> None:
    if not 1 <= days <= MAX_DAYS:
        raise SecurityArgumentError(f"validity = {days} days must be in 1…{MAX_DAYS} days")


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
        _check_roles(self.roles)
        _check_days(self.days)
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
    return _client_config(plan.endpoint, role)


def _client_config(endpoint: str, role: str) -> dict[str, object]:
    role_kind(role)
    return {
        "mode": "client",
        "connect": {"endpoints": [endpoint]},
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
        lines += _file_lines(self.files)
        d = self.directory
        lines.append("next (each in its own terminal or service, the router first; see docs/security.md):")
        lines.append(f"  axisflow router --zenoh-config {d / 'router.json5'}")
        lines += [_how_to_run(d, role) for role in self.plan.roles]
        return "\n".join(lines)


def _file_lines(files: list[WrittenFile]) -> list[str]:
    return [f"  {oct(f.mode)[2:]:>4}  {f.path.name:<18} {f.what}" for f in files]


def _how_to_run(directory: Path, role: str) -> str:
    config = directory / f"{role}.json5"
    return {
        "planner": f"  {role}: open_session(ZenohOptions(config_file=Path('{config}')))",
        "bridge": f"  axisflow bridge --sim --zenoh-config {config}",
        "recorder": f"  axisflow record -o session.mcap --zenoh-config {config}",
    }[role_kind(role)]


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

    def merge(self) -> None:
        """Rename the files one by one into the existing target, in the order written (the last one
        last); on failure the ones already moved are removed again."""
        moved: list[Path] = []
        try:
            for f in self.files:
                os.replace(self.tmp / f.path.name, f.path)
                moved.append(f.path)
        except BaseException:
            for path in moved:
                path.unlink(missing_ok=True)
            raise
        finally:
            self.discard()

    def discard(self) -> None:
        shutil.rmtree(self.tmp, ignore_errors=True)

    @contextmanager
    def discarded_on_error(self, what: str) -> Iterator[None]:
        """Discard everything written on any error in the block; an :class:`OSError` becomes a
        :class:`SecurityError` saying ``cannot write WHAT``."""
        try:
            yield
        except BaseException as exc:
            self.discard()
            if isinstance(exc, OSError):
                raise SecurityError(f"cannot write {what}: {exc.strerror or exc}") from None
            raise


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
    check_writable(target.parent, f"cannot write into {target.parent}")
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
    with folder.discarded_on_error(str(target)):
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
    return SecurityInit(target, plan, not_after, folder.files)


def _write_identity(
    folder: _Folder, name: str, issued: _Issued, config: dict[str, object], plan: SecurityPlan, stamp: str
) -> None:
    who = "the router (run: axisflow router --zenoh-config FILE)" if name == ROUTER else f"role {name}"
    header = (
        f"Zenoh configuration of {who}, written by `axisflow security init` on {stamp}.\n"
        f"Router {plan.endpoint}; keys {plan.prefix}/**. Paths are relative to this file's folder\n"
        "(axisflow resolves them there; for zenohd, start it in this folder)."
    )
    _write_files(folder, name, issued, config, header)


def _write_files(folder: _Folder, name: str, issued: _Issued, config: dict[str, object], header: str) -> None:
    """An identity's certificate, private key and Zenoh configuration (checked to load in zenoh)."""
    folder.write(f"{name}.pem", _pem_cert(issued.certificate), PUBLIC_MODE, f"certificate CN={name}")
    folder.write(f"{name}.key", _pem_key(issued.key), PRIVATE_MODE, f"private key of {name}")
    text = _json5(config, header)
    _check_zenoh_config(f"{name}.json5", text)
    folder.write(f"{name}.json5", text.encode(), PUBLIC_MODE, f"zenoh config of {name}")


# ---- adding identities to a folder ----------------------------------------------------------------
@dataclass
class SecurityAdd:
    """What :func:`add_roles` wrote."""

    directory: Path
    added: tuple[str, ...]
    roles: tuple[str, ...]
    """every role the router admits now (the folder's and the added ones)"""
    not_after: dt.datetime
    """end of validity of the added certificates (UTC; never after the CA's)"""
    files: list[WrittenFile] = field(default_factory=list)

    def format(self) -> str:
        d = self.directory
        lines = [
            f"added {', '.join(self.added)} to {d} ({len(self.files)} files; certificates valid until "
            f"{self.not_after:%Y-%m-%d %H:%M} UTC); router.json5 now admits {', '.join(self.roles)}",
        ]
        lines += _file_lines(self.files)
        lines.append("next: restart the router (it reads its access-control list at start):")
        lines.append(f"  axisflow router --zenoh-config {d / 'router.json5'}")
        lines += [_how_to_run(d, role) for role in self.added]
        return "\n".join(lines)


def _read_json5(path: Path) -> dict:
    """A ``.json5`` file this module wrote (``//`` comment lines, then JSON)."""
    try:
        text = path.read_text()
    except FileNotFoundError:
        raise SecurityError(f"{path} is missing: not a folder written by `axisflow security init`") from None
    except OSError as exc:
        raise SecurityError(f"cannot read {path}: {exc.strerror}") from None
    body = "".join(line for line in text.splitlines(keepends=True) if not line.lstrip().startswith("//"))
    try:
        return json.loads(body)
    except json.JSONDecodeError as exc:
        raise SecurityError(
            f"{path} is not the JSON that `axisflow security init` writes (line {exc.lineno}: {exc.msg}): "
            "edited by hand? not rewriting it"
        ) from None


def _folder_acl(router: dict, path: Path) -> tuple[str, tuple[str, ...]]:
    """The prefix and roles of a router configuration's ACL, checked to be exactly what
    :func:`acl_config` writes for them (a hand-edited list is not rewritten)."""
    try:
        acl = router["access_control"]
        roles = tuple(str(subject["id"]) for subject in acl["subjects"])
        first = roles[0]
        key = acl["rules"][0]["key_exprs"][0]
        prefix = key[: -len(ROLE_GRANTS[role_kind(first)][0].suffixes[0]) - 1]
        same = acl == acl_config(prefix, roles)
    except (KeyError, IndexError, TypeError, ValueError, SecurityError):
        same = False
    if not same:
        raise SecurityError(
            f"the access-control list in {path} is not one `axisflow security init` wrote: edited by "
            "hand? not rewriting it (add the role there by hand, or rotate with `security init`)"
        )
    return prefix, roles


def _load_ca(directory: Path) -> _Issued:
    try:
        cert = x509.load_pem_x509_certificate((directory / "ca.pem").read_bytes())
        key = serialization.load_pem_private_key((directory / "ca.key").read_bytes(), password=None)
    except FileNotFoundError as exc:
        raise SecurityError(
            f"{exc.filename} is missing: adding a role needs the CA's certificate and private key (bring "
            "ca.key back from where it is kept offline)"
        ) from None
    except (OSError, ValueError, TypeError) as exc:
        raise SecurityError(f"cannot load the CA of {directory}: {exc}") from None
    if not isinstance(key, ec.EllipticCurvePrivateKey) or key.public_key() != cert.public_key():
        raise SecurityError(f"{directory / 'ca.key'} is not the private key of {directory / 'ca.pem'}")
    return _Issued(key, cert)


def add_roles(
    directory: Path, roles: tuple[str, ...], days: int = DEFAULT_DAYS, now: dt.datetime | None = None
) -> SecurityAdd:
    """Issue certificates for more ``roles`` with the CA of a folder of :func:`init_security`, write
    their files, and rewrite its ``router.json5`` so that the ACL admits them too (the router reads it
    at start: restart it). The folder's other files are not touched; nothing is written on error."""
    d = Path(directory).absolute()
    if not d.is_dir():
        raise SecurityError(
            f"{directory} does not exist or is not a folder: `security add` needs a folder written by "
            "`axisflow security init`"
        )
    _check_days(days)
    _check_roles(roles)
    router = _read_json5(d / f"{ROUTER}.json5")
    prefix, existing = _folder_acl(router, d / f"{ROUTER}.json5")
    for name in roles:
        if name in existing or (d / f"{name}.pem").exists() or (d / f"{name}.key").exists():
            raise SecurityError(
                f"role {name!r} is already in {directory}: not reissuing it (a new name of its kind, e.g. "
                f"{role_kind(name)}-2, or rotate with `security init` to replace a key)"
            )
    endpoint = _client_config_endpoint(d / f"{existing[0]}.json5")
    ca = _load_ca(d)
    issued_at = now or dt.datetime.now(dt.UTC)
    ca_end = ca.certificate.not_valid_after_utc
    if ca_end <= issued_at:
        raise SecurityError(f"the CA of {directory} expired on {ca_end:%Y-%m-%d %H:%M} UTC: rotate with init")
    not_after = min(issued_at + dt.timedelta(days=days), ca_end)
    stamp = f"{issued_at:%Y-%m-%d %H:%M} UTC"
    everyone = existing + tuple(roles)
    router["access_control"] = acl_config(prefix, everyone)
    try:
        folder = _Folder(d)
    except OSError as exc:
        raise SecurityError(f"cannot create a temporary folder in {d.parent}: {exc.strerror}") from None
    with folder.discarded_on_error(f"into {d}"):
        for name in roles:
            leaf = _issue_leaf(
                ca, name, ExtendedKeyUsageOID.CLIENT_AUTH, issued_at - CLOCK_SKEW, not_after, []
            )
            header = (
                f"Zenoh configuration of role {name}, written by `axisflow security add` on {stamp}.\n"
                f"Router {endpoint}; keys {prefix}/**. Paths are relative to this file's folder."
            )
            _write_files(folder, name, leaf, _client_config(endpoint, name), header)
        header = (
            f"Zenoh configuration of the router (run: axisflow router --zenoh-config FILE), rewritten by\n"
            f"`axisflow security add` on {stamp} (roles {', '.join(everyone)}); keys {prefix}/**.\n"
            "Paths are relative to this file's folder (for zenohd, start it in this folder)."
        )
        text = _json5(router, header)
        _check_zenoh_config(f"{ROUTER}.json5", text)
        folder.write(f"{ROUTER}.json5", text.encode(), PUBLIC_MODE, f"zenoh config of {ROUTER} (rewritten)")
        folder.merge()
    return SecurityAdd(d, tuple(roles), everyone, not_after, folder.files)


def _client_config_endpoint(path: Path) -> str:
    try:
        return str(_read_json5(path)["connect"]["endpoints"][0])
    except (KeyError, IndexError, TypeError):
        raise SecurityError(f"{path} names no router endpoint: not a role file of `security init`") from None
