"""The router's access-control list (ACL): default deny, one subject per role keyed on its
certificate's common name, the role's kind's grants (:data:`.roles.ROLE_GRANTS`) as allow rules."""

from __future__ import annotations

from pathlib import Path

from ...acquisition.wire.keys import all_keys
from .errors import SecurityError
from .roles import ROLE_GRANTS, role_axes, role_kind


def acl_config(prefix: str, roles: tuple[str, ...]) -> dict[str, object]:
    """The router's ``access_control`` section: default deny, one subject per role (its certificate's
    common name), the role's kind's :data:`ROLE_GRANTS` as allow rules under ``prefix`` (on the role's
    axes only for a role limited to some: :meth:`Grant.key_exprs`)."""
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
                    "key_exprs": grant.key_exprs(prefix, role_axes(role)),
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


def acl_roles(acl: object, path: Path) -> tuple[str, tuple[str, ...]]:
    """The prefix and roles of an ``access_control`` section read from ``path``, checked to be exactly
    what :func:`acl_config` writes for them (a hand-edited list is never rewritten: a
    :class:`SecurityError` says so)."""
    try:
        roles = tuple(str(subject["id"]) for subject in acl["subjects"])  # type: ignore[index]
        first = roles[0]
        key = acl["rules"][0]["key_exprs"][0]  # type: ignore[index]
        tail = ROLE_GRANTS[role_kind(first)][0].key_exprs("", role_axes(first))[0]  # "/*/trajectory"
        prefix = key.removesuffix(tail) if key.endswith(tail) else ""
        same = acl == acl_config(prefix, roles)
    except (KeyError, IndexError, TypeError, ValueError, SecurityError):
        same = False
    if not same:
        raise SecurityError(
            f"the access-control list in {path} is not one `axisflow security init` wrote: edited by "
            "hand? not rewriting it (add the role there by hand, or rotate with `security init`)"
        )
    return prefix, roles
