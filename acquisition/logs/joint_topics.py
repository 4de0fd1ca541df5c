"""The JointState topics of a log and the joints they carry, and choosing the one to read when the
user has not said: a log of one JointState topic of one joint needs no name (a foreign recording, an
imported scope export); a log of several is refused with their list.

Our recordings name their topics by axis (:mod:`.recorded_axes` chooses among those); these functions
are for logs without any axis of ours.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from ..errors import RecordingError
from ..wire.messages import JointState
from .reader import list_topics
from .reader.framing import McapFile
from .reader.messages import Catalog, MessageBatch, MessageScan, Selection


def joint_state_topics(path: str | Path) -> list[str]:
    """The ROS 2 JointState topics of the MCAP file ``path``, sorted."""
    return [t.topic for t in list_topics(path) if t.is_joint_state]


def joints_of(path: str | Path, topic: str) -> tuple[str, ...] | None:
    """The joint names of the first message of ``topic`` in ``path`` (None: the topic holds no
    message that can be read)."""
    with McapFile.open(path) as file:
        catalog = Catalog(file.summary)
        for event in MessageScan(file, catalog, Selection(catalog, topic)).events():
            if isinstance(event, MessageBatch) and len(event):
                starts, ends = event.payload_bounds()
                return JointState.decode(memoryview(event.buffer)[int(starts[0]) : int(ends[0])]).name
    return None


def only_joint_state_topic(paths: Sequence[str | Path], option: str = "--topic") -> str | None:
    """The JointState topic of ``paths`` when each log has exactly one and it is the same in all; None
    when a log has none (its reading will say what it has); else a :class:`RecordingError` listing
    the topics."""
    found: dict[str, str] = {}
    for path in paths:
        topics = joint_state_topics(path)
        if not topics:
            return None
        if len(topics) > 1:
            raise RecordingError(
                f"{path} holds {len(topics)} JointState topics ({', '.join(topics)}): "
                f"choose one with {option}"
            )
        found[str(path)] = topics[0]
    if len(set(found.values())) > 1:
        held = ", ".join(f"{topic} in {path}" for path, topic in found.items())
        raise RecordingError(f"the logs hold different JointState topics ({held}): choose one with {option}")
    return next(iter(found.values()), None)


def choose_joint(paths: Sequence[str | Path], topic: str, preferred: str, option: str = "--joint") -> str:
    """The joint of ``topic`` to read in every log of ``paths``: its only joint when it has one (the
    same in all), else ``preferred`` when every log has it (our recordings: ``carriage`` and
    ``motor``); otherwise a :class:`RecordingError` listing the joints. A log whose topic has no
    message gives ``preferred`` (its reading will say what is wrong)."""
    chosen: set[str] = set()
    for path in paths:
        try:
            joints = joints_of(path, topic)
        except RecordingError:
            return preferred  # a file that cannot be read: the reader names the problem
        if joints is None:
            return preferred
        if len(joints) == 1:
            chosen.add(joints[0])
        elif preferred in joints:
            chosen.add(preferred)
        else:
            raise RecordingError(
                f"{path}: topic {topic} has {len(joints)} joints ({', '.join(joints)}): "
                f"choose one with {option}"
            )
    if len(chosen) > 1:
        raise RecordingError(
            f"the logs' topic {topic} has different joints ({', '.join(sorted(chosen))}): "
            f"choose one with {option}"
        )
    return chosen.pop() if chosen else preferred
