"""A view of recorded sessions: the axes of one or more MCAP logs as one rerun recording.

An axis is found by its topics (:mod:`axisflow.acquisition.logs.recorded_axes`): its state or setpoint
topic, and its move statuses, plan records and an adaptive node's parameter estimates, drawn when
present. The logs of a session (e.g. the demo's excitation and experiment recordings) land in
one recording, each axis in one column of the layout, the logs one after the other on the drive-time
timeline.

Reading uses the fast column reader (:func:`~axisflow.acquisition.read_joint_states`, ~1 s per hour
of a 1 kHz topic; the state and setpoint topics of an axis are read at once, on two threads) and
writing ``send_columns`` (:mod:`.scene`). Every log is checked (exists, is MCAP, holds an axis)
before anything is written.
"""

from __future__ import annotations

from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import rerun as rr
import rerun.blueprint as rrb

from ..acquisition.errors import AxisNotRecordedError
from ..acquisition.logs.reader import list_topics, read_joint_states, read_messages
from ..acquisition.logs.recorded_axes import RecordedAxis, axis_names, find_axes
from ..acquisition.wire.move_status import MOVE_STATUS_TYPE, MoveStatus
from ..acquisition.wire.params_estimate import PARAMS_ESTIMATE_TYPE, ParamsEstimate
from ..acquisition.wire.plan_record import PLAN_TYPE, PlanRecord
from ..model import AxisParams
from .blueprint import view_blueprint
from .entities import AxisEntities
from .errors import VizError
from .outputs import RerunOutput, ViewOutput, view_size_estimate
from .samples import AxisSamples
from .scene import AxisScene


@dataclass(frozen=True)
class SessionLogs:
    """Logs checked for viewing, with the axes each holds."""

    logs: tuple[tuple[Path, tuple[RecordedAxis, ...]], ...]

    @classmethod
    def open(cls, paths: Sequence[str | Path], only: Sequence[str] = ()) -> SessionLogs:
        """Check every log (exists, is MCAP, holds an axis); a :class:`VizError` (or the reader's
        ``RecordingError``) names the first that does not. ``only``: the axes to view (by name or
        label; default: every axis); one held by none of the logs is an
        :class:`~axisflow.acquisition.errors.AxisNotRecordedError` listing the axes they hold."""
        if not paths:
            raise VizError("no log to view: give one or more LOG.mcap")
        logs = []
        for path in paths:
            p = Path(path)
            topics = list_topics(p)
            axes = find_axes(topics)
            if not axes:
                names = ", ".join(t.topic for t in topics) or "none"
                raise VizError(
                    f"{p} holds no axis: no sensor_msgs/msg/JointState topic /<prefix>/<axis>/state or "
                    f"/<prefix>/<axis>/setpoint (its topics: {names})"
                )
            logs.append((p, tuple(axes)))
        return cls(tuple(logs)).only(only) if only else cls(tuple(logs))

    def only(self, names: Sequence[str]) -> SessionLogs:
        """The session with the axes ``names`` (axis names or labels) only; a log that holds none of
        them drops out."""
        held = {a.label: a for _p, axes in self.logs for a in axes}
        missing = [n for n in names if not any(n in (a.axis, a.label) for a in held.values())]
        if missing:
            paths = ", ".join(str(p) for p, _axes in self.logs)
            raise AxisNotRecordedError(
                f"--axis {', '.join(missing)}: not in {paths}; "
                f"{'it holds' if len(self.logs) == 1 else 'they hold'} {axis_names(list(held.values()))}"
            )
        kept = []
        for path, axes in self.logs:
            chosen = tuple(a for a in axes if a.axis in names or a.label in names)
            if chosen:
                kept.append((path, chosen))
        return SessionLogs(tuple(kept))

    @property
    def labels(self) -> list[str]:
        """Every axis of the session, sorted."""
        return sorted({a.label for _p, axes in self.logs for a in axes})

    def blueprint(self) -> rrb.Blueprint:
        adapted = {a.label for _p, axes in self.logs for a in axes if a.params is not None}
        return view_blueprint(self.labels, adapted)


@dataclass
class AxisSummary:
    label: str
    state_samples: int = 0
    setpoint_samples: int = 0
    statuses: int = 0
    plans: int = 0
    params: int = 0
    """an adaptive node's estimates"""


@dataclass
class SessionSummary:
    """What :func:`log_session` sent, per axis."""

    logs: list[Path] = field(default_factory=list)
    axes: dict[str, AxisSummary] = field(default_factory=dict)

    def format(self) -> str:
        lines = [f"{len(self.logs)} log(s): {', '.join(str(p) for p in self.logs)}"]
        for a in self.axes.values():
            lines.append(
                f"  axis {a.label}: {a.state_samples} state and {a.setpoint_samples} setpoint samples, "
                f"{a.statuses} move statuses, {a.plans} plan records"
                + (f", {a.params} parameter estimates" if a.params else "")
            )
        return "\n".join(lines)


def log_session(rec: rr.RecordingStream, session: SessionLogs, params: AxisParams) -> SessionSummary:
    """Send every axis of every log of ``session`` to ``rec`` (limits from ``params``)."""
    scenes: dict[str, AxisScene] = {}
    summary = SessionSummary()
    for path, axes in session.logs:
        summary.logs.append(path)
        for topics in axes:
            scene = scenes.get(topics.label)
            if scene is None:
                scene = scenes[topics.label] = AxisScene(rec, AxisEntities(topics.label), params)
            counts = summary.axes.setdefault(topics.label, AxisSummary(topics.label))
            _log_axis(scene, path, topics, counts)
    for scene in scenes.values():
        scene.finish()
    return summary


def _log_axis(scene: AxisScene, path: Path, topics: RecordedAxis, counts: AxisSummary) -> None:
    """One axis of one log: the records first (so that each move's span is known when its samples
    come), then the setpoints, then the measured samples (read while the setpoints are)."""
    if topics.plan is not None:
        plans = [PlanRecord.decode(m.data) for m in read_messages(path, topics.plan, PLAN_TYPE)]
        scene.add_plans(plans)
        counts.plans += len(plans)
    if topics.event is not None:
        statuses = [MoveStatus.decode(m.data) for m in read_messages(path, topics.event, MOVE_STATUS_TYPE)]
        scene.add_statuses(statuses)
        counts.statuses += len(statuses)
    if topics.params is not None:
        records = [
            ParamsEstimate.decode(m.data) for m in read_messages(path, topics.params, PARAMS_ESTIMATE_TYPE)
        ]
        scene.add_params(records)
        counts.params += len(records)
    with ThreadPoolExecutor(1) as reader:
        # the two topics share the file's chunks: reading them at once keeps both cores busy
        state = reader.submit(read_joint_states, path, topics.state) if topics.state is not None else None
        if topics.setpoint is not None:
            setpoint = AxisSamples.of_columns(read_joint_states(path, topics.setpoint))
            scene.add_setpoint(setpoint)
            counts.setpoint_samples += len(setpoint)
            del setpoint
        if state is not None:
            samples = AxisSamples.of_columns(state.result())
            scene.add_state(samples)
            counts.state_samples += len(samples)


def write_session_rrd(recordings: Sequence[str | Path], out_rrd: str | Path, params: AxisParams) -> Path:
    """The view of ``recordings`` (MCAP logs, e.g. a demo session's) saved to ``out_rrd`` with its
    layout; written atomically (nothing is left at ``out_rrd`` if it fails). Returns ``out_rrd``."""
    output = ViewOutput(rrd=Path(out_rrd), expected_bytes=view_size_estimate(recordings))
    session = SessionLogs.open(recordings)
    with RerunOutput(output, session.blueprint()) as out:
        log_session(out.rec, session, params)
    return Path(out_rrd)
