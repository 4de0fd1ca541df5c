"""The two-joint ``sensor_msgs/msg/JointState`` of an axis, encoded in one call (the 1 kHz hot path).

For one axis name the CDR bytes of an :class:`~.messages.AxisSample` have a fixed layout: the
encapsulation header, the stamp (``int32`` seconds, ``uint32`` nanoseconds), the frame id (the axis
name), the joint names (``carriage``, ``motor``) and three sequences of two ``float64`` (position,
velocity, effort), each after its ``uint32`` length and the padding that aligns its doubles to 8. Only
the stamp and the six doubles change from one message to the next. :class:`AxisSampleEncoder` reads
that layout once from :meth:`AxisSample.encode` (the contract's one encoder, which stays the
reference) and then packs a message with one ``struct`` call: the constant runs of bytes between the
fields are passed as ``s`` fields. tests/acquisition/wire/test_axis_sample_encoder.py holds it to
``AxisSample.encode`` byte for byte.
"""

from __future__ import annotations

import struct

from ..errors import WireError
from .cdr import NS_PER_S
from .messages import AxisSample

_STAMP = struct.Struct("<iI")
_PAIR = struct.Struct("<dd")
# distinct sentinels for the six doubles: their bytes locate each field in the reference encoding
_SENTINELS = (1.0000000000000002, 2.0000000000000004, 3.000000000000001, 4.000000000000001,
              5.000000000000001, 6.000000000000001)  # fmt: skip
_STAMP_OFFSET = 4
"""the stamp follows the 4-byte encapsulation header"""


class AxisSampleEncoder:
    """Packs :class:`AxisSample` fields of one axis into their CDR bytes (see the module docstring)."""

    def __init__(self, axis: str) -> None:
        self.axis = axis
        s = _SENTINELS
        # position (carriage, motor), velocity (…), effort (…): the JointState's field order
        template = AxisSample(0, axis, s[0], s[2], s[4], s[1], s[3], s[5]).encode()
        offsets = []
        for a, b in ((s[0], s[1]), (s[2], s[3]), (s[4], s[5])):
            at = template.find(_PAIR.pack(a, b))
            if at < 0 or template.find(_PAIR.pack(a, b), at + 1) >= 0:
                raise WireError(f"the JointState of axis {axis!r} has no fixed layout to pack into")
            offsets.append(at)
        if not _STAMP_OFFSET + _STAMP.size <= offsets[0] < offsets[1] < offsets[2]:
            raise WireError(f"the JointState of axis {axis!r} has an unexpected layout")
        end = offsets[2] + _PAIR.size
        gaps = (
            template[_STAMP_OFFSET + _STAMP.size : offsets[0]],
            template[offsets[0] + _PAIR.size : offsets[1]],
            template[offsets[1] + _PAIR.size : offsets[2]],
        )
        self._head = template[:_STAMP_OFFSET]
        self._gaps = gaps
        self._tail = template[end:]
        self.size = len(template)
        self._struct = struct.Struct(
            f"<{_STAMP_OFFSET}siI{len(gaps[0])}sdd{len(gaps[1])}sdd{len(gaps[2])}sdd{len(self._tail)}s"
        )
        assert self._struct.size == self.size

    def encode(
        self,
        stamp_ns: int,
        position_m: float,
        motor_angle_rad: float,
        velocity_m_s: float,
        motor_speed_rad_s: float,
        force_n: float,
        motor_torque_nm: float,
    ) -> bytes:
        """The CDR bytes of the sample with these fields (in the JointState's order: position,
        velocity, effort; carriage then motor), equal to ``AxisSample(...).encode()``."""
        sec, nsec = divmod(stamp_ns, NS_PER_S)
        g = self._gaps
        try:
            return self._struct.pack(
                self._head, sec, nsec, g[0], position_m, motor_angle_rad, g[1], velocity_m_s,
                motor_speed_rad_s, g[2], force_n, motor_torque_nm, self._tail,
            )  # fmt: skip
        except struct.error:
            raise WireError(
                f"time stamp {stamp_ns} ns is outside the int32 seconds range of builtin_interfaces/Time"
            ) from None

    def encode_sample(self, sample: AxisSample) -> bytes:
        """``sample.encode()`` for a sample of this encoder's axis."""
        if sample.axis != self.axis:
            return sample.encode()
        return self.encode(
            sample.stamp_ns, sample.position_m, sample.motor_angle_rad, sample.velocity_m_s,
            sample.motor_speed_rad_s, sample.force_n, sample.motor_torque_nm,
        )  # fmt: skip
