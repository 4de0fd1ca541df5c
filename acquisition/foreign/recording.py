"""Foreign joints written as the recorder writes its logs: one ``sensor_msgs/msg/JointState`` topic in
an MCAP file of the ROS 2 profile, through the recorder's own writer
(:class:`~axisflow.acquisition.logs.recording_writer.RecordingWriter`: zstd chunks, message and chunk
indexes, statistics, summary) with payloads encoded in bulk
(:class:`~axisflow.acquisition.logs.joint_state_layout.JointStateLayout`).

Each sample is one message of one joint: header stamp = MCAP log time = publish time = the sample's
stamp [ns]; sequence numbers 1, 2, … over the file; ``frame_id`` empty (a joint state's usual);
velocity and effort arrays empty where the log has none.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..logs.chunking import DEFAULT_BACKLOG_BYTES
from ..logs.joint_state_layout import JointStateLayout
from ..logs.recording_writer import RecordingWriter
from ..wire.messages import JOINT_STATE_TYPE, JointState
from .samples import JointSamples

DEFAULT_TOPIC = "/joint_states"
"""the topic an import writes unless told: ROS 2's usual name for joint states"""


def _payloads(samples: JointSamples) -> np.ndarray:
    """The samples' JointState payloads as uint8 rows (n, size)."""
    one = (0.0,)
    layout, template = JointStateLayout.for_message(
        JointState(
            0,
            "",
            (samples.joint,),
            one,
            one if samples.velocity is not None else (),
            one if samples.effort is not None else (),
        )
    )
    empty = np.zeros((len(samples), 1))
    return layout.encode(
        template,
        samples.stamp_ns,
        samples.position[:, None],
        empty if samples.velocity is None else samples.velocity[:, None],
        empty if samples.effort is None else samples.effort[:, None],
    )


def write_joint_states(path: str | Path, logs: Sequence[JointSamples], topic: str = DEFAULT_TOPIC) -> int:
    """Write ``logs`` (in time order, not overlapping) to the new MCAP file ``path`` on ``topic``;
    returns the messages written. The writer is flushed before its backlog would drop a message."""
    writer = RecordingWriter(path)
    try:
        channel = writer.channel_for(topic, JOINT_STATE_TYPE)
        sequence = 0
        for samples in logs:
            rows = _payloads(samples)
            for stamp, payload in zip(samples.stamp_ns.tolist(), rows, strict=True):
                sequence += 1
                if writer.backlog > DEFAULT_BACKLOG_BYTES // 2:
                    writer.flush()
                writer.add(channel, stamp, stamp, sequence, payload.tobytes())
    finally:
        writer.finish()
    return writer.messages
