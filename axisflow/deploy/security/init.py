"""``security init``: a new folder with a CA, the router's and each role's certificate and key, and
their Zenoh files (see the package docstring for the layout)."""

from __future__ import annotations

import datetime as dt
from dataclasses import dataclass, field
from pathlib import Path

from .certificates import Issued, issue_ca, issue_role, issue_router
from .folder import PRIVATE_MODE, PUBLIC_MODE, FolderWriter, WrittenFile, check_new_folder, file_lines
from .plan import SecurityPlan
from .roles import ROUTER, how_to_run
from .validity import CLOCK_SKEW
from .zenoh_files import check_loads_in_zenoh, client_config, router_config, to_json5


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
        lines += file_lines(self.files)
        d = self.directory
        lines.append("next (each in its own terminal or service, the router first; see docs/security.md):")
        lines.append(f"  axisflow router --zenoh-config {d / 'router.json5'}")
        lines += [how_to_run(d, role, self.plan.prefix) for role in self.plan.roles]
        return "\n".join(lines)


def init_security(plan: SecurityPlan, now: dt.datetime | None = None) -> SecurityInit:
    """Generate the CA, the router's and each role's certificate and key, and their Zenoh files."""
    target = check_new_folder(plan.directory, plan.force)
    issued_at = now or dt.datetime.now(dt.UTC)
    not_before = issued_at - CLOCK_SKEW
    not_after = issued_at + dt.timedelta(days=plan.days)
    stamp = f"{issued_at:%Y-%m-%d %H:%M} UTC"
    folder = FolderWriter(target)
    with folder.discarded_on_error(str(target)):
        ca = issue_ca(f"axisflow CA {plan.prefix} {stamp}", not_before, not_after)
        folder.write("ca.pem", ca.certificate_pem, PUBLIC_MODE, "CA certificate (every host)")
        folder.write("ca.key", ca.key_pem, PRIVATE_MODE, "CA private key (keep offline)")
        router = issue_router(ca, plan.host, not_before, not_after)
        config = router_config(plan.listen_endpoint, plan.prefix, plan.roles)
        write_identity(folder, ROUTER, router, config, _header(plan, ROUTER, stamp))
        for role in plan.roles:
            issued = issue_role(ca, role, not_before, not_after)
            write_identity(
                folder, role, issued, client_config(plan.endpoint, role), _header(plan, role, stamp)
            )
        folder.commit()
    return SecurityInit(target, plan, not_after, folder.files)


def _header(plan: SecurityPlan, name: str, stamp: str) -> str:
    who = "the router (run: axisflow router --zenoh-config FILE)" if name == ROUTER else f"role {name}"
    return (
        f"Zenoh configuration of {who}, written by `axisflow security init` on {stamp}.\n"
        f"Router {plan.endpoint}; keys {plan.prefix}/**. Paths are relative to this file's folder\n"
        "(axisflow resolves them there; for zenohd, start it in this folder)."
    )


def write_identity(
    folder: FolderWriter, name: str, issued: Issued, config: dict[str, object], header: str
) -> None:
    """An identity's certificate, private key and Zenoh configuration (checked to load in zenoh)."""
    folder.write(f"{name}.pem", issued.certificate_pem, PUBLIC_MODE, f"certificate CN={name}")
    folder.write(f"{name}.key", issued.key_pem, PRIVATE_MODE, f"private key of {name}")
    text = to_json5(config, header)
    check_loads_in_zenoh(f"{name}.json5", text)
    folder.write(f"{name}.json5", text.encode(), PUBLIC_MODE, f"zenoh config of {name}")
