"""Round trips of every wire record, checked against mcap_ros2's independent CDR codec."""

import dataclasses
import math
from pathlib import Path

import pytest
from axisflow.acquisition import (
    JOINT_STATE_TYPE,
    MOVE_STATUS_TYPE,
    MOVE_TYPE,
    SCHEMAS,
    Attachment,
    AxisSample,
    JointState,
    MoveCommand,
    MoveState,
    MoveStatus,
    WireError,
)
from axisflow.acquisition.wire.cdr import CdrWriter, write_time
from axisflow.acquisition.wire.params_estimate import PARAMS_ESTIMATE_TYPE, Decision, ParamsEstimate
from axisflow.acquisition.wire.quick_stop import QUICK_STOP_TYPE, QuickStop
from mcap_ros2._dynamic import generate_dynamic, serialize_dynamic

SAMPLE = AxisSample(
    stamp_ns=1_700_000_000_123_000_000,
    axis="a0",
    position_m=0.4,
    velocity_m_s=-0.25,
    force_n=12.5,
    motor_angle_rad=133.3,
    motor_speed_rad_s=-83.3,
    motor_torque_nm=0.0375,
)
MOVE = MoveCommand(
    stamp_ns=1_700_000_000_000_000_001,
    axis="a0",
    move_id=7,
    start_ns=1_700_000_001_000_000_000,
    law="poly5",
    start_position_m=0.1,
    end_position_m=0.6,
    duration_s=0.9,
)


def _reference(type_name: str):
    return generate_dynamic(type_name, SCHEMAS[type_name])[type_name]


def test_axis_sample_round_trip_and_reference_decode():
    data = SAMPLE.encode()
    assert AxisSample.decode(data) == SAMPLE
    ref = _reference(JOINT_STATE_TYPE)(data)
    assert ref.header.stamp.sec * 10**9 + ref.header.stamp.nanosec == SAMPLE.stamp_ns
    assert ref.header.frame_id == "a0"
    assert ref.name == ["carriage", "motor"]
    assert list(ref.position) == [0.4, 133.3]
    assert list(ref.velocity) == [-0.25, -83.3]
    assert list(ref.effort) == [12.5, 0.0375]


def test_joint_state_bytes_equal_reference_encoder():
    js = SAMPLE.to_joint_state()
    encode = serialize_dynamic(JOINT_STATE_TYPE, SCHEMAS[JOINT_STATE_TYPE])[JOINT_STATE_TYPE]
    ref_bytes = encode(
        {
            "header": {"stamp": {"sec": 1_700_000_000, "nanosec": 123_000_000}, "frame_id": "a0"},
            "name": list(js.name),
            "position": list(js.position),
            "velocity": list(js.velocity),
            "effort": list(js.effort),
        }
    )
    assert js.encode() == ref_bytes


@pytest.mark.parametrize(
    "js",
    [
        JointState(0, "", (), (), (), ()),
        JointState(5, "x", ("a", "bb", "ccc"), (1.0, 2.0, 3.0), (), (0.5,)),
        JointState(-1_500_000_000, "neg", ("j",), (1.0,), (2.0,), (3.0,)),
    ],
)
def test_joint_state_round_trip(js):
    assert JointState.decode(js.encode()) == js


def test_move_round_trip_and_reference_decode():
    data = MOVE.encode()
    assert MoveCommand.decode(data) == MOVE
    ref = _reference(MOVE_TYPE)(data)
    assert (ref.move_id, ref.law, ref.duration_s) == (7, "poly5", 0.9)
    assert (ref.start_position_m, ref.end_position_m) == (0.1, 0.6)
    assert ref.start.sec * 10**9 + ref.start.nanosec == MOVE.start_ns


STATUS = MoveStatus(
    stamp_ns=1_700_000_000_250_000_000,
    axis="a0",
    state=MoveState.REJECTED,
    move_id=3,
    tick=250,
    start_tick=-1,
    end_tick=-1,
    sender=bytes(range(16)).hex(),
    text="rejected move 3: start_position_m = 0.2 m jumps",
)


def test_move_status_round_trip_and_reference_codec():
    data = STATUS.encode()
    assert MoveStatus.decode(data) == STATUS
    ref = _reference(MOVE_STATUS_TYPE)(data)
    assert (ref.status, ref.move_id, ref.tick, ref.start_tick, ref.end_tick) == (2, 3, 250, -1, -1)
    assert (ref.header.frame_id, ref.sender, ref.text) == ("a0", STATUS.sender, STATUS.text)
    assert ref.header.stamp.sec * 10**9 + ref.header.stamp.nanosec == STATUS.stamp_ns
    encode = serialize_dynamic(MOVE_STATUS_TYPE, SCHEMAS[MOVE_STATUS_TYPE])[MOVE_STATUS_TYPE]
    ref_bytes = encode(
        {
            "header": {"stamp": {"sec": 1_700_000_000, "nanosec": 250_000_000}, "frame_id": "a0"},
            "status": 2,
            "move_id": 3,
            "tick": 250,
            "start_tick": -1,
            "end_tick": -1,
            "sender": STATUS.sender,
            "text": STATUS.text,
            "error_code": 0,
            "error_register": 0,
            "statusword": 0,
        }
    )
    assert bytes(ref_bytes) == data
    # the schema's constants are the enum's values, for readers that only have the schema
    for state in MoveState:
        assert f"uint8 {state.name}={state.value}" in SCHEMAS[MOVE_STATUS_TYPE]


def test_move_status_with_an_unknown_state_is_a_wire_error():
    data = bytearray(STATUS.encode())
    data[data.index(b"a0\x00") + 3] = 99  # the status byte (uint8: no padding) follows the frame id
    with pytest.raises(WireError, match="move status 99 is not one of 1 \\(accepted\\)"):
        MoveStatus.decode(bytes(data))


FAULT = MoveStatus(
    stamp_ns=1_700_000_000_250_000_000,
    axis="a0",
    state=MoveState.FAULT,
    move_id=0,
    tick=250,
    text="drive node 5 faulted: 0x2310 continuous over-current",
    error_code=0x2310,
    error_register=0x03,
    statusword=0x0218,
)


def test_a_drive_event_round_trips_through_both_codecs():
    data = FAULT.encode()
    assert MoveStatus.decode(data) == FAULT
    ref = _reference(MOVE_STATUS_TYPE)(data)
    assert (ref.status, ref.error_code, ref.error_register, ref.statusword) == (7, 0x2310, 3, 0x0218)
    assert ref.text == FAULT.text


def test_a_status_recorded_before_the_drive_fields_existed_decodes_with_them_zero():
    w = CdrWriter()  # the record's layout before the drive's fields were appended
    write_time(w, FAULT.stamp_ns)
    for write, value in ((w.string, "a0"), (w.uint8, 7), (w.uint64, 0), (w.int64, 250), (w.int64, -1)):
        write(value)
    for write, value in ((w.int64, -1), (w.string, ""), (w.string, FAULT.text)):
        write(value)
    expected = MoveStatus(FAULT.stamp_ns, "a0", MoveState.FAULT, 0, 250, text=FAULT.text)
    assert MoveStatus.decode(w.to_bytes()) == expected


@pytest.mark.parametrize(
    ("name", "value"), [("error_code", 1 << 16), ("error_register", 256), ("statusword", -1)]
)
def test_drive_fields_out_of_their_unsigned_range_are_a_wire_error(name, value):
    with pytest.raises(WireError, match=f"{name} = {value} must be an unsigned"):
        MoveStatus(1, "a0", MoveState.FAULT, 0, 0, **{name: value})


def test_quick_stop_round_trips_with_and_without_a_fault_reset():
    for request in (QuickStop(1_700_000_000_000_000_000, "a0", "operator"), QuickStop(5, "a1", "", True)):
        data = request.encode()
        assert QuickStop.decode(data) == request
        ref = _reference(QUICK_STOP_TYPE)(data)
        assert (ref.header.frame_id, ref.reason, ref.reset_fault) == (
            request.axis,
            request.reason,
            request.reset_fault,
        )
    old = QuickStop(7, "a0", "x").encode()[:-1]  # sent before reset_fault existed
    assert QuickStop.decode(old) == QuickStop(7, "a0", "x", False)


def test_attachment_round_trip():
    att = Attachment(sequence=42, source_stamp_ns=1_700_000_000_000_000_000, publisher_gid=bytes(range(16)))
    raw = att.encode()
    assert len(raw) == 33
    assert Attachment.decode(raw) == att


@pytest.mark.parametrize(
    ("data", "match"),
    [
        (b"", "CDR_LE header"),
        (b"\x00\x00\x00\x00" + bytes(8), "CDR_LE header"),
        (SAMPLE.encode()[:30], "truncated|exceeds"),
        (SAMPLE.encode()[:-8], "truncated|exceeds"),
    ],
    ids=["empty", "big-endian", "cut-in-names", "cut-in-efforts"],
)
def test_bad_bytes_raise_wire_error(data, match):
    with pytest.raises(WireError, match=match):
        AxisSample.decode(data)


def test_wrong_joints_and_bad_records_rejected():
    js = JointState(0, "a0", ("x", "y"), (0.0, 0.0), (0.0, 0.0), (0.0, 0.0))
    with pytest.raises(WireError, match="axis contract"):
        AxisSample.decode(js.encode())
    with pytest.raises(WireError, match="not finite"):
        MoveCommand(0, "a0", 1, 0, "poly5", float("nan"), 0.5, 1.0)
    with pytest.raises(WireError, match="start_ns = -1 ns"):
        MoveCommand(0, "a0", 1, -1, "poly5", 0.0, 0.5, 1.0)
    with pytest.raises(WireError, match="33"):
        Attachment.decode(b"\x00" * 10)
    with pytest.raises(ValueError):  # WireError is a ValueError
        Attachment(1, 2, b"short")


def test_a_sampled_move_carries_its_knots_exactly():
    import numpy as np
    from axisflow.acquisition.wire.messages import SAMPLED_LAW, Knots

    t = np.linspace(0.0, 0.5, 501)
    knots = Knots(t, 0.2 + 0.1 * t**2, 0.2 * t, np.full(t.size, 0.2))
    knots.velocity_m_s[-1] = 0.0
    cmd = MoveCommand(1, "a0", 9, 0, SAMPLED_LAW, 0.2, 0.225, 0.5, knots)
    data = cmd.encode()
    back = MoveCommand.decode(data)
    assert back == cmd and back.knots is not None and back.knots.t_s.dtype == np.float64
    ref = _reference(MOVE_TYPE)(data)
    assert list(ref.knot_position_m) == knots.position_m.tolist()
    assert list(ref.knot_t_s) == t.tolist() and list(ref.knot_acceleration_m_s2) == [0.2] * 501
    assert MoveCommand.decode(MOVE.encode()).knots is None  # a polynomial move has none


def test_plan_record_round_trip_and_reference_codec():
    from axisflow.acquisition import PLAN_TYPE, PlanRecord

    rec = PlanRecord(
        1_700_000_000_000_000_123, "a0", 12, "ab" * 16, "refit", 7, "min-time-energy", "poly5", "exact",
        0.9, 0.12, 0.55, 1.234, 56.7, "positive", 5.81, 0.0, "converged", 0, 4.2e-5,
        {"gap_j": 1e-9, "t_lower_s": 1.2339, "t_upper_s": 1.2341, "dJ_dT": -1e-7},
    )  # fmt: skip
    data = rec.encode()
    assert PlanRecord.decode(data) == rec
    ref = _reference(PLAN_TYPE)(data)
    assert (ref.move_id, ref.run, ref.waypoint_index, ref.case, ref.law) == (
        12,
        "refit",
        7,
        "min-time-energy",
        "poly5",
    )
    assert (ref.duration_s, ref.energy_j, ref.iterations) == (1.234, 56.7, 0)
    assert dict(zip(ref.certificate_keys, ref.certificate_values, strict=True)) == rec.certificate
    empty = PlanRecord(
        0, "a0", 1, "", "", 0, "min-time", "poly3", "ipopt", 0.9, 0, 0.1, 0.3, 1, "signed", 30, 0, "x", 9, 0
    )
    assert PlanRecord.decode(empty.encode()).certificate == {}


def test_drive_info_round_trip_and_reference_codec():
    from axisflow.acquisition.wire.drive_info import DRIVE_INFO_TYPE, DriveInfo

    info = DriveInfo(
        1_700_000_000_250_000_000, "a0", "simulated", "realistic", "packaged plant_realistic.toml"
    )
    data = info.encode()
    assert DriveInfo.decode(data) == info
    ref = _reference(DRIVE_INFO_TYPE)(data)
    assert (ref.header.frame_id, ref.drive, ref.profile, ref.source) == (
        "a0", "simulated", "realistic", "packaged plant_realistic.toml"
    )  # fmt: skip
    assert ref.header.stamp.sec * 10**9 + ref.header.stamp.nanosec == info.stamp_ns
    assert info.describe() == "simulated axis, plant realistic (packaged plant_realistic.toml)"
    assert DriveInfo(0, "a0", "acme servo X1").describe() == "acme servo X1"


def test_a_hello_round_trips_and_refuses_what_is_not_one():
    from axisflow.acquisition.wire.hello import Hello

    hello = Hello("axisflow/a0/state", "ab" * 16, "0123456789abcdef", "host-1", 4242, 31_337)
    assert Hello.decode(hello.encode()) == hello
    assert hello.where == "pid 4242 on host host-1 (Zenoh id 0123456789abcdef)"
    assert hello.publisher_id == b"\xab" * 16
    for bad, says in (
        (b"not json", "undecodable hello"),
        (b"[1, 2]", "undecodable hello"),
        (b'{"key": "k"}', "undecodable hello"),
        (hello.encode().replace(b"4242", b"-1"), "pid = -1"),
        (hello.encode().replace(b'"host-1"', b"7"), "host = 7"),
        (hello.encode().replace(b"31337", b"-3"), "sequence = -3"),
        (hello.encode().replace(b"31337", b"true"), "sequence = True"),
    ):
        with pytest.raises(WireError, match=says):
            Hello.decode(bad)


def test_last_sequence_numbers_round_trip_and_refuse_what_is_not_them():
    from axisflow.acquisition.wire.last_sequences import LastSequence, LastSequences

    state, other = LastSequence("axisflow/a0/state", "ab" * 16, 8000), LastSequence("k/x", "cd" * 16, 0)
    record = LastSequences((state, other))
    assert LastSequences.decode(record.encode()) == record
    assert record.publishers[1].publisher_id == b"\xcd" * 16
    assert LastSequences.decode(LastSequences(()).encode()) == LastSequences(())
    good = record.encode()
    for bad, says in (
        (b"not json", "undecodable last sequence"),
        (b'{"other": []}', "undecodable last sequence"),
        (b'{"last_sequences": [["k", "ab"]]}', "undecodable last sequence"),
        (good.replace(b"8000", b"-1"), "sequence -1 is not a count"),
        (good.replace(b"8000", b"1.5"), "sequence 1.5 is not a count"),
        (good.replace(b'"axisflow/a0/state"', b'""'), "key '' is not a key"),
        (good.replace(b"ab" * 16, b"ab" * 15), "is not a 16-byte id"),
        (good.replace(b"ab" * 16, b"zz" * 16), "is not a 16-byte id"),
    ):
        with pytest.raises(WireError, match=says):
            LastSequences.decode(bad)


def test_a_plan_record_carries_its_parameter_version_and_one_written_before_it_decodes_with_zero():
    from axisflow.acquisition import PLAN_TYPE, PlanRecord

    rec = PlanRecord(
        1_700_000_000_000_000_123, "a0", 12, "ab" * 16, "adapt", 7, "min-time", "poly5", "exact",
        0.9, 0.12, 0.55, 1.234, 56.7, "positive", 5.81, 0.0, "converged", 0, 4.2e-5, {"gap_j": 1e-9}, 42,
    )  # fmt: skip
    data = rec.encode()
    assert PlanRecord.decode(data) == rec
    assert _reference(PLAN_TYPE)(data).params_version == 42
    old = data[:-4]  # the record as it was before the field was appended (no padding before a uint32)
    assert PlanRecord.decode(old) == dataclasses.replace(rec, params_version=0)


ESTIMATE = ParamsEstimate(
    stamp_ns=1_700_000_123_000_000_000,
    axis="a0",
    version=4,
    base_version=3,
    decision=Decision.ACCEPTED,
    reason="accepted: held-out error 0.0150 N·m against 0.0171 N·m of version 3 (−12.3 %)",
    fitted=("M_eq", "a2", "coulomb"),
    values=(115.2, 74.1, 160.3, 198.5, 10.24, 12.5, -3.25, 8.0),
    std=(0.4, 0.9, 2.2, 2.4, math.nan, math.nan, 0.31, 0.72),
    window_start_ns=1_700_000_103_000_000_000,
    window_end_ns=1_700_000_123_000_000_000,
    samples=1234,
    fit_rms_nm=0.0148,
    holdout_rms_nm=0.0150,
    holdout_rms_kept_nm=0.0171,
)


def test_a_parameter_estimate_round_trips_through_both_codecs():
    data = ESTIMATE.encode()
    back = ParamsEstimate.decode(data)
    assert back.encode() == data  # NaN ≠ NaN: compare the bytes, and the fields one by one
    assert back.values == ESTIMATE.values and back.std[:4] == ESTIMATE.std[:4] and math.isnan(back.std[4])
    assert math.isnan(back.std[5]) and back.std[6:] == (0.31, 0.72)
    assert (back.version, back.base_version, back.decision, back.fitted) == (
        4,
        3,
        "accepted",
        ESTIMATE.fitted,
    )
    ref = _reference(PARAMS_ESTIMATE_TYPE)(data)
    assert (ref.header.frame_id, ref.version, ref.base_version, ref.accepted) == ("a0", 4, 3, True)
    assert (ref.decision, ref.reason, list(ref.fitted)) == (
        "accepted",
        ESTIMATE.reason,
        list(ESTIMATE.fitted),
    )
    assert (ref.m_eq_kg, ref.a1_n, ref.a2_n_s_m, ref.a3_n, ref.a4_s_m) == ESTIMATE.values[:5]
    assert (ref.f0_n, ref.da1_n, ref.da2_n_s_m) == ESTIMATE.values[5:]
    assert math.isnan(ref.a4_std_s_m) and ref.m_eq_std_kg == 0.4
    assert math.isnan(ref.f0_std_n) and (ref.da1_std_n, ref.da2_std_n_s_m) == (0.31, 0.72)
    assert ref.window_start.sec * 10**9 + ref.window_start.nanosec == ESTIMATE.window_start_ns
    assert (ref.samples, ref.fit_rms_nm, ref.holdout_rms_kept_nm) == (1234, 0.0148, 0.0171)
    encode = serialize_dynamic(PARAMS_ESTIMATE_TYPE, SCHEMAS[PARAMS_ESTIMATE_TYPE])[PARAMS_ESTIMATE_TYPE]
    time = lambda ns: {"sec": ns // 10**9, "nanosec": ns % 10**9}  # noqa: E731
    names = ("m_eq_kg", "a1_n", "a2_n_s_m", "a3_n", "a4_s_m", "f0_n", "da1_n", "da2_n_s_m")
    std_names = (
        "m_eq_std_kg", "a1_std_n", "a2_std_n_s_m", "a3_std_n", "a4_std_s_m",
        "f0_std_n", "da1_std_n", "da2_std_n_s_m",
    )  # fmt: skip
    fields = {
        "header": {"stamp": time(ESTIMATE.stamp_ns), "frame_id": "a0"},
        "version": 4,
        "base_version": 3,
        "accepted": True,
        "decision": "accepted",
        "reason": ESTIMATE.reason,
        "fitted": list(ESTIMATE.fitted),
        **dict(zip(names, ESTIMATE.values, strict=True)),
        **dict(zip(std_names, ESTIMATE.std, strict=True)),
        "window_start": time(ESTIMATE.window_start_ns),
        "window_end": time(ESTIMATE.window_end_ns),
        "samples": 1234,
        "fit_rms_nm": 0.0148,
        "holdout_rms_nm": 0.0150,
        "holdout_rms_kept_nm": 0.0171,
    }
    assert bytes(encode(fields)) == data


def test_an_estimate_written_before_the_terms_beside_eq1_reads_with_them_off():
    data = ESTIMATE.encode()
    old = data[: -6 * 8]  # the record as it was before f0, da1, da2 and their σ were appended
    back = ParamsEstimate.decode(old)
    assert back.values == (*ESTIMATE.values[:5], 0.0, 0.0, 0.0)
    assert back.std[:4] == ESTIMATE.std[:4] and all(math.isnan(s) for s in back.std[4:])
    assert back.friction.is_symmetric and back.holdout_rms_kept_nm == ESTIMATE.holdout_rms_kept_nm
    # and so does a record built with eq. (1)'s five values only
    five = dataclasses.replace(ESTIMATE, values=ESTIMATE.values[:5], std=ESTIMATE.std[:5])
    assert five.values == back.values and ParamsEstimate.decode(five.encode()).encode() == five.encode()


def test_a_rejected_estimate_keeps_its_version_and_names_why():
    kept = dataclasses.replace(ESTIMATE, version=3, decision=Decision.NO_IMPROVEMENT, reason="no better")
    back = ParamsEstimate.decode(kept.encode())
    assert (back.version, back.accepted, back.decision) == (3, False, Decision.NO_IMPROVEMENT)


@pytest.mark.parametrize(
    ("changes", "match"),
    [
        ({"version": 3}, "version = 3 after a decision accepted on version 3 must be 4"),
        ({"decision": Decision.UNCERTAIN}, "version = 4 after a decision uncertain on version 3 must be 3"),
        ({"values": (1.0, 2.0)}, r"values has 2 numbers, needs 8 \(M_eq, a1, a2, a3, a4, f0, da1, da2\)"),
        ({"std": (1.0,) * 6}, "std has 6 numbers, needs 8"),
        ({"samples": -1}, "samples = -1 must be in"),
    ],
)
def test_an_inconsistent_estimate_is_a_wire_error(changes, match):
    with pytest.raises(WireError, match=match):
        dataclasses.replace(ESTIMATE, **changes)


def test_an_estimate_whose_flag_contradicts_its_decision_is_a_wire_error():
    data = bytearray(ESTIMATE.encode())
    head = CdrWriter()  # the fields before the flag: stamp, frame id, version, base version
    write_time(head, ESTIMATE.stamp_ns)
    head.string("a0")
    head.uint32(4)
    head.uint32(3)
    flag = len(head.to_bytes())
    assert data[flag] == 1
    data[flag] = 0
    with pytest.raises(WireError, match="accepted = 0 contradicts the decision accepted"):
        ParamsEstimate.decode(bytes(data))


def test_an_estimate_applies_to_a_parameter_set_through_the_cart_mass():
    from axisflow.model import load_params

    params = load_params(None)
    applied = ESTIMATE.applied_to(params)
    assert applied.M_eq == pytest.approx(115.2, rel=1e-12)
    assert applied.J_m == params.J_m and applied.r == params.r
    assert (applied.a1, applied.a2, applied.a3, applied.a4) == (74.1, 160.3, 198.5, 10.24)
    assert (applied.f0, applied.da1, applied.da2) == (12.5, -3.25, 8.0)
    assert applied.terms == ("coulomb", "viscous", "offset", "asymmetry", "atan")
    assert applied.friction == ESTIMATE.friction  # the law the planner plans with is the record's
    with pytest.raises(WireError, match="has no values"):
        dataclasses.replace(ESTIMATE, values=(math.nan,) * 5).applied_to(params)
    with pytest.raises(WireError, match="M_eq = 1 kg is not above the rotating parts' share"):
        dataclasses.replace(ESTIMATE, values=(1.0, 74.1, 160.3, 198.5, 10.24)).applied_to(params)


def test_an_estimate_without_the_terms_beside_eq1_switches_them_off_in_the_set_it_applies_to():
    from axisflow.model import load_params

    axis = load_params(Path(__file__).parents[3] / "docs" / "axes" / "belt.toml")
    assert {"offset", "asymmetry"} <= set(axis.terms)
    old = ParamsEstimate.decode(ESTIMATE.encode()[: -6 * 8])
    applied = old.applied_to(axis)
    assert (applied.f0, applied.da1, applied.da2) == (0.0, 0.0, 0.0)
    assert not {"offset", "asymmetry"} & set(applied.terms) and applied.a2 == 160.3
