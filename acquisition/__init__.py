"""Data acquisition: the Zenoh drive bridge, the simulated axis and the MCAP recorder (issue 4).

Wire contract: :mod:`.keys` (key expressions), :mod:`.messages` (ROS 2 CDR records and schemas),
:mod:`.attachment` (sequence numbers). Drive side: :mod:`.drive` (the interface),
:mod:`.sim_axis` (the simulated axis), :mod:`.move_queue`, :mod:`.bridge`, :mod:`.move_sender`
(the API to send moves). Recording: :mod:`.recorder`, :mod:`.mcap_writer`, :mod:`.recording`,
:mod:`.recover`, :mod:`.replay`. Sessions: :mod:`.zenoh_config`.
"""

from .attachment import Attachment
from .bridge import BridgeConfig, BridgeReport, run_bridge
from .drive import DRIVE_PERIOD_NS, Drive, Setpoint
from .errors import (
    AcquisitionError,
    MoveRejectedError,
    PlantError,
    RecordingError,
    WireError,
    ZenohConfigError,
)
from .keys import AxisKeys, KeyExprError, all_keys, key_for_topic, topic_for_key
from .messages import (
    APPEND,
    JOINT_STATE_TYPE,
    MOVE_TYPE,
    SCHEMAS,
    AxisSample,
    BridgeEvent,
    JointState,
    MoveCommand,
)
from .move_queue import MoveQueue
from .move_sender import MoveSender
from .recorder import Recorder, RecorderConfig, RecordSummary
from .recording import RecordedMessage, is_complete, iter_recording
from .recover import RecoverReport, recover
from .replay import ReplayReport, replay
from .sim_axis import PlantConfig, SimulatedAxis, load_plant
from .zenoh_config import ZenohOptions, build_config, open_session

__all__ = [
    "APPEND",
    "DRIVE_PERIOD_NS",
    "JOINT_STATE_TYPE",
    "MOVE_TYPE",
    "SCHEMAS",
    "AcquisitionError",
    "Attachment",
    "AxisKeys",
    "AxisSample",
    "BridgeConfig",
    "BridgeEvent",
    "BridgeReport",
    "Drive",
    "JointState",
    "KeyExprError",
    "MoveCommand",
    "MoveQueue",
    "MoveRejectedError",
    "MoveSender",
    "PlantConfig",
    "PlantError",
    "RecordSummary",
    "RecordedMessage",
    "Recorder",
    "RecorderConfig",
    "RecordingError",
    "RecoverReport",
    "ReplayReport",
    "Setpoint",
    "SimulatedAxis",
    "WireError",
    "ZenohConfigError",
    "ZenohOptions",
    "all_keys",
    "build_config",
    "is_complete",
    "iter_recording",
    "key_for_topic",
    "load_plant",
    "open_session",
    "recover",
    "replay",
    "run_bridge",
    "topic_for_key",
]
