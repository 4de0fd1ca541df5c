"""The moves a savings comparison is about: a recorded session's, a way-point file's, or random ones.

* **A recording** (``axisflow savings LOG.mcap``): every move the bridge completed on the axis, in the
  order it ran, whatever sent it (a planner node, the excitation, a quick stop is left out): its
  ticks come from the bridge's ``COMPLETED`` move status, its end points from the recorded setpoints
  at its first tick and at its end tick. A log without such a move has nothing to compare: refused.
* **A way-point file** (``--waypoints FILE``, :func:`axisflow.waypoints.load_waypoints`): the moves
  between consecutive way points.
* **Random way points** (``--random N [--seed S]``): the paper's experiment's (uniform in the stroke,
  seeded as ``axisflow experiment`` draws them).
"""

from __future__ import annotations

from itertools import pairwise
from pathlib import Path

import numpy as np

from ..acquisition import (
    MOVE_STATUS_TYPE,
    AxisKeys,
    MoveState,
    MoveStatus,
    read_joint_states,
    read_messages,
    topic_for_key,
)
from ..acquisition.wire.quick_stop import STOP_MOVE_ID
from ..experiment.waypoints import load_waypoints, random_waypoints
from ..model import EXECUTION_PERIOD_NS, AxisflowError, AxisParams
from ..planner.cycle_time import Moves


class NoMovesError(AxisflowError):
    """A recording holds no move that ran on the axis."""


def moves_of_waypoints(points: np.ndarray) -> list[tuple[float, float]]:
    return [(float(a), float(b)) for a, b in pairwise(points)]


def moves_of_file(path: str | Path, params: AxisParams) -> list[tuple[float, float]]:
    return moves_of_waypoints(load_waypoints(path, params))


def moves_of_random(count: int, seed: int, params: AxisParams) -> list[tuple[float, float]]:
    return moves_of_waypoints(random_waypoints(count, seed, params))


def moves_of_recording(path: str | Path, params: AxisParams, keys: AxisKeys | None = None) -> Moves:
    """The moves the axis completed in the recording ``path`` (the module docstring), in order."""
    keys = keys or AxisKeys()
    topic = topic_for_key(keys.event)
    done: dict[tuple[str, int, int], MoveStatus] = {}
    for m in read_messages(path, topic, MOVE_STATUS_TYPE):
        s = MoveStatus.decode(m.data)
        if s.state is MoveState.COMPLETED and s.move_id != STOP_MOVE_ID and s.start_tick >= 0:
            done.setdefault((s.sender, s.move_id, s.start_tick), s)
    if not done:
        raise NoMovesError(
            f"{path} holds no move that ran on axis {keys.axis!r} (no completed move status on {topic}): "
            "nothing to compare; record while moves run, or give --waypoints FILE"
        )
    setpoint = read_joint_states(path, topic_for_key(keys.setpoint)).joint("carriage")
    order = np.argsort(setpoint.stamp_ns, kind="stable")
    stamps, position = setpoint.stamp_ns[order], setpoint.position[order]
    half = EXECUTION_PERIOD_NS // 2

    def at(stamp_ns: int) -> float | None:
        i = int(np.searchsorted(stamps, stamp_ns - half, "left"))
        if i < stamps.size and abs(int(stamps[i]) - stamp_ns) <= half:
            return float(position[i])
        return None

    moves = []
    for s in sorted(done.values(), key=lambda s: s.stamp_of(s.start_tick)):
        x0, x1 = at(s.stamp_of(s.start_tick)), at(s.stamp_of(s.end_tick))
        if x0 is not None and x1 is not None:
            moves.append((min(max(x0, 0.0), params.L), min(max(x1, 0.0), params.L)))
    if not moves:
        raise NoMovesError(
            f"{path}: {len(done)} moves completed on axis {keys.axis!r}, but no setpoint of their first and "
            f"last ticks was recorded ({topic_for_key(keys.setpoint)}): their end points are unknown"
        )
    return moves
