"""The certificate authority and the certificates it issues.

Keys are ECDSA P-256; certificates are X.509 v3 signed with SHA-256. The CA may sign certificates
only (``path_length=0``); the router's certificate is for server authentication and names its
address (subject alternative name, which every client verifies), a role's is for client
authentication. Every certificate is valid from :data:`~.validity.CLOCK_SKEW` before it is issued
(hosts whose clocks lag a little) for a number of days (:mod:`.validity`), never past the CA's end.
"""

from __future__ import annotations

import datetime as dt
import ipaddress
from dataclasses import dataclass
from pathlib import Path

from cryptography import x509
from cryptography.hazmat.primitives import hashes, serialization
from cryptography.hazmat.primitives.asymmetric import ec
from cryptography.x509.oid import ExtendedKeyUsageOID, NameOID

from .errors import SecurityError
from .roles import ROUTER


@dataclass(frozen=True)
class Issued:
    """A private key and its certificate."""

    key: ec.EllipticCurvePrivateKey
    certificate: x509.Certificate

    @property
    def key_pem(self) -> bytes:
        """the private key, PEM (PKCS #8, unencrypted: the file's mode protects it)"""
        return self.key.private_bytes(
            serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8, serialization.NoEncryption()
        )

    @property
    def certificate_pem(self) -> bytes:
        return self.certificate.public_bytes(serialization.Encoding.PEM)


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


def issue_ca(name: str, not_before: dt.datetime, not_after: dt.datetime) -> Issued:
    """A self-signed CA named ``name`` that signs certificates only."""
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
    return Issued(key, cert)


def issue_leaf(
    ca: Issued,
    common_name: str,
    usage: x509.ObjectIdentifier,
    not_before: dt.datetime,
    not_after: dt.datetime,
    san: list[x509.GeneralName],
) -> Issued:
    """A new key and its certificate (CN = ``common_name``, extended key usage ``usage``, subject
    alternative names ``san`` if any) signed by ``ca``."""
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
    return Issued(key, builder.sign(ca.key, hashes.SHA256()))


def issue_router(ca: Issued, host: str, not_before: dt.datetime, not_after: dt.datetime) -> Issued:
    """The router's certificate: server authentication, ``host`` (an IP or a DNS name) as its SAN."""
    return issue_leaf(ca, ROUTER, ExtendedKeyUsageOID.SERVER_AUTH, not_before, not_after, [_san_of(host)])


def issue_role(ca: Issued, role: str, not_before: dt.datetime, not_after: dt.datetime) -> Issued:
    """A role's certificate: client authentication, CN = the role's name."""
    return issue_leaf(ca, role, ExtendedKeyUsageOID.CLIENT_AUTH, not_before, not_after, [])


def _san_of(host: str) -> x509.GeneralName:
    try:
        return x509.IPAddress(ipaddress.ip_address(host))
    except ValueError:
        return x509.DNSName(host)


def load_ca(directory: Path) -> Issued:
    """The CA of a folder (``ca.pem`` and ``ca.key``), checked to be a matching pair."""
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
    return Issued(key, cert)
