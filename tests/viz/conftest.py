"""Fixtures for the view tests: small real MCAP logs of the axis contract, reading an .rrd back with
rerun's own reader (`axisflow` subprocesses: the `cli` fixture of tests/conftest.py)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pyarrow as pa
import pytest
from axisflow.acquisition import MoveState, MoveStatus, PlanRecord
from axisflow.acquisition.logs.mcap_writer import Ros2McapWriter
from axisflow.acquisition.logs.synthetic_log import SyntheticLogSpec, synthetic_block
from axisflow.acquisition.wire.keys import AxisKeys, topic_for_key
from axisflow.acquisition.wire.messages import AXIS_JOINTS, JOINT_STATE_TYPE, JointState
from axisflow.acquisition.wire.move_status import MOVE_STATUS_TYPE
from axisflow.acquisition.wire.params_estimate import PARAMS_ESTIMATE_TYPE, ParamsEstimate
from axisflow.acquisition.wire.plan_record import PLAN_TYPE
from axisflow.model import EXECUTION_PERIOD_NS, default_params
from rerun.chunk import RrdReader

SENDER = "0123456789abcdef0123456789abcdef"


@dataclass
class MoveSpec:
    """A move of a test log: ticks [start, end], its end position and planned energy."""

    move_id: int
    start_tick: int
    end_tick: int
    end_position_m: float
    energy_j: float
    dropped: bool = False


@dataclass
class WrittenLog:
    path: Path
    axes: tuple[str, ...]
    start_ns: int
    ticks: int
    moves: list[MoveSpec] = field(default_factory=list)


def write_test_log(
    path: Path,
    axes: tuple[str, ...] = ("a0",),
    seconds: float = 3.0,
    moves: bool = True,
    prefix: str = "axisflow",
    estimates: Sequence[ParamsEstimate] = (),
) -> WrittenLog:
    """A log as `axisflow record` writes it: per axis 1 kHz state and setpoint (the synthetic log's
    motion, encoded message by message), and, with ``moves``, move statuses and plan records of four
    moves (the third dropped before it started)."""
    params = default_params()
    writer = Ros2McapWriter(path)
    spec0 = SyntheticLogSpec(duration_s=seconds, axis=axes[0])
    log = WrittenLog(path, axes, spec0.start_ns, spec0.ticks)
    if moves:
        log.moves = [
            MoveSpec(1, 200, 700, 0.61, 12.5),
            MoveSpec(2, 700, 1350, 0.22, 20.0),
            MoveSpec(3, 1350, 1800, 0.5, 9.0, dropped=True),
            MoveSpec(4, 1350, 2600, 0.47, 31.0),
        ]
    for i, axis in enumerate(axes):
        keys = AxisKeys(axis, prefix)
        spec = SyntheticLogSpec(duration_s=seconds, axis=axis, seed=i)
        block = synthetic_block(spec, 0)
        state = writer.channel_for(topic_for_key(keys.state), JOINT_STATE_TYPE)
        setpoint = writer.channel_for(topic_for_key(keys.setpoint), JOINT_STATE_TYPE)
        for k in range(spec.ticks):
            for channel, cols in ((state, block.state), (setpoint, block.setpoint)):
                js = JointState(
                    int(cols.stamp_ns[k]),
                    axis,
                    AXIS_JOINTS,
                    tuple(cols.position[k]),
                    tuple(cols.velocity[k]),
                    tuple(cols.effort[k]),
                )
                writer.add(
                    channel, int(cols.log_time_ns[k]), int(cols.publish_time_ns[k]), k + 1, js.encode()
                )
        if moves:
            _write_moves(writer, keys, log, params)
        if estimates:
            channel = writer.channel_for(topic_for_key(keys.params), PARAMS_ESTIMATE_TYPE)
            for n, record in enumerate(estimates, start=1):
                writer.add(channel, record.stamp_ns, record.stamp_ns, n, record.encode())
    writer.finish()
    return log


def _write_moves(writer: Ros2McapWriter, keys: AxisKeys, log: WrittenLog, params: object) -> None:
    event = writer.channel_for(topic_for_key(keys.event), MOVE_STATUS_TYPE)
    plan = writer.channel_for(topic_for_key(keys.plan), PLAN_TYPE)
    stamp = log.start_ns + 100 * EXECUTION_PERIOD_NS
    for n, m in enumerate(log.moves):
        record = PlanRecord(
            stamp,
            keys.axis,
            m.move_id,
            SENDER,
            "test",
            n + 1,
            "min-time",
            "poly5",
            "exact",
            0.9,
            0.4,
            m.end_position_m,
            (m.end_tick - m.start_tick) / 1000,
            m.energy_j,
            "positive",
            1.0,
            0.0,
            "converged",
            3,
            1e-5,
        )
        writer.add(plan, stamp, stamp, n + 1, record.encode())
        statuses = [
            MoveStatus(
                stamp,
                keys.axis,
                MoveState.ACCEPTED,
                m.move_id,
                100,
                m.start_tick,
                m.end_tick,
                SENDER,
                f"accepted move {m.move_id}",
            )
        ]
        if m.dropped:
            statuses.append(
                MoveStatus(
                    stamp + 1,
                    keys.axis,
                    MoveState.DROPPED,
                    m.move_id,
                    101,
                    m.start_tick,
                    m.end_tick,
                    SENDER,
                    f"dropped move {m.move_id}",
                )
            )
        else:
            done = log.start_ns + m.end_tick * EXECUTION_PERIOD_NS
            statuses.append(
                MoveStatus(
                    done,
                    keys.axis,
                    MoveState.COMPLETED,
                    m.move_id,
                    m.end_tick,
                    m.start_tick,
                    m.end_tick,
                    SENDER,
                    f"completed move {m.move_id}",
                )
            )
        for j, st in enumerate(statuses):
            writer.add(event, st.stamp_ns, st.stamp_ns, 2 * n + j + 1, st.encode())


@dataclass
class EntityData:
    """One entity read back from an .rrd: its temporal rows sorted by time, and whether it has static
    data (styles)."""

    stamp_ns: np.ndarray
    values: list
    """per row, the component's values (a list of floats, or of strings for a text log)"""
    static: bool = False

    def scalars(self) -> np.ndarray:
        """The values as floats, shape (rows,) for one series or (rows, k)."""
        arr = np.array(self.values, dtype=float)
        return arr[:, 0] if arr.ndim == 2 and arr.shape[1] == 1 else arr


_COMPONENTS = ("Scalars:scalars", "TextLog:text", "LineStrips2D:strips")


def read_rrd(path: Path) -> dict[str, EntityData]:
    """Every entity of an .rrd by path, through rerun's RrdReader (data columns: Scalars, TextLog,
    LineStrips2D)."""
    rows: dict[str, list[tuple[np.ndarray, list]]] = {}
    static: set[str] = set()
    for chunk in RrdReader(path).store().stream():
        entity = chunk.entity_path
        if chunk.is_static:
            static.add(entity)
            continue
        batch = chunk.to_record_batch()
        names = batch.schema.names
        if "stamp" not in names:
            continue
        stamps = batch.column(names.index("stamp")).cast(pa.int64()).to_numpy()
        component = next((n for n in names if n in _COMPONENTS), None)
        if component is None:
            continue
        rows.setdefault(entity, []).append((stamps, batch.column(names.index(component)).to_pylist()))
    out = {}
    for entity in set(rows) | static:
        parts = rows.get(entity, [])
        stamps = np.concatenate([p[0] for p in parts]) if parts else np.empty(0, np.int64)
        values = [v for p in parts for v in p[1]]
        order = np.argsort(stamps, kind="stable")
        out[entity] = EntityData(stamps[order], [values[i] for i in order], entity in static)
    return out


@pytest.fixture(scope="session")
def test_log(tmp_path_factory) -> WrittenLog:
    """One axis, 3 s, with moves."""
    return write_test_log(tmp_path_factory.mktemp("logs") / "session.mcap")


@pytest.fixture(scope="session")
def two_axis_log(tmp_path_factory) -> WrittenLog:
    """Two axes (a0, a1) in one log, 2 s, no moves."""
    return write_test_log(
        tmp_path_factory.mktemp("logs") / "two.mcap", axes=("a0", "a1"), seconds=2.0, moves=False
    )


@pytest.fixture
def rrd_reader():
    return read_rrd
