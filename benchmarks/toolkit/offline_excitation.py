"""The identification excitation on the simulated axis, offline: no Zenoh, no processes, the same data.

:func:`record_offline_excitation` does what ``axisflow bridge --sim`` + ``axisflow record`` +
``axisflow excite`` do, in one loop and as fast as Python runs it: a move to the excitation's centre
(minimum-time poly5, the exact planner) and every burst as a sampled move go through the bridge's move
queue (:class:`~axisflow.acquisition.bridge.move_queue.MoveQueue`, validated like live moves); each
tick the drive's sample (unless the plant lost it) and the setpoint are written, as the recorder
writes them, to an MCAP file (:class:`~axisflow.acquisition.logs.mcap_writer.Ros2McapWriter`:
``/<prefix>/<axis>/state`` and ``setpoint``, and the drive's DriveInfo once a second; publish time =
the sample's stamp, log time 0.4 ms later, sequence numbers per topic). The tests and the docs'
figures of the realistic plant use it; the end-to-end path with real processes is tests/demo.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ...acquisition.bridge.move_queue import MoveQueue, QueuedMove
from ...acquisition.drives.plant import PlantConfig
from ...acquisition.drives.sim_axis import SimulatedAxis
from ...acquisition.logs.mcap_writer import Ros2McapWriter
from ...acquisition.wire.axis_sample_encoder import AxisSampleEncoder
from ...acquisition.wire.drive_info import DRIVE_INFO_TYPE, SIMULATED, DriveInfo
from ...acquisition.wire.drive_info import PERIOD_TICKS as DRIVE_INFO_PERIOD
from ...acquisition.wire.keys import AxisKeys, topic_for_key
from ...acquisition.wire.messages import APPEND, JOINT_STATE_TYPE, SAMPLED_LAW, Knots, MoveCommand
from ...identification.excitation import ExcitationPlan
from ...identification.signals import TimeWindow
from ...model import AxisParams, move_ticks, polynomial_law
from ...planner import Case, MoveProblem, solve_exact

RECORD_DELAY_NS = 400_000
"""log time − publish time of the written messages [ns] (what the recorder sees on loopback)"""
SETTLE_S = 0.5
"""drive time held at rest before the first move and after the last [s]"""


@dataclass(frozen=True)
class OfflineRun:
    """What :func:`record_offline_excitation` wrote."""

    path: Path
    ticks: int
    samples_written: int
    samples_lost: int
    window: TimeWindow
    """the excitation's moves (from the first move's start to the last one's end), ±0.2 s"""
    drive: SimulatedAxis
    """the simulated drive after the run (its true parameters: ``drive.true_params()``)"""


def record_offline_excitation(
    path: str | Path,
    plan: ExcitationPlan,
    plant: PlantConfig,
    nominal: AxisParams,
    keys: AxisKeys | None = None,
    start_ns: int = 1_767_225_600_000_000_000,
) -> OfflineRun:
    """Run ``plan`` on a simulated axis with ``plant`` (controller and feed-forward from ``nominal``) and
    write the recording to ``path`` (a new file; see the module docstring)."""
    keys = keys or AxisKeys()
    drive = SimulatedAxis(plant, nominal, start_ns, keys.axis)
    first = drive.read()
    assert first is not None  # the first sample is never lost
    queue = MoveQueue(nominal, first.position_m, first.stamp_ns, keys.axis)
    commands = []
    x0 = first.position_m
    if abs(x0 - plan.center_m) > 1e-9:
        problem = MoveProblem(x0, plan.center_m, polynomial_law("poly5"), Case.MIN_TIME)
        duration = solve_exact(problem, nominal).duration_s
        commands.append(MoveCommand(start_ns, keys.axis, 1, APPEND, "poly5", x0, plan.center_m, duration))
    for trajectory in plan.trajectories():
        t = trajectory
        commands.append(
            MoveCommand(
                start_ns,
                keys.axis,
                len(commands) + 1,
                APPEND,
                SAMPLED_LAW,
                t.x0_m,
                t.x1_m,
                t.duration_s,
                Knots.of(t),
            )
        )
    settle = move_ticks(SETTLE_S)
    queued: list[QueuedMove] = []
    for cmd in commands:
        queued.append(queue.submit(cmd, settle if not queued else 0))
    end_tick = queued[-1].end_tick + settle
    written = lost = 0
    encoder = AxisSampleEncoder(keys.axis)  # the bridge's one-call encoder: the same bytes as .encode()
    with _Writer(path, keys) as out:
        for tick in range(end_tick):
            sample = drive.read()
            setpoint = queue.setpoint(tick)
            stamp = queue.stamp_of(tick)
            if not drive.status().fresh:
                lost += 1
            else:
                out.state(sample.stamp_ns, encoder.encode_sample(sample))
                written += 1
            out.setpoint(stamp, encoder.encode_sample(setpoint.to_sample(stamp, keys.axis, nominal)))
            if tick % DRIVE_INFO_PERIOD == 0:
                out.drive(stamp, DriveInfo(stamp, keys.axis, SIMULATED, plant.profile, plant.source).encode())
            drive.apply(setpoint)
    origin = queue.stamp_of(queued[0].start_tick)
    end_s = (queue.stamp_of(queued[-1].end_tick) - origin) * 1e-9
    window = TimeWindow(-0.2, end_s + 0.2, origin)
    return OfflineRun(Path(path), end_tick, written, lost, window, drive)


class _Writer:
    """The two 1 kHz topics into one MCAP file, as the recorder writes them."""

    def __init__(self, path: str | Path, keys: AxisKeys) -> None:
        self._mcap = Ros2McapWriter(path)
        self._state = self._mcap.channel_for(topic_for_key(keys.state), JOINT_STATE_TYPE)
        self._setpoint = self._mcap.channel_for(topic_for_key(keys.setpoint), JOINT_STATE_TYPE)
        self._drive = self._mcap.channel_for(topic_for_key(keys.drive), DRIVE_INFO_TYPE)
        self._sequence = {self._state: 0, self._setpoint: 0, self._drive: 0}

    def __enter__(self) -> _Writer:
        return self

    def __exit__(self, *_exc: object) -> None:
        self._mcap.finish()

    def _add(self, channel: int, stamp_ns: int, data: bytes) -> None:
        self._sequence[channel] += 1
        self._mcap.add(channel, stamp_ns + RECORD_DELAY_NS, stamp_ns, self._sequence[channel], data)

    def state(self, stamp_ns: int, data: bytes) -> None:
        self._add(self._state, stamp_ns, data)

    def setpoint(self, stamp_ns: int, data: bytes) -> None:
        self._add(self._setpoint, stamp_ns, data)

    def drive(self, stamp_ns: int, data: bytes) -> None:
        self._add(self._drive, stamp_ns, data)
