"""Logs for the identification tests, written by writers other than axisflow's recorder."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from axisflow.model import cart_force, default_params, motor_torque

NOMINAL = default_params()
PLANT = NOMINAL.replace(m=95.0, a1=80.0, a2=195.0, a3=214.0, a4=10.3)
"""the 'true' axis of the foreign logs"""

JOINT_STATE_DEF = (
    "std_msgs/Header header\nstring[] name\nfloat64[] position\nfloat64[] velocity\nfloat64[] effort\n"
    "================================================================================\nMSG: std_msgs/Header\n"
    "builtin_interfaces/Time stamp\nstring frame_id\n"
    "================================================================================\n"
    "MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n"
)


def motion(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Position, velocity, acceleration of a slow, growing sinusoid about mid-stroke."""
    w = 2 * math.pi * 0.25
    amp = 0.02 + 0.3 * t / t[-1]
    x = 0.4 + amp * np.sin(w * t)
    v = 0.3 / t[-1] * np.sin(w * t) + amp * w * np.cos(w * t)
    a = 2 * 0.3 / t[-1] * w * np.cos(w * t) - amp * w * w * np.sin(w * t)
    return x, v, a


def brisk_motion(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Two sinusoids (0.3 Hz, 0.15 m and 1.1 Hz, 0.03 m): accelerations up to 2 m/s² that vary apart
    from the speed, so that the torque's timing shows (a single sinusoid's delay looks exactly like a
    change of a2 and M_eq: its jerk is −ω²·v). 3 N·m at most, below the drive's limit."""
    x, v, a = np.full_like(t, 0.4), np.zeros_like(t), np.zeros_like(t)
    for amp, hz in ((0.15, 0.3), (0.03, 1.1)):
        w = 2 * math.pi * hz
        x += amp * np.sin(w * t)
        v += amp * w * np.cos(w * t)
        a -= amp * w * w * np.sin(w * t)
    return x, v, a


def write_foreign_log(
    path: Path,
    duration_s: float = 40.0,
    *,
    topic: str = "/robot/joint_states",
    joints: tuple[str, ...] = ("base_yaw", "slider_motor", "gripper"),
    slider: int = 1,
    noise_nm: float = 0.01,
    edit=None,  # callable(t_ns, pos, vel, eff) -> (t_ns, pos, vel, eff), to spoil the log
    compression: str = "zstd",
    delay_s: float = 0.0,
    kinematics=motion,
    velocity: bool = True,
    others: bool = True,
) -> Path:
    """A ROS 2 bag-like MCAP by mcap_ros2's writer: a JointState topic whose joint ``slider`` is a motor
    (rad, rad/s, N·m) driving the axis PLANT, interleaved with a second JointState topic and a
    std_msgs/String topic in the same chunks. The torque describes the instant ``delay_s`` before its
    stamp; ``velocity`` False sends empty velocity arrays (as many drivers do); ``others`` False leaves
    the second JointState topic and the String topic out."""
    from mcap.writer import CompressionType
    from mcap_ros2.writer import Writer

    rng = np.random.default_rng(1)
    t = np.arange(0.0, duration_s, 1e-3)
    x, v, a = kinematics(t)
    _, v_then, a_then = kinematics(t - delay_s) if delay_s else (x, v, a)
    k = PLANT.i_r / PLANT.r
    pos = np.zeros((t.size, len(joints)))
    vel = np.zeros_like(pos)
    eff = np.zeros_like(pos)
    pos[:, slider], vel[:, slider] = x * k, v * k
    torque = motor_torque(cart_force(v_then, a_then, PLANT), PLANT)
    eff[:, slider] = torque + rng.normal(0.0, noise_nm, t.size)
    t_ns = 1_700_000_000 * 10**9 + np.arange(t.size, dtype=np.int64) * 1_000_000
    if edit is not None:
        t_ns, pos, vel, eff = edit(t_ns, pos, vel, eff)
    comp = {"zstd": CompressionType.ZSTD, "lz4": CompressionType.LZ4, "none": CompressionType.NONE}[
        compression
    ]
    with open(path, "wb") as fh:
        writer = Writer(fh, compression=comp, chunk_size=256 * 1024)
        js = writer.register_msgdef("sensor_msgs/msg/JointState", JOINT_STATE_DEF)
        text = writer.register_msgdef("std_msgs/msg/String", "string data\n")
        for i, stamp in enumerate(t_ns.tolist()):
            sec, nsec = divmod(stamp, 10**9)
            header = {"stamp": {"sec": sec, "nanosec": nsec}, "frame_id": "robot"}
            msg = {"header": header, "name": list(joints), "position": pos[i].tolist(),
                   "velocity": vel[i].tolist() if velocity else [], "effort": eff[i].tolist()}  # fmt: skip
            writer.write_message(topic, js, msg, log_time=stamp, publish_time=stamp)
            if others and i % 10 == 0:
                other = {
                    "header": header,
                    "name": ["wrist"],
                    "position": [0.1],
                    "velocity": [0.0],
                    "effort": [0.0],
                }
                writer.write_message("/arm/joint_states", js, other, log_time=stamp, publish_time=stamp)
            if others and i % 500 == 0:
                writer.write_message(
                    "/rosout_text", text, {"data": f"tick {i}"}, log_time=stamp, publish_time=stamp
                )
        writer.finish()
    return path


@pytest.fixture(scope="session")
def foreign_log(tmp_path_factory) -> Path:
    return write_foreign_log(tmp_path_factory.mktemp("foreign") / "bag.mcap")
