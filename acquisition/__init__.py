"""Data acquisition: the wire records, the drives, the Zenoh bridge, the bus and the MCAP logs.

The folders follow the data path, from the drive to the disk:

* :mod:`.wire` — the contract: key expressions and the ROS 2 CDR records (samples, moves, statuses,
  plans, quick stops) that cross Zenoh and land in MCAP;
* :mod:`.drives` — the drive interface and its implementations (the simulated axis);
* :mod:`.bridge` — the 1 kHz loop between a drive and Zenoh, with its move queue and intake;
* :mod:`.bus` — Zenoh sessions, the numbered publisher, the move sender, the latest sample of an axis;
* :mod:`.logs` — the MCAP writer, the log readers, recover, and the recorder and replay.

Only :mod:`.bus`, :mod:`.bridge` (its loop and intake), the recorder and replay load Zenoh;
identification and the views use the rest, and reading a log never loads Zenoh (tests/test_layers.py).
Names of the Zenoh modules are importable from this package too; they are loaded (with zenoh) on first
use, so ``from axisflow.acquisition import AxisSample`` stays light. (The function ``replay`` is
imported from its module, ``axisflow.acquisition.logs.replay``, whose name it shares.)
"""

from __future__ import annotations

import importlib
from typing import Any

from .bridge.move_queue import MoveQueue
from .drives.drive import Drive, Setpoint
from .drives.plant import PlantConfig, load_plant, load_profile
from .drives.sim_axis import SimulatedAxis
from .errors import (
    AcquisitionError,
    BridgeLostError,
    DamagedLogWarning,
    MoveRejectedError,
    PlantError,
    RecordingError,
    WireError,
    ZenohConfigError,
    ZenohConnectError,
)
from .logs.reader import (
    DamagedChunk,
    Hole,
    JointColumns,
    JointStateColumns,
    RawMessage,
    RecordedMessage,
    SkippedChunk,
    TopicInfo,
    is_complete,
    iter_recording,
    list_topics,
    read_joint_states,
    read_messages,
)
from .logs.recover import RecoverReport, recover
from .wire.attachment import Attachment
from .wire.keys import AxisKeys, KeyExprError, all_keys, key_for_topic, topic_for_key
from .wire.messages import (
    APPEND,
    JOINT_STATE_TYPE,
    MOVE_TYPE,
    SCHEMAS,
    AxisSample,
    JointState,
    MoveCommand,
)
from .wire.move_status import MOVE_STATUS_TYPE, MoveState, MoveStatus
from .wire.plan_record import PLAN_TYPE, PlanRecord

_NETWORK_NAMES: dict[str, str] = {
    "AxisState": "bus.axis_state",
    "Bridge": "bridge.bridge",
    "BridgeConfig": "bridge.bridge",
    "BridgeReport": "bridge.bridge",
    "run_bridge": "bridge.bridge",
    "MoveSender": "bus.move_sender",
    "Recorder": "logs.recorder",
    "RecorderConfig": "logs.recorder",
    "RecordSummary": "logs.recorder",
    "ReplayReport": "logs.replay",
    "ZenohOptions": "bus.session",
    "build_config": "bus.session",
    "open_session": "bus.session",
}


def __getattr__(name: str) -> Any:
    """Load a name of the network layer (and zenoh) on first use."""
    module = _NETWORK_NAMES.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f".{module}", __name__), name)


__all__ = [
    "APPEND",
    "JOINT_STATE_TYPE",
    "MOVE_STATUS_TYPE",
    "MOVE_TYPE",
    "PLAN_TYPE",
    "SCHEMAS",
    "AcquisitionError",
    "BridgeLostError",
    "Attachment",
    "AxisKeys",
    "AxisSample",
    "DamagedChunk",
    "DamagedLogWarning",
    "Drive",
    "Hole",
    "JointColumns",
    "JointState",
    "JointStateColumns",
    "KeyExprError",
    "MoveCommand",
    "MoveQueue",
    "MoveRejectedError",
    "MoveState",
    "MoveStatus",
    "PlanRecord",
    "PlantConfig",
    "RawMessage",
    "PlantError",
    "RecordedMessage",
    "RecordingError",
    "RecoverReport",
    "Setpoint",
    "SkippedChunk",
    "SimulatedAxis",
    "TopicInfo",
    "WireError",
    "ZenohConfigError",
    "ZenohConnectError",
    "all_keys",
    "is_complete",
    "iter_recording",
    "key_for_topic",
    "list_topics",
    "load_plant",
    "load_profile",
    "read_joint_states",
    "read_messages",
    "recover",
    "topic_for_key",
    *_NETWORK_NAMES,
]
