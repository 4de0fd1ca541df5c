"""The one-call encoder of the axis JointState equals the contract's encoder byte for byte."""

import math
import random

import pytest
from axisflow.acquisition.errors import WireError
from axisflow.acquisition.wire.axis_sample_encoder import AxisSampleEncoder
from axisflow.acquisition.wire.messages import JOINT_STATE_SCHEMA, JOINT_STATE_TYPE, AxisSample
from mcap.records import Schema
from mcap_ros2.decoder import DecoderFactory


def _fields(s: AxisSample) -> tuple:
    return (s.stamp_ns, s.position_m, s.motor_angle_rad, s.velocity_m_s, s.motor_speed_rad_s, s.force_n,
            s.motor_torque_nm)  # fmt: skip


@pytest.mark.parametrize("axis", ["a0", "", "x", "ab", "abc", "abcd", "axis_with_a_long_name_7"])
def test_equals_the_contract_encoder_for_random_samples(axis):
    rng = random.Random(7)
    enc = AxisSampleEncoder(axis)
    specials = [0.0, -0.0, math.inf, -math.inf, 1e-300, -1e300]
    for i in range(2000):
        values = [rng.choice(specials) if i % 10 == 0 else rng.uniform(-1e3, 1e3) for _ in range(6)]
        stamp = rng.randrange(0, 2**31 * 10**9)
        sample = AxisSample(stamp, axis, *values)
        assert enc.encode(*_fields(sample)) == sample.encode()
        assert enc.encode_sample(sample) == sample.encode()
        assert len(sample.encode()) == enc.size


def test_nan_keeps_its_bits_and_an_independent_decoder_reads_it():
    enc = AxisSampleEncoder("a0")
    sample = AxisSample(1_700_000_000_123_456_789, "a0", 0.4, 0.1, math.nan, 133.0, 33.0, 0.05)
    data = enc.encode_sample(sample)
    assert data == sample.encode()

    schema = Schema(id=1, name=JOINT_STATE_TYPE, encoding="ros2msg", data=JOINT_STATE_SCHEMA.encode())
    msg = DecoderFactory().decoder_for("cdr", schema)(data)
    assert (msg.header.stamp.sec, msg.header.stamp.nanosec) == (1_700_000_000, 123_456_789)
    assert list(msg.name) == ["carriage", "motor"] and msg.header.frame_id == "a0"
    assert list(msg.position) == [0.4, 133.0] and list(msg.velocity) == [0.1, 33.0]
    assert math.isnan(msg.effort[0]) and msg.effort[1] == 0.05


def test_a_sample_of_another_axis_is_encoded_by_the_contract():
    sample = AxisSample(5, "b1", 1.0, 2.0, 3.0, 4.0, 5.0, 6.0)
    assert AxisSampleEncoder("a0").encode_sample(sample) == sample.encode()


def test_a_stamp_beyond_int32_seconds_is_refused_as_the_contract_refuses_it():
    with pytest.raises(WireError, match="int32 seconds range"):
        AxisSample(2**31 * 10**9, "a0", 0, 0, 0, 0, 0, 0).encode()
    with pytest.raises(WireError, match="int32 seconds range"):
        AxisSampleEncoder("a0").encode(2**31 * 10**9, 0, 0, 0, 0, 0, 0)
