"""The roles of a secure deployment and what each kind may do.

A role is a certificate identity (its common name): ``planner``, ``bridge``, ``recorder``, ``adapter``,
or one of these kinds followed by ``-NAME`` (``planner-cell2``: another planner with its own
certificate and the same rights). :data:`ROLE_GRANTS` lists everything a kind may do; the
access-control list (:mod:`.access_control`) denies anything else.

A role may be **limited to axes** by ``@AXIS`` (``bridge@a0``, ``planner-line2@a3``, ``bridge-m1@a0+a1``
for a machine that drives two): its grants then name those axes instead of every axis (``P/a0/state``
instead of ``P/*/state``), so the bridge of a0 cannot publish a1's samples nor take a1's moves, and the
planner of a3 cannot move a0. Only who listens (``declare_subscriber`` towards the role, see
:class:`Grant`) stays cell-wide. The axes are part of the name, hence of the certificate's common
name and of its files (``bridge@a0.pem``), so the access list read back from ``router.json5`` says
them too.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from ...acquisition.wire.keys import DEFAULT_PREFIX
from .errors import SecurityArgumentError

ROUTER = "router"
"""the router's certificate common name and file stem (reserved: not a role name)"""
DEFAULT_ROLES = ("planner", "bridge", "recorder")


@dataclass(frozen=True)
class Grant:
    """One ACL rule of a role: ``messages`` allowed on ``<prefix>/<suffix>`` keys in one direction.

    ``flow`` is seen from the router: ``ingress`` = sent by the role, ``egress`` = delivered to it.
    Zenoh allows a message when a granted key expression *includes* the message's key expression.
    """

    flow: str
    messages: tuple[str, ...]
    suffixes: tuple[str, ...]
    cell_wide: bool = False
    """true for a grant that stays on every axis for a role limited to some: the declarations of who
    listens, which the router must pass to a publisher for its data to reach a recorder of the whole
    cell (``P/**``); they carry no data"""

    def key_exprs(self, prefix: str, axes: tuple[str, ...] = ()) -> list[str]:
        """The granted key expressions under ``prefix``: for every axis, or (``axes``) for those only
        (``*/state`` → ``a0/state``, ``**`` → ``a0/**``)."""
        if not axes or self.cell_wide:
            return [f"{prefix}/{suffix}" for suffix in self.suffixes]
        out = []
        for axis in axes:
            for suffix in self.suffixes:
                scoped = f"{axis}/**" if suffix == "**" else f"{axis}{suffix.removeprefix('*')}"
                out.append(f"{prefix}/{scoped}")
        return out


ROLE_GRANTS: dict[str, tuple[Grant, ...]] = {
    # the planner commands: moves and quick stops, its sender token, its plan records; it reads what
    # MoveSender and AxisState read (events, state, setpoint, the bridge's token) and, with --adapt, an
    # adaptive node's parameter estimates
    "planner": (
        Grant("ingress", ("put",), ("*/trajectory", "*/stop", "*/plan")),
        Grant("ingress", ("liveliness_token",), ("*/sender/*",)),
        Grant(
            "ingress", ("declare_subscriber",), ("*/event", "*/state", "*/setpoint", "*/drive", "*/params")
        ),
        Grant("ingress", ("declare_liveliness_subscriber", "liveliness_query"), ("*/alive",)),
        Grant("egress", ("put",), ("*/event", "*/state", "*/setpoint", "*/drive", "*/params")),
        Grant("egress", ("liveliness_token",), ("*/alive",)),
        Grant("egress", ("declare_subscriber",), ("**",), cell_wide=True),  # who listens to its moves
    ),
    # the bridge publishes telemetry and events and its token; it reads moves, stops, sender tokens
    "bridge": (
        Grant("ingress", ("put",), ("*/state", "*/setpoint", "*/event", "*/drive")),
        Grant("ingress", ("liveliness_token",), ("*/alive",)),
        Grant("ingress", ("declare_subscriber",), ("*/trajectory", "*/stop")),
        Grant("ingress", ("declare_liveliness_subscriber", "liveliness_query"), ("*/sender/*",)),
        Grant("egress", ("put",), ("*/trajectory", "*/stop")),
        Grant("egress", ("liveliness_token",), ("*/sender/*",)),
        Grant("egress", ("declare_subscriber",), ("**",), cell_wide=True),  # who listens to its telemetry
    ),
    # the recorder only listens: every key and token under the prefix, never a put
    "recorder": (
        Grant("ingress", ("declare_subscriber",), ("**",)),
        Grant("ingress", ("declare_liveliness_subscriber", "liveliness_query"), ("**",)),
        Grant("egress", ("put",), ("**",)),
        Grant("egress", ("liveliness_token",), ("**",)),
    ),
    # the adaptive node (axisflow adapt) reads the samples and publishes parameter estimates; it cannot
    # command the axis: a planner decides whether to plan with its estimates (--adapt)
    "adapter": (
        Grant("ingress", ("put",), ("*/params",)),
        Grant("ingress", ("declare_subscriber",), ("*/state",)),
        Grant("egress", ("put",), ("*/state",)),
        Grant("egress", ("declare_subscriber",), ("**",), cell_wide=True),  # who listens to its estimates
    ),
}
"""everything each kind of role may do; anything else is denied (``default_permission: deny``)"""

_AXIS = r"[A-Za-z0-9_][A-Za-z0-9_-]{0,30}"
_ROLE_NAME = re.compile(
    rf"^(?P<kind>[a-z]+)(?:-(?P<suffix>[a-z0-9][a-z0-9_-]{{0,30}}))?(?:@(?P<axes>{_AXIS}(?:\+{_AXIS})*))?$"
)


def _match(name: str) -> re.Match[str]:
    m = _ROLE_NAME.match(name)
    if m is None or m["kind"] not in ROLE_GRANTS:
        raise SecurityArgumentError(
            f"role {name!r} is not one of {', '.join(ROLE_GRANTS)} (or one of them followed by -NAME of "
            "lower-case letters, digits, '-' or '_', e.g. planner-cell2, and/or by @AXIS to limit it to "
            "an axis, e.g. bridge@a0 or bridge-m1@a0+a1)"
        )
    return m


def role_kind(name: str) -> str:
    """The kind of a role name: ``planner``, ``bridge``, ``recorder``, ``adapter``, or one of them followed by
    ``-NAME`` (``planner-cell2``: another planner identity with its own certificate) and/or ``@AXES``."""
    return _match(name)["kind"]


def role_axes(name: str) -> tuple[str, ...]:
    """The axes a role is limited to (``bridge@a0+a1`` → ``("a0", "a1")``); () for every axis."""
    axes = _match(name)["axes"]
    return tuple(axes.split("+")) if axes else ()


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


def check_roles(roles: tuple[str, ...]) -> None:
    """At least one role, each of a known kind, none twice; else a :class:`SecurityArgumentError`."""
    if not roles:
        raise SecurityArgumentError("no role given: at least one of planner, bridge, recorder, adapter")
    for name in roles:
        role_kind(name)
    if len(set(roles)) != len(roles):
        raise SecurityArgumentError(f"roles {', '.join(roles)} name a role more than once")


def how_to_run(directory: Path, role: str, prefix: str = DEFAULT_PREFIX) -> str:
    """One line saying how to start ``role`` with its file in ``directory``."""
    config = directory / f"{role}.json5"
    axes = role_axes(role)
    if not axes:
        return {
            "planner": f"  {role}: open_session(ZenohOptions(config_file=Path('{config}')))",
            "bridge": f"  axisflow bridge --sim --zenoh-config {config}",
            "recorder": f"  axisflow record -o session.mcap --zenoh-config {config}",
            "adapter": f"  axisflow adapt --axis a0 --zenoh-config {config}",
        }[role_kind(role)]
    first = axes[0]
    return {
        "planner": f"  {role}: axisflow planner --axis {first} --random 10 --zenoh-config {config}",
        "bridge": f"  axisflow bridge --sim --axis {first} --zenoh-config {config}",
        "recorder": f"  axisflow record -o {first}.mcap --keys {prefix}/{first}/** --zenoh-config {config}",
        "adapter": f"  axisflow adapt --axis {first} --zenoh-config {config}",
    }[role_kind(role)] + (f" (and the same for {', '.join(axes[1:])})" if len(axes) > 1 else "")
