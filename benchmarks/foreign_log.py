"""A log as another tool writes it: one JointState topic of one joint, position and effort only (no
velocity), the stamps as given (jitter and lost samples kept), written with axisflow's MCAP writer in
the ROS 2 profile. The rigs of ``bench identify-real`` write their logs this way."""

from __future__ import annotations

from pathlib import Path

import numpy as np

FOREIGN_TOPIC = "/rig/joint_states"


def write_joint_log(
    path: str | Path,
    stamp_ns: np.ndarray,
    position: np.ndarray,
    effort: np.ndarray,
    joint: str,
    topic: str = FOREIGN_TOPIC,
) -> Path:
    """Write the samples (int64 stamps [ns], the joint's position and effort in its units) to ``path``,
    atomically; every message has empty velocity arrays."""
    from ..acquisition.logs.joint_state_layout import JointStateLayout
    from ..acquisition.logs.mcap_writer import Ros2McapWriter
    from ..acquisition.wire.messages import JOINT_STATE_TYPE, JointState
    from ..model.files import atomic_path

    out = Path(path)
    stamps = np.asarray(stamp_ns, dtype=np.int64)
    layout, template = JointStateLayout.for_message(JointState(0, "rig", (joint,), (0.0,), (), (0.0,)))
    rows = layout.encode(
        template,
        stamps,
        np.asarray(position, dtype=float)[:, None],
        np.empty((stamps.size, 0)),
        np.asarray(effort, dtype=float)[:, None],
    )
    with atomic_path(out) as part:
        writer = Ros2McapWriter(part)
        try:
            channel = writer.channel_for(topic, JOINT_STATE_TYPE)
            for i, stamp in enumerate(stamps.tolist()):
                writer.add(channel, stamp, stamp, i + 1, rows[i].tobytes())
        finally:
            writer.finish()
    return out
