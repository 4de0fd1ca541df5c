"""A synthetic recording: one axis moving for an hour (or any duration) at 1 kHz, written fast.

What :func:`write_synthetic_log` writes is what ``axisflow record`` writes for one axis: an MCAP file in
the ROS 2 profile (header profile ``ros2``, schema ``sensor_msgs/msg/JointState`` in ``ros2msg`` from
:data:`~axisflow.acquisition.SCHEMAS`, channels in ``cdr`` with the ``offered_qos_profiles`` metadata),
zstd chunks of 512 KiB with message indexes and a summary, and the two 1 kHz topics interleaved in
arrival order — ``/axisflow/<axis>/state`` then ``/axisflow/<axis>/setpoint`` for each tick.

The motion is a sum of three sines about the middle of the stroke (amplitudes 0.1875, 0.075 and
0.025 of the stroke L at 0.2, 0.5 and 1.3 Hz, phases drawn from the seed): it crosses zero velocity
often and reaches ~0.675·L/s, which excites every term of the friction law. For tick k (t = k·1 ms):

* setpoint: x(t), ẋ(t) and the feed-forward F_ff = eq. (1) at (ẋ, ẍ) with the nominal ``params``,
  τ_ff = F_ff·r/i_r (:func:`axisflow.model.cart_force`, :func:`axisflow.model.motor_torque`);
* state: x quantised to the simulated encoder (2^17 counts per pulley revolution), ẋ plus
  N(0, 1 mm/s), and the measured torque τ = eq. (1) with ``true_params`` (the plant) plus the
  simulated torque sensor's N(0, 0.01 N·m); carriage effort F = τ·i_r/r with the nominal parameters.

Stamps advance by exactly 1 ms from ``start_ns``; publish time = stamp + 50 µs (state) or + 60 µs
(setpoint) plus 0–20 µs; log time = publish time + 400 µs + an exponential delay (mean 100 µs); MCAP
sequence numbers count 1, 2, … per topic. Everything random comes from ``numpy.random.default_rng
([seed, block])`` per block of 10 000 ticks, so a file is bit-for-bit reproducible from its spec, and
a shorter log is a prefix of a longer one with the same seed.

Payloads are encoded in bulk (:class:`.joint_state_layout.JointStateLayout`) and
handed pre-encoded to a plain ``mcap.writer.Writer``; its per-message ``add_message`` is what costs
the time (~200 k messages/s).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from mcap.writer import Writer

from ...model import (
    EXECUTION_PERIOD_NS,
    AxisParams,
    cart_force,
    cart_force_from_torque,
    default_params,
    motor_angle,
    motor_speed,
    motor_torque,
    move_ticks,
)
from ...model.encoder import axis_resolution_m
from ...model.files import atomic_path
from ..drives.plant import EncoderConfig, TorqueSensorConfig
from ..errors import RecordingError
from ..wire.keys import DEFAULT_AXIS, AxisKeys, topic_for_key
from ..wire.messages import AXIS_JOINTS, JOINT_STATE_TYPE, SCHEMAS, JointState
from .chunking import DEFAULT_CHUNK_SIZE
from .joint_state_layout import JointStateLayout
from .mcap_writer import COMPRESSIONS, LIBRARY, OFFERED_QOS_PROFILES

DEFAULT_START_NS = 1_767_225_600_000_000_000
"""first stamp of a synthetic log: 2026-01-01T00:00:00Z [ns since the Unix epoch]"""
BLOCK_TICKS = 10_000
"""ticks generated (and seeded) together; fixed, so that a log does not depend on how it is written"""
MOTION = ((0.1875, 0.2), (0.075, 0.5), (0.025, 1.3))
"""(amplitude as a fraction of the stroke L, frequency [Hz]) of the three sines of the motion"""
VELOCITY_NOISE_M_S = 1e-3
"""standard deviation of the state's velocity noise [m/s]"""
STATE_PUBLISH_DELAY_NS = 50_000
SETPOINT_PUBLISH_DELAY_NS = 60_000
PUBLISH_JITTER_NS = 20_000
RECORD_DELAY_NS = 400_000
RECORD_JITTER_MEAN_NS = 100_000.0


@dataclass(frozen=True)
class SyntheticLogSpec:
    """What to write; equal specs give bit-identical files."""

    duration_s: float = 3600.0
    seed: int = 0
    axis: str = DEFAULT_AXIS
    start_ns: int = DEFAULT_START_NS
    params: AxisParams = field(default_factory=default_params)
    """nominal parameters: the setpoint's feed-forward and the state's force-from-torque"""
    true_params: AxisParams | None = None
    """the plant's parameters for the state's measured torque (None: ``params``)"""
    compression: str = "zstd"
    chunk_size: int = DEFAULT_CHUNK_SIZE
    """MCAP chunk size before compression [bytes]"""

    def __post_init__(self) -> None:
        if not (math.isfinite(self.duration_s) and self.duration_s > 0):
            raise RecordingError(f"synthetic log duration_s = {self.duration_s} s must be > 0 s")
        if self.compression not in COMPRESSIONS:
            raise RecordingError(f"compression {self.compression!r} is not one of {', '.join(COMPRESSIONS)}")
        if self.chunk_size <= 0:
            raise RecordingError(f"chunk_size = {self.chunk_size} bytes must be > 0")

    @property
    def ticks(self) -> int:
        """1 kHz ticks in the log (per topic): those with 0 ≤ k·1 ms < duration."""
        return move_ticks(self.duration_s)

    @property
    def plant(self) -> AxisParams:
        return self.params if self.true_params is None else self.true_params

    def topic(self, kind: str) -> str:
        """The MCAP topic of the axis's ``state`` or ``setpoint`` key (``/axisflow/<axis>/<kind>``)."""
        keys = AxisKeys(self.axis)
        return topic_for_key({"state": keys.state, "setpoint": keys.setpoint}[kind])


@dataclass(frozen=True)
class SyntheticColumns:
    """One topic's messages of a block of ticks, as the reader returns them: ``stamp_ns``,
    ``log_time_ns``, ``publish_time_ns``, ``sequence`` (int64, (n,)) and ``position``, ``velocity``,
    ``effort`` (float64, (n, 2): carriage [m, m/s, N], motor [rad, rad/s, N·m])."""

    stamp_ns: np.ndarray
    log_time_ns: np.ndarray
    publish_time_ns: np.ndarray
    sequence: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    effort: np.ndarray


@dataclass(frozen=True)
class SyntheticBlock:
    state: SyntheticColumns
    setpoint: SyntheticColumns


@dataclass(frozen=True)
class SyntheticLog:
    """What :func:`write_synthetic_log` wrote."""

    path: Path
    spec: SyntheticLogSpec
    messages_per_topic: int
    size_bytes: int
    wall_s: float
    """time taken to write it [s]"""

    @property
    def topics(self) -> tuple[str, str]:
        return self.spec.topic("state"), self.spec.topic("setpoint")


def _phases(seed: int) -> np.ndarray:
    return np.random.default_rng([seed, 2**32 - 1]).uniform(0.0, 2.0 * math.pi, len(MOTION))


def _motion(t_s: np.ndarray, spec: SyntheticLogSpec) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """x [m], ẋ [m/s], ẍ [m/s²] of the sum of sines at times ``t_s``."""
    stroke = spec.params.L
    x = np.full_like(t_s, 0.5 * stroke)
    v = np.zeros_like(t_s)
    a = np.zeros_like(t_s)
    for (fraction, f_hz), phase in zip(MOTION, _phases(spec.seed), strict=True):
        w = 2.0 * math.pi * f_hz
        amp = fraction * stroke
        arg = w * t_s + phase
        x += amp * np.sin(arg)
        v += amp * w * np.cos(arg)
        a -= amp * w * w * np.sin(arg)
    return x, v, a


def synthetic_block(spec: SyntheticLogSpec, block: int) -> SyntheticBlock:
    """The state and setpoint columns of ticks [block·10 000, (block+1)·10 000) ∩ [0, spec.ticks)."""
    k0 = block * BLOCK_TICKS
    k = np.arange(k0, min(k0 + BLOCK_TICKS, spec.ticks), dtype=np.int64)
    n = len(k)
    rng = np.random.default_rng([spec.seed, block])

    def noise(draw: np.ndarray) -> np.ndarray:  # drawn for the whole block: the last one is a prefix
        return draw[:n]

    stamp_ns = spec.start_ns + k * EXECUTION_PERIOD_NS
    x, v, a = _motion(k * (EXECUTION_PERIOD_NS * 1e-9), spec)
    p, plant = spec.params, spec.plant

    force_ff = cart_force(v, a, p)
    setpoint_arrays = (
        np.column_stack([x, motor_angle(x, p)]),
        np.column_stack([v, motor_speed(v, p)]),
        np.column_stack([force_ff, motor_torque(force_ff, p)]),
    )
    m_per_count = axis_resolution_m(p, EncoderConfig().counts_per_rev)
    x_meas = np.round(x / m_per_count) * m_per_count
    v_meas = v + noise(rng.normal(0.0, VELOCITY_NOISE_M_S, BLOCK_TICKS))
    torque_noise = noise(rng.normal(0.0, TorqueSensorConfig().noise_std_nm, BLOCK_TICKS))
    torque = motor_torque(cart_force(v, a, plant), plant) + torque_noise
    state_arrays = (
        np.column_stack([x_meas, motor_angle(x_meas, p)]),
        np.column_stack([v_meas, motor_speed(v_meas, p)]),
        np.column_stack([cart_force_from_torque(torque, p), torque]),
    )
    columns = []
    for delay_ns, arrays in (
        (STATE_PUBLISH_DELAY_NS, state_arrays),
        (SETPOINT_PUBLISH_DELAY_NS, setpoint_arrays),
    ):
        publish = stamp_ns + delay_ns + noise(rng.integers(0, PUBLISH_JITTER_NS, BLOCK_TICKS))
        delay = noise(rng.exponential(RECORD_JITTER_MEAN_NS, BLOCK_TICKS)).astype(np.int64)
        log = publish + RECORD_DELAY_NS + delay
        columns.append(SyntheticColumns(stamp_ns, log, publish, k + 1, *arrays))
    return SyntheticBlock(state=columns[0], setpoint=columns[1])


def write_synthetic_log(path: str | Path, spec: SyntheticLogSpec | None = None) -> SyntheticLog:
    """Write the log of ``spec`` (default: one hour of axis ``a0``, seed 0) to ``path`` (replaced,
    atomically)."""
    spec = spec or SyntheticLogSpec()
    out = Path(path)
    layout, template = JointStateLayout.for_message(
        JointState(0, spec.axis, AXIS_JOINTS, (0.0, 0.0), (0.0, 0.0), (0.0, 0.0))
    )
    size = layout.size
    started = time.perf_counter()
    with atomic_path(out) as part, open(part, "wb") as fh:
        writer = Writer(fh, chunk_size=spec.chunk_size, compression=COMPRESSIONS[spec.compression])
        writer.start(profile="ros2", library=LIBRARY)
        schema_id = writer.register_schema(JOINT_STATE_TYPE, "ros2msg", SCHEMAS[JOINT_STATE_TYPE].encode())
        metadata = {"offered_qos_profiles": OFFERED_QOS_PROFILES}
        channels = [
            writer.register_channel(spec.topic(kind), "cdr", schema_id, metadata)
            for kind in ("state", "setpoint")
        ]
        add = writer.add_message
        for block in range((spec.ticks + BLOCK_TICKS - 1) // BLOCK_TICKS):
            both = synthetic_block(spec, block)
            streams = []
            for cols in (both.state, both.setpoint):
                blob = layout.encode(template, cols.stamp_ns, cols.position, cols.velocity, cols.effort)
                streams.append(
                    (
                        blob.tobytes(),
                        cols.log_time_ns.tolist(),
                        cols.publish_time_ns.tolist(),
                        cols.sequence.tolist(),
                    )
                )
            (s_blob, s_log, s_pub, s_seq), (p_blob, p_log, p_pub, p_seq) = streams
            s_ch, p_ch = channels
            for i in range(len(s_log)):
                a, b = i * size, (i + 1) * size
                add(s_ch, s_log[i], s_blob[a:b], s_pub[i], s_seq[i] & 0xFFFFFFFF)
                add(p_ch, p_log[i], p_blob[a:b], p_pub[i], p_seq[i] & 0xFFFFFFFF)
        writer.finish()
    wall_s = time.perf_counter() - started
    return SyntheticLog(out, spec, spec.ticks, out.stat().st_size, wall_s)
