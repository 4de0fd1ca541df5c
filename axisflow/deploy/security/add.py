"""``security add``: more identities issued with the CA of a folder of ``security init``, and the
folder's router configuration rewritten so that its access-control list admits them too (the router
reads it at start: restart it). The folder's other files are not touched; nothing is written on
error."""

from __future__ import annotations

import datetime as dt
from dataclasses import dataclass, field
from pathlib import Path

from ...acquisition.wire.keys import DEFAULT_PREFIX
from .access_control import acl_config, acl_roles
from .certificates import issue_role, load_ca
from .errors import SecurityError
from .folder import PUBLIC_MODE, FolderWriter, WrittenFile, file_lines
from .init import write_identity
from .roles import ROUTER, check_roles, how_to_run, role_kind
from .validity import CLOCK_SKEW, DEFAULT_DAYS, check_days
from .zenoh_files import check_loads_in_zenoh, client_config, client_endpoint, read_json5, to_json5


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
    prefix: str = DEFAULT_PREFIX
    """the key prefix of the folder's access list"""

    def format(self) -> str:
        d = self.directory
        lines = [
            f"added {', '.join(self.added)} to {d} ({len(self.files)} files; certificates valid until "
            f"{self.not_after:%Y-%m-%d %H:%M} UTC); router.json5 now admits {', '.join(self.roles)}",
        ]
        lines += file_lines(self.files)
        lines.append("next: restart the router (it reads its access-control list at start):")
        lines.append(f"  axisflow router --zenoh-config {d / 'router.json5'}")
        lines += [how_to_run(d, role, self.prefix) for role in self.added]
        return "\n".join(lines)


def add_roles(
    directory: Path, roles: tuple[str, ...], days: int = DEFAULT_DAYS, now: dt.datetime | None = None
) -> SecurityAdd:
    """Issue certificates for more ``roles`` with the CA of a folder of ``security init``, write
    their files, and rewrite its ``router.json5`` so that the ACL admits them too."""
    d = Path(directory).absolute()
    if not d.is_dir():
        raise SecurityError(
            f"{directory} does not exist or is not a folder: `security add` needs a folder written by "
            "`axisflow security init`"
        )
    check_days(days)
    check_roles(roles)
    router_file = d / f"{ROUTER}.json5"
    router = read_json5(router_file)
    prefix, existing = acl_roles(router.get("access_control"), router_file)
    for name in roles:
        if name in existing or (d / f"{name}.pem").exists() or (d / f"{name}.key").exists():
            raise SecurityError(
                f"role {name!r} is already in {directory}: not reissuing it (a new name of its kind, e.g. "
                f"{role_kind(name)}-2, or rotate with `security init` to replace a key)"
            )
    endpoint = client_endpoint(d / f"{existing[0]}.json5")
    ca = load_ca(d)
    issued_at = now or dt.datetime.now(dt.UTC)
    ca_end = ca.certificate.not_valid_after_utc
    if ca_end <= issued_at:
        raise SecurityError(f"the CA of {directory} expired on {ca_end:%Y-%m-%d %H:%M} UTC: rotate with init")
    not_after = min(issued_at + dt.timedelta(days=days), ca_end)
    stamp = f"{issued_at:%Y-%m-%d %H:%M} UTC"
    everyone = existing + tuple(roles)
    router["access_control"] = acl_config(prefix, everyone)
    folder = FolderWriter(d)
    with folder.discarded_on_error(f"into {d}"):
        for name in roles:
            leaf = issue_role(ca, name, issued_at - CLOCK_SKEW, not_after)
            header = (
                f"Zenoh configuration of role {name}, written by `axisflow security add` on {stamp}.\n"
                f"Router {endpoint}; keys {prefix}/**. Paths are relative to this file's folder."
            )
            write_identity(folder, name, leaf, client_config(endpoint, name), header)
        header = (
            f"Zenoh configuration of the router (run: axisflow router --zenoh-config FILE), rewritten by\n"
            f"`axisflow security add` on {stamp} (roles {', '.join(everyone)}); keys {prefix}/**.\n"
            "Paths are relative to this file's folder (for zenohd, start it in this folder)."
        )
        text = to_json5(router, header)
        check_loads_in_zenoh(f"{ROUTER}.json5", text)
        folder.write(f"{ROUTER}.json5", text.encode(), PUBLIC_MODE, f"zenoh config of {ROUTER} (rewritten)")
        folder.merge()
    return SecurityAdd(d, tuple(roles), everyone, not_after, folder.files, prefix)
