"""Data acquisition: the wire records, the drives, the Zenoh bridge, the bus and the MCAP logs.

Installs as ``axisflow.acquisition`` from the folder ``acquisition/`` (pyproject.toml maps each top-level
folder to a sub-package of ``axisflow``; docs/architecture.md draws their imports).

The folders follow the data path, from the drive to the disk:

* :mod:`.wire` — the contract: key expressions and the ROS 2 CDR records (samples, moves, statuses,
  plans, quick stops) that cross Zenoh and land in MCAP;
* :mod:`.drives` — the drive interface and its implementations (the simulated axis);
* :mod:`.bridge` — the 1 kHz loop between a drive and Zenoh, with its move queue and intake;
* :mod:`.bus` — Zenoh sessions, the numbered publisher, the move sender, the latest sample of an axis;
* :mod:`.logs` — the MCAP writer, the log readers, recover, and the recorder and replay.

Only :mod:`.bus`, :mod:`.bridge` (its loop, intake and admission), the recorder and replay load Zenoh;
identification and the views use the rest, and reading a log never loads Zenoh (tests/test_layers.py).
Names of the Zenoh modules are importable from this package too. Every name is loaded with its module
on first use, so ``from axisflow.acquisition import AxisSample`` loads no Zenoh, and importing one module
(``axisflow.acquisition.wire.keys``, say) costs that module only. (The function ``replay`` is
imported from its module, ``axisflow.acquisition.logs.replay``, whose name it shares.)
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..model import lazy_names

if TYPE_CHECKING:  # what a type checker sees; at run time __getattr__ loads each name from _HOMES
    from .bridge.bridge import Bridge, run_bridge  # noqa: F401
    from .bridge.config import BridgeConfig  # noqa: F401
    from .bridge.move_queue import MoveQueue  # noqa: F401
    from .bridge.report import BridgeReport  # noqa: F401
    from .bus.axis_state import AxisState  # noqa: F401
    from .bus.move_sender import MoveSender  # noqa: F401
    from .bus.options import ZenohOptions  # noqa: F401
    from .bus.session import build_config, open_session  # noqa: F401
    from .drives.drive import Drive, Setpoint  # noqa: F401
    from .drives.plant import PlantConfig, load_plant, load_profile  # noqa: F401
    from .drives.sim_axis import SimulatedAxis  # noqa: F401
    from .errors import (  # noqa: F401
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
    from .logs.reader import (  # noqa: F401
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
    from .logs.recorder import Recorder, RecorderConfig, RecordSummary  # noqa: F401
    from .logs.recover import RecoverReport, recover  # noqa: F401
    from .logs.replay import ReplayReport  # noqa: F401
    from .wire.attachment import Attachment  # noqa: F401
    from .wire.keys import AxisKeys, KeyExprError, all_keys, key_for_topic, topic_for_key  # noqa: F401
    from .wire.messages import (  # noqa: F401
        APPEND,
        JOINT_STATE_TYPE,
        MOVE_TYPE,
        SCHEMAS,
        AxisSample,
        JointState,
        MoveCommand,
    )
    from .wire.move_status import MOVE_STATUS_TYPE, MoveState, MoveStatus  # noqa: F401
    from .wire.plan_record import PLAN_TYPE, PlanRecord  # noqa: F401

# each public name → its module, relative to this package
_HOMES: dict[str, str] = {
    "MoveQueue": "bridge.move_queue",
    "Drive": "drives.drive",
    "Setpoint": "drives.drive",
    "PlantConfig": "drives.plant",
    "load_plant": "drives.plant",
    "load_profile": "drives.plant",
    "SimulatedAxis": "drives.sim_axis",
    "AcquisitionError": "errors",
    "BridgeLostError": "errors",
    "DamagedLogWarning": "errors",
    "MoveRejectedError": "errors",
    "PlantError": "errors",
    "RecordingError": "errors",
    "WireError": "errors",
    "ZenohConfigError": "errors",
    "ZenohConnectError": "errors",
    "DamagedChunk": "logs.reader",
    "Hole": "logs.reader",
    "JointColumns": "logs.reader",
    "JointStateColumns": "logs.reader",
    "RawMessage": "logs.reader",
    "RecordedMessage": "logs.reader",
    "SkippedChunk": "logs.reader",
    "TopicInfo": "logs.reader",
    "is_complete": "logs.reader",
    "iter_recording": "logs.reader",
    "list_topics": "logs.reader",
    "read_joint_states": "logs.reader",
    "read_messages": "logs.reader",
    "RecoverReport": "logs.recover",
    "recover": "logs.recover",
    "Attachment": "wire.attachment",
    "AxisKeys": "wire.keys",
    "KeyExprError": "wire.keys",
    "all_keys": "wire.keys",
    "key_for_topic": "wire.keys",
    "topic_for_key": "wire.keys",
    "APPEND": "wire.messages",
    "JOINT_STATE_TYPE": "wire.messages",
    "MOVE_TYPE": "wire.messages",
    "SCHEMAS": "wire.messages",
    "AxisSample": "wire.messages",
    "JointState": "wire.messages",
    "MoveCommand": "wire.messages",
    "MOVE_STATUS_TYPE": "wire.move_status",
    "MoveState": "wire.move_status",
    "MoveStatus": "wire.move_status",
    "PLAN_TYPE": "wire.plan_record",
    "PlanRecord": "wire.plan_record",
    "AxisState": "bus.axis_state",
    "Bridge": "bridge.bridge",
    "BridgeConfig": "bridge.config",
    "BridgeReport": "bridge.report",
    "run_bridge": "bridge.bridge",
    "MoveSender": "bus.move_sender",
    "Recorder": "logs.recorder",
    "RecorderConfig": "logs.recorder",
    "RecordSummary": "logs.recorder",
    "ReplayReport": "logs.replay",
    "ZenohOptions": "bus.options",
    "build_config": "bus.session",
    "open_session": "bus.session",
}


__getattr__ = lazy_names(__name__, _HOMES)


__all__ = sorted(_HOMES)
