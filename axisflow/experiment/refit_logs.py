"""A refit of the logs a user names — ours, any ROS 2 recording, or CSV, Parquet and MATLAB files — into
a folder: the JointState topic and joint chosen from the logs, foreign files imported on the way (one
temporary MCAP each, through the importer of ``axisflow import``), then :func:`.refit_folder.identify_to`.
What ``axisflow identify`` runs."""

from __future__ import annotations

import dataclasses
import os
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

from ..identification.errors import IdentificationError
from ..identification.signals import DEFAULT_JOINT, DEFAULT_TOPIC

if TYPE_CHECKING:
    from ..acquisition.foreign import ColumnMap, CsvOptions
    from ..identification.refit import IdentifySettings
    from ..model import AxisParams


@dataclass(frozen=True)
class LogChoice:
    """Which JointState topic and joint of the logs to fit (None: chosen from the logs)."""

    topic: str | None = None
    axis: str | None = None
    """one of our axes by name (its state topic)"""
    prefix: str | None = None
    """the key prefix of ``axis``"""
    joint: str | None = None


@dataclass(frozen=True)
class ForeignColumns:
    """How the columns of foreign logs (.csv, .tsv, .parquet, .mat) become a joint."""

    columns: ColumnMap
    csv: CsvOptions | None = None


def state_topic(choice: LogChoice, logs: Sequence[str | Path]) -> str:
    """The JointState topic to fit: the chosen topic, else the state topic of the chosen axis (or of the
    logs' only axis) in every log; in logs without any axis of ours, their only JointState topic (several
    are refused with their list); logs without any keep the default topic, whose reading then says what
    is wrong with them."""
    from ..acquisition.logs.joint_topics import only_joint_state_topic
    from ..acquisition.logs.recorded_axes import choose_axis_of_logs, recorded_axes

    if choice.topic is not None:
        if choice.prefix is not None:
            raise IdentificationError(
                "--prefix goes with --axis, not with --topic (a topic names it already)"
            )
        return choice.topic
    if choice.axis is None and choice.prefix is None and not any(recorded_axes(log) for log in logs):
        return only_joint_state_topic(logs) or DEFAULT_TOPIC
    state = choose_axis_of_logs(logs, choice.axis, choice.prefix).state
    if state is None:  # chosen for its state topic: an axis without one is never chosen
        raise IdentificationError(f"the axis chosen in {', '.join(map(str, logs))} has no state topic")
    return state


def refit_logs(
    out: Path,
    fit: Sequence[str | Path],
    validate: Sequence[str | Path],
    nominal: AxisParams,
    settings: IdentifySettings,
    choice: LogChoice = LogChoice(),
    foreign: ForeignColumns | None = None,
) -> dict[str, Any]:
    """The refit of ``fit`` (validated on ``validate``) written to ``out`` (checked by the caller);
    report.json's content. Foreign logs among them need ``foreign``; each is imported into a temporary
    MCAP that lives as long as the refit."""
    from ..acquisition.foreign import ForeignLogError, format_of, import_for_reading

    logs = [*fit, *validate]
    foreign_logs = [log for log in logs if format_of(log) is not None]
    if foreign_logs and foreign is None:
        raise ForeignLogError(f"{foreign_logs[0]} needs its column map (--position COL, …)")
    with tempfile.TemporaryDirectory(prefix="axisflow-identify-") as folder:
        imported: dict[str | Path, Any] = {}
        if foreign_logs:
            assert foreign is not None
            read = import_for_reading(foreign_logs, foreign.columns, folder, csv=foreign.csv)
            imported = dict(zip(foreign_logs, read, strict=True))
        sides = {log.side for log in imported.values()}
        return _refit(
            out,
            [imported.get(log, log) for log in fit],
            [imported.get(log, log) for log in validate],
            nominal,
            settings,
            choice,
            sides.pop() if len(sides) == 1 else None,
        )


def _refit(
    out: Path,
    fit: list[str | os.PathLike],
    validate: list[str | os.PathLike],
    nominal: AxisParams,
    settings: IdentifySettings,
    choice: LogChoice,
    imported_side: str | None,
) -> dict[str, Any]:
    """The refit with the topic and joint chosen from the logs; ``imported_side``: the side of the
    foreign logs among them (the kind of a joint they name otherwise)."""
    from ..acquisition.logs.joint_topics import choose_joint
    from .refit_folder import identify_to

    # an ImportedLog is a path-like, not a Path: everything below opens its logs through os.fspath
    # (the temporary MCAP) and names them through str (the file the user gave)
    fit_paths, validate_paths = cast("list[str | Path]", fit), cast("list[str | Path]", validate)
    logs = [*fit_paths, *validate_paths]
    topic = state_topic(choice, logs)
    joint = choice.joint if choice.joint is not None else choose_joint(logs, topic, DEFAULT_JOINT)
    kind = settings.joint_kind if settings.joint_kind is not None else imported_side
    chosen = dataclasses.replace(settings, topic=topic, joint=joint, joint_kind=kind)
    _ident, report = identify_to(out, fit_paths, nominal, chosen, validate=validate_paths)
    return report
