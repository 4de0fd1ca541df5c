"""Data acquisition: the wire records, the drive side, the Zenoh bridge and the MCAP recorder.

Two layers, each importing only the one below it (and :mod:`axisflow.model`):

* **records and logs** — no Zenoh: the wire contract (:mod:`.keys` key expressions, :mod:`.messages`
  and :mod:`.move_status` ROS 2 CDR records and schemas, :mod:`.cdr`, :mod:`.attachment`), the drive
  side (:mod:`.drive` the interface, :mod:`.sim_axis` the simulated axis, :mod:`.move_queue`) and the
  logs (:mod:`.mcap_writer`, :mod:`.recording`, :mod:`.log_reader`, :mod:`.recover`). Identification
  and the views use this layer; importing it never loads zenoh.
* **network** — Zenoh sessions (:mod:`.zenoh_config`, :mod:`.publisher`), the bridge (:mod:`.bridge`,
  :mod:`.move_intake`), :mod:`.move_sender` (the planner's API) and :mod:`.axis_state` (where an
  axis is), :mod:`.recorder`, :mod:`.replay`.

Names of the network layer are importable from this package too; they are loaded (with zenoh) on
first use, so ``from axisflow.acquisition import AxisSample`` stays light. (The function ``replay``
is imported from its module, ``axisflow.acquisition.replay``, whose name it shares.)
"""

from __future__ import annotations

import importlib
from typing import Any

from .attachment import Attachment
from .drive import Drive, Setpoint
from .errors import (
    AcquisitionError,
    BridgeLostError,
    MoveRejectedError,
    PlantError,
    RecordingError,
    WireError,
    ZenohConfigError,
    ZenohConnectError,
)
from .keys import AxisKeys, KeyExprError, all_keys, key_for_topic, topic_for_key
from .log_reader import (
    JointColumns,
    JointStateColumns,
    RawMessage,
    TopicInfo,
    list_topics,
    read_joint_states,
    read_messages,
)
from .messages import (
    APPEND,
    JOINT_STATE_TYPE,
    MOVE_TYPE,
    SCHEMAS,
    AxisSample,
    JointState,
    MoveCommand,
)
from .move_queue import MoveQueue
from .move_status import MOVE_STATUS_TYPE, MoveState, MoveStatus
from .plan_record import PLAN_TYPE, PlanRecord
from .recording import RecordedMessage, is_complete, iter_recording
from .recover import RecoverReport, recover
from .sim_axis import PlantConfig, SimulatedAxis, load_plant

_NETWORK_NAMES: dict[str, str] = {
    "AxisState": "axis_state",
    "Bridge": "bridge",
    "BridgeConfig": "bridge",
    "BridgeReport": "bridge",
    "run_bridge": "bridge",
    "MoveSender": "move_sender",
    "Recorder": "recorder",
    "RecorderConfig": "recorder",
    "RecordSummary": "recorder",
    "ReplayReport": "replay",
    "ZenohOptions": "zenoh_config",
    "build_config": "zenoh_config",
    "open_session": "zenoh_config",
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
    "Drive",
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
    "read_joint_states",
    "read_messages",
    "recover",
    "topic_for_key",
    *_NETWORK_NAMES,
]
