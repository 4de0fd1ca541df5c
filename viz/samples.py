"""The samples a view shows, taken out of JointState messages of the axis contract.

A state or setpoint message carries two joints (docs/acquisition.md): ``carriage`` [m, m/s, N] and
``motor`` [rad, rad/s, N·m]. The views need the carriage position and velocity, the motor torque
(measured, or the feed-forward of a setpoint) and the motor speed (for τ_m·ω_m). :class:`AxisSamples`
holds those columns for a batch of messages, from a log (:meth:`AxisSamples.of_columns`, the fast
reader's columns) or from payloads received live (:func:`decode_payloads`, decoded in bulk with
:class:`~axisflow.acquisition.logs.joint_state_layout.JointStateLayout` where the payloads share one layout,
one by one with :meth:`JointState.decode` where they do not).
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..acquisition.logs.joint_state_layout import JointStateLayout
from ..acquisition.logs.reader import JointStateColumns
from ..acquisition.wire.messages import CARRIAGE_JOINT, MOTOR_JOINT, JointState
from .errors import VizError


@dataclass(frozen=True)
class AxisSamples:
    """n samples of one topic of an axis: ``stamp_ns`` (int64, header stamp [ns since the epoch]) and
    float64 columns, each of shape (n,)."""

    stamp_ns: np.ndarray
    position_m: np.ndarray
    velocity_m_s: np.ndarray
    torque_nm: np.ndarray
    """measured motor torque (state) or the model feed-forward (setpoint)"""
    motor_speed_rad_s: np.ndarray

    def __len__(self) -> int:
        return len(self.stamp_ns)

    @classmethod
    def of_columns(cls, columns: JointStateColumns) -> AxisSamples:
        """The carriage and motor columns of a topic read by
        :func:`~axisflow.acquisition.logs.reader.read_joint_states` (rows in file order)."""
        return cls.of_joints(
            columns.stamp_ns,
            columns.position,
            columns.velocity,
            columns.effort,
            columns.joint_names,
            columns.topic,
        )

    @classmethod
    def of_joints(
        cls,
        stamp_ns: np.ndarray,
        position: np.ndarray,
        velocity: np.ndarray,
        effort: np.ndarray,
        names: Sequence[str],
        where: str,
    ) -> AxisSamples:
        """The axis's columns out of rows × joints arrays whose joints are ``names`` (a
        :class:`VizError` naming ``where`` if the carriage or the motor joint is missing)."""
        c, m = _joint(names, CARRIAGE_JOINT, where), _joint(names, MOTOR_JOINT, where)
        return cls(stamp_ns, position[:, c], velocity[:, c], effort[:, m], velocity[:, m])

    @classmethod
    def concatenate(cls, parts: Sequence[AxisSamples]) -> AxisSamples:
        """One batch of several, in order."""
        return cls(*(np.concatenate([getattr(p, f) for p in parts]) for f in _FIELDS))

    def sorted(self) -> AxisSamples:
        """The same samples in increasing stamp order (itself if already so; stable)."""
        if len(self) < 2 or bool(np.all(self.stamp_ns[1:] >= self.stamp_ns[:-1])):
            return self
        order = np.argsort(self.stamp_ns, kind="stable")
        return AxisSamples(*(getattr(self, f)[order] for f in _FIELDS))


_FIELDS = ("stamp_ns", "position_m", "velocity_m_s", "torque_nm", "motor_speed_rad_s")


def _joint(names: Sequence[str], joint: str, where: str) -> int:
    if joint not in names:
        raise VizError(
            f"{where}: the JointState has joints {list(names)}, the axis contract needs "
            f"{CARRIAGE_JOINT!r} and {MOTOR_JOINT!r}"
        )
    return list(names).index(joint)


def _of_layout(layout: JointStateLayout, rows: np.ndarray, where: str) -> AxisSamples:
    """The samples of payload ``rows`` of one fixed ``layout``."""
    d = layout.decode(rows)
    return AxisSamples.of_joints(d.stamp_ns, d.position, d.velocity, d.effort, layout.joint_names, where)


def _decode_one_layout(payloads: Sequence[bytes], where: str) -> AxisSamples | None:
    """The usual case at once — every payload of one layout (one publisher) — or None."""
    if not payloads or len({len(p) for p in payloads}) != 1:
        return None
    rows = np.frombuffer(b"".join(payloads), dtype=np.uint8).reshape(len(payloads), -1)
    layout = JointStateLayout.of(payloads[0])
    if layout is None or not layout.matches(rows):
        return None
    return _of_layout(layout, rows, where)


def decode_payloads(payloads: Sequence[bytes], where: str) -> AxisSamples:
    """The samples of JointState CDR payloads (one topic), in the order given.

    Payloads of one length whose constant bytes (frame_id, joint names, counts, padding) agree are
    decoded together at fixed offsets; the rest one by one. Raises
    :class:`~axisflow.acquisition.errors.WireError` for a payload that does not decode and
    :class:`VizError` for joints that are not the axis contract (``where`` names the key).
    """
    whole = _decode_one_layout(payloads, where)
    if whole is not None:
        return whole
    by_size: dict[int, list[int]] = defaultdict(list)
    for i, payload in enumerate(payloads):
        by_size[len(payload)].append(i)
    n = len(payloads)
    stamp = np.empty(n, dtype=np.int64)
    out = {f: np.empty(n) for f in _FIELDS[1:]}
    for size, rows_at in by_size.items():
        index = np.asarray(rows_at)
        rows = np.frombuffer(b"".join(payloads[i] for i in rows_at), dtype=np.uint8).reshape(-1, size)
        layout = JointStateLayout.of(payloads[rows_at[0]])
        if layout is not None and layout.matches(rows):
            part = _of_layout(layout, rows, where)
            stamp[index] = part.stamp_ns
            for f in _FIELDS[1:]:
                out[f][index] = getattr(part, f)
            continue
        for i in rows_at:
            message = JointState.decode(payloads[i])
            c = _joint(message.name, CARRIAGE_JOINT, where)
            m = _joint(message.name, MOTOR_JOINT, where)
            stamp[i] = message.stamp_ns
            values = (message.position, message.velocity, message.effort, message.velocity)
            for f, array, j in zip(_FIELDS[1:], values, (c, c, m, m), strict=True):
                out[f][i] = array[j] if j < len(array) else np.nan
    return AxisSamples(
        stamp, out["position_m"], out["velocity_m_s"], out["torque_nm"], out["motor_speed_rad_s"]
    )
