"""The axes a recording holds, found by their topics, and choosing one of them by name.

An axis is found by its topics (the wire contract, docs/acquisition.md): ``/<prefix>/<axis>/state``
and ``…/setpoint`` (``sensor_msgs/msg/JointState``), ``…/event`` (``axisflow_msgs/msg/MoveStatus``),
``…/plan`` (``axisflow_msgs/msg/PlanResult``) and ``…/params`` (``axisflow_msgs/msg/ParamsEstimate``).
An axis needs a state or a setpoint topic; the others belong to it when present. A recording of a
cell holds several (``axisflow demo --axes 4``: ``a0`` … ``a3``); the commands that read one axis
(identify, table2) take ``--axis`` and, when it is missing from a log, say which axes the log holds
(:func:`choose_axis`); the view shows them all.

An axis is named by its ``label``: the axis name under the default prefix ``axisflow``, else
``<prefix>/<axis>`` (the same label names its column in the rerun views).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from ..errors import AxisNotRecordedError
from ..wire.keys import DEFAULT_PREFIX
from ..wire.move_status import MOVE_STATUS_TYPE
from ..wire.params_estimate import PARAMS_ESTIMATE_TYPE
from ..wire.plan_record import PLAN_TYPE
from .reader import TopicInfo, list_topics

_AXIS_TOPIC = re.compile(r"^/(?P<prefix>.+)/(?P<axis>[^/]+)/(?P<kind>state|setpoint|event|plan|params)$")
_RECORD_TYPES = {"event": MOVE_STATUS_TYPE, "plan": PLAN_TYPE, "params": PARAMS_ESTIMATE_TYPE}


def axis_label(prefix: str, axis: str) -> str:
    """The label of an axis: ``axis`` under the default key prefix, else ``<prefix>/<axis>``."""
    return axis if prefix == DEFAULT_PREFIX else f"{prefix}/{axis}"


@dataclass(frozen=True)
class RecordedAxis:
    """The topics of one axis in one log (None: absent)."""

    prefix: str
    axis: str
    state: str | None = None
    setpoint: str | None = None
    event: str | None = None
    plan: str | None = None
    params: str | None = None

    @property
    def label(self) -> str:
        return axis_label(self.prefix, self.axis)


def find_axes(topics: Sequence[TopicInfo]) -> list[RecordedAxis]:
    """The axes among a log's topics, sorted by label (see the module docstring)."""
    found: dict[tuple[str, str], dict[str, str]] = {}
    for t in topics:
        m = _AXIS_TOPIC.match(t.topic)
        if m is None:
            continue
        kind = m["kind"]
        wanted = (
            t.is_joint_state
            if kind in ("state", "setpoint")
            else (t.schema_name == _RECORD_TYPES[kind] and t.message_encoding == "cdr")
        )
        if wanted:
            found.setdefault((m["prefix"], m["axis"]), {})[kind] = t.topic
    axes = [
        RecordedAxis(p, a, **kinds) for (p, a), kinds in found.items() if {"state", "setpoint"} & kinds.keys()
    ]
    return sorted(axes, key=lambda a: a.label)


def recorded_axes(path: str | Path) -> list[RecordedAxis]:
    """The axes of the MCAP file ``path``, sorted by label (a :class:`RecordingError` for a file that is
    missing or not MCAP)."""
    return find_axes(list_topics(path))


def axis_names(axes: Sequence[RecordedAxis]) -> str:
    """``a0, a1, a2`` — the labels, for a message ("none" for none)."""
    return ", ".join(a.label for a in axes) or "none"


def choose_axis(
    path: str | Path,
    axis: str | None,
    prefix: str | None = None,
    what: str = "state",
    option: str = "--axis",
) -> RecordedAxis:
    """The axis of ``path`` named ``axis`` (under ``prefix``, or under any prefix when that is
    unambiguous) that has a ``what`` topic (state, setpoint, event or plan). With ``axis`` None: the
    only axis of the log. Otherwise an :class:`AxisNotRecordedError` naming the file and listing its
    axes, e.g. ``run.mcap holds 4 axes (a0, a1, a2, a3): choose one with --axis``."""
    axes = [a for a in recorded_axes(path) if getattr(a, what) is not None]
    if not axes:
        raise AxisNotRecordedError(
            f"{path} holds no axis with a {what} topic (/<prefix>/<axis>/{what}): was it recorded while "
            "a bridge ran?"
        )
    candidates = [
        a for a in axes if (axis is None or axis in (a.axis, a.label)) and prefix in (None, a.prefix)
    ]
    if len(candidates) == 1:
        return candidates[0]
    if axis is None:  # several (under the prefix given, if any)
        raise AxisNotRecordedError(f"{path} holds {_count(candidates or axes)}: choose one with {option}")
    if not candidates:
        asked = axis if prefix is None else axis_label(prefix, axis)
        raise AxisNotRecordedError(
            f"{option} {asked}: {path} holds no such axis with a {what} topic; it holds {_count(axes)}"
        )
    raise AxisNotRecordedError(
        f"{option} {axis}: {path} holds it under several prefixes ({axis_names(candidates)}): give the "
        "prefix too"
    )


def _count(axes: Sequence[RecordedAxis]) -> str:
    return f"one axis ({axes[0].label})" if len(axes) == 1 else f"{len(axes)} axes ({axis_names(axes)})"


def choose_axis_of_logs(
    paths: Sequence[str | Path],
    axis: str | None,
    prefix: str | None = None,
    what: str = "state",
    option: str = "--axis",
) -> RecordedAxis:
    """:func:`choose_axis` in every log of ``paths``: the same axis in each (with ``axis`` None, each
    log's only axis, and the same one in all; else an :class:`AxisNotRecordedError` naming them)."""
    chosen = {Path(p): choose_axis(p, axis, prefix, what, option) for p in paths}
    labels = {a.label for a in chosen.values()}
    if len(labels) > 1:
        held = ", ".join(f"{a.label} in {p}" for p, a in chosen.items())
        raise AxisNotRecordedError(f"the logs hold different axes ({held}): choose one with {option}")
    return next(iter(chosen.values()))
