"""Foreign logs → the recorder's JointState MCAP → our log reader: the same samples, in SI units, with
the stamps exact to the nanosecond, from CSV (decimal comma, units row), Parquet, MATLAB v5 and v7.3;
units converted through the one table; several files; and each refusal, with nothing written."""

from __future__ import annotations

import math

import numpy as np
import pytest
from axisflow.acquisition.foreign import (
    ColumnMap,
    ForeignLogError,
    Signal,
    import_logs,
    parse_counts_per,
    parse_scale,
)
from axisflow.acquisition.logs.reader import list_topics, read_joint_states
from mcap.reader import make_reader

from .foreign_files import write_csv, write_mat_v5, write_mat_v73, write_parquet

N = 1500
RNG = np.random.default_rng(7)
T_S = np.arange(N) * 0.001  # 1 kHz, float seconds as a scope writes them
X_M = 0.4 + 0.1 * np.sin(2 * math.pi * 0.5 * T_S) + RNG.normal(0, 1e-6, N)
V_M_S = 0.1 * math.pi * np.cos(2 * math.pi * 0.5 * T_S)
F_N = 80.0 * np.sign(V_M_S) + 200.0 * V_M_S + RNG.normal(0, 0.5, N)
STAMPS_NS = np.arange(N, dtype=np.int64) * 1_000_000


def _read(path, topic="/joint_states", joint="carriage"):
    columns = read_joint_states(path, topic)
    assert columns.joint_names == (joint,)
    return columns.joint(joint)


def _same(joint, position, velocity, effort, stamps=STAMPS_NS, rtol=1e-12):
    assert np.array_equal(joint.stamp_ns, stamps)  # exact, not close
    np.testing.assert_allclose(joint.position, position, rtol=rtol, atol=1e-15)
    if velocity is None:
        assert np.isnan(joint.velocity).all()
    else:
        np.testing.assert_allclose(joint.velocity, velocity, rtol=rtol, atol=1e-15)
    np.testing.assert_allclose(joint.effort, effort, rtol=rtol, atol=1e-12)


def test_a_scope_csv_with_decimal_comma_and_a_units_row(tmp_path):
    csv = write_csv(
        tmp_path / "scope.csv",
        ["Zeit", "Lage", "Geschw.", "Kraft"],
        [T_S, X_M * 1e3, V_M_S * 1e3, F_N / 1e3],
        units=["s", "mm", "mm/s", "kN"],
        preamble=("Abtastzeit;1;ms",),
    )
    cmap = ColumnMap(Signal("Lage"), time=Signal("Zeit"), velocity=Signal("Geschw."), effort=Signal("Kraft"))
    result = import_logs([csv], cmap, tmp_path / "scope.mcap")
    assert (result.joint, result.side, result.messages) == ("carriage", "carriage", N)
    _same(_read(tmp_path / "scope.mcap"), X_M, V_M_S, F_N)


def test_the_mcap_is_the_recorders_ros2_joint_state_file(tmp_path):
    csv = write_csv(tmp_path / "a.csv", ["t", "x"], [T_S, X_M], decimal=".")
    import_logs([csv], ColumnMap(Signal("x", "m"), time=Signal("t")), tmp_path / "a.mcap")
    with open(tmp_path / "a.mcap", "rb") as fh:
        reader = make_reader(fh)
        assert reader.get_header().profile == "ros2"
        summary = reader.get_summary()
    (channel,) = summary.channels.values()
    assert channel.message_encoding == "cdr" and "offered_qos_profiles" in channel.metadata
    assert summary.schemas[channel.schema_id].name == "sensor_msgs/msg/JointState"
    assert [(t.topic, t.message_count) for t in list_topics(tmp_path / "a.mcap")] == [("/joint_states", N)]


def test_parquet_with_time_stamps_in_nanoseconds(tmp_path):
    start = 1_767_225_600_123_456_789  # an absolute stamp that a float64 in seconds could not hold
    stamps = start + STAMPS_NS
    path = write_parquet(
        tmp_path / "p.parquet", {"stamp": stamps.astype("datetime64[ns]"), "x": X_M, "f": F_N}
    )
    cmap = ColumnMap(Signal("x", "m"), time=Signal("stamp"), effort=Signal("f", "N"))
    import_logs([path], cmap, tmp_path / "p.mcap")
    _same(_read(tmp_path / "p.mcap"), X_M, None, F_N, stamps=stamps)


@pytest.mark.parametrize("writer", [write_mat_v5, write_mat_v73], ids=["v5", "v7.3"])
def test_mat_emps_style_position_and_voltage_times_a_gain_variable(tmp_path, writer):
    gtau = 35.15  # N per V
    path = writer(tmp_path / "emps.mat", {"t": T_S, "qm": X_M, "vir": F_N / gtau, "gtau": gtau})
    cmap = ColumnMap(
        Signal("qm", "m"), time=Signal("t", "s"), effort=Signal("vir", "V"), effort_scale=parse_scale("gtau")
    )
    import_logs([path], cmap, tmp_path / "emps.mcap")
    _same(_read(tmp_path / "emps.mcap"), X_M, None, F_N)


def test_motor_side_units_become_a_motor_joint_in_rad_rad_s_and_n_m(tmp_path):
    counts = np.round(X_M * 131072 / (2 * math.pi) * 30).astype(np.int64)  # a 17-bit encoder, any angle
    rpm = V_M_S * 300.0
    torque_mnm = F_N * 10.0
    path = write_csv(
        tmp_path / "m.csv", ["n", "p", "w", "tq"], [np.arange(N), counts, rpm, torque_mnm], decimal="."
    )
    cmap = ColumnMap(
        Signal("p", "counts"),
        rate_hz=1000.0,
        velocity=Signal("w", "rpm"),
        effort=Signal("tq", "mNm"),
        counts_per=parse_counts_per("131072/rev"),
    )
    result = import_logs([path], cmap, tmp_path / "m.mcap")
    assert (result.joint, result.side) == ("motor", "motor")
    motor = _read(tmp_path / "m.mcap", joint="motor")
    _same(motor, counts * (2 * math.pi / 131072), rpm * (2 * math.pi / 60), torque_mnm * 1e-3)


def test_a_rate_and_an_offset_place_the_rows(tmp_path):
    path = write_csv(tmp_path / "r.csv", ["x"], [X_M], decimal=".")
    cmap = ColumnMap(Signal("x", "m"), rate_hz=3000.0, time_offset_s=2.5, joint="slider")
    result = import_logs([path], cmap, tmp_path / "r.mcap")
    joint = _read(tmp_path / "r.mcap", joint="slider")
    expected = 2_500_000_000 + np.rint(np.arange(N) * (1e9 / 3000.0)).astype(np.int64)
    assert np.array_equal(joint.stamp_ns, expected) and result.joint == "slider"


def test_a_single_missing_value_is_a_lost_sample(tmp_path):
    f = F_N.copy()
    f[[100, 700]] = np.nan
    path = write_csv(tmp_path / "h.csv", ["t", "x", "f"], [T_S, X_M, f])
    result = import_logs(
        [path], ColumnMap(Signal("x", "m"), time=Signal("t"), effort=Signal("f", "N")), tmp_path / "h.mcap"
    )
    assert result.files[0].dropped == 2 and result.messages == N - 2
    keep = np.isfinite(f)
    _same(_read(tmp_path / "h.mcap"), X_M[keep], None, F_N[keep], stamps=STAMPS_NS[keep])


def test_files_that_follow_one_another_make_one_log_in_time_order(tmp_path):
    half = N // 2
    first = write_csv(tmp_path / "1.csv", ["t", "x"], [T_S[:half], X_M[:half]])
    second = write_csv(tmp_path / "2.csv", ["t", "x"], [T_S[half:], X_M[half:]])
    cmap = ColumnMap(Signal("x", "m"), time=Signal("t"))
    result = import_logs([second, first], cmap, tmp_path / "both.mcap")  # given out of order
    assert [f.source.name for f in result.files] == ["1.csv", "2.csv"]
    joint = _read(tmp_path / "both.mcap")
    assert np.array_equal(joint.stamp_ns, STAMPS_NS)
    np.testing.assert_allclose(joint.position, X_M, rtol=1e-12)


# ---- refusals: one line naming it, nothing written -----------------------------------------------


def _refused(tmp_path, files, cmap, match, out="out.mcap", **kw):
    before = sorted(p.name for p in tmp_path.iterdir())
    with pytest.raises(ForeignLogError, match=match):
        import_logs(files, cmap, tmp_path / out, **kw)
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # nothing written, no temporary left


def test_time_that_goes_back_names_the_lines_and_values(tmp_path):
    t = T_S.copy()
    t[10] = 0.0085
    path = write_csv(tmp_path / "b.csv", ["t", "x"], [t, X_M], decimal=".")
    _refused(
        tmp_path,
        [path],
        ColumnMap(Signal("x", "m"), time=Signal("t")),
        r"time goes back at line 12: 0\.0085 s after 0\.009 s at line 11",
    )


def test_a_run_of_missing_values_is_refused_with_where_and_how_long(tmp_path):
    f = F_N.copy()
    f[200:205] = np.nan
    f[900:902] = np.nan
    path = write_csv(tmp_path / "n.csv", ["t", "x", "f"], [T_S, X_M, f])
    _refused(
        tmp_path,
        [path],
        ColumnMap(Signal("x", "m"), time=Signal("t"), effort=Signal("f", "N")),
        r"2 run\(s\) of 2 or more rows with missing values .*the longest 5 rows from line 202 \(in f\)",
    )


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"effort": Signal("v", "V")}, r"effort 'v' in V is not a force: give a scale \(N per V"),
        (
            {"effort": Signal("v", "N·m")},
            r"position in mm is on the carriage side but effort in N·m is on the motor side",
        ),
        (
            {"effort": Signal("v", "lbf")},
            r"effort unit 'lbf' is not one of the known ones: N, kN, N·m, mN·m, V, A",
        ),
        ({"effort": Signal("v", "V"), "effort_scale": "gain"}, r"has no effort scale variable 'gain'"),
        ({"velocity": Signal("w", "mm/s")}, r"has no velocity column 'w'; its columns: t, x, v"),
    ],
)
def test_units_sides_and_columns_are_checked(tmp_path, kw, match):
    path = write_csv(tmp_path / "u.csv", ["t", "x", "v"], [T_S, X_M, F_N])
    _refused(tmp_path, [path], ColumnMap(Signal("x", "mm"), time=Signal("t"), **kw), match)


def test_mat_lengths_that_differ_and_a_scale_that_is_not_a_scalar(tmp_path):
    path = write_mat_v5(tmp_path / "l.mat", {"t": T_S, "qm": X_M[:-1], "vir": F_N, "gtau": F_N})
    _refused(
        tmp_path,
        [path],
        ColumnMap(Signal("qm", "m"), time=Signal("t")),
        r"differ in length \(time 't' 1500, position 'qm' 1499 values\)",
    )
    cmap = ColumnMap(Signal("vir", "m"), time=Signal("t"), effort=Signal("vir", "V"), effort_scale="gtau")
    _refused(tmp_path, [path], cmap, r"effort scale 'gtau' is a vector of 1500 values, not a scalar")


def test_overlapping_files_an_existing_output_and_an_input_as_output(tmp_path):
    a = write_csv(tmp_path / "a.csv", ["t", "x"], [T_S, X_M])
    b = write_csv(tmp_path / "b.csv", ["t", "x"], [T_S, X_M])
    cmap = ColumnMap(Signal("x", "m"), time=Signal("t"))
    _refused(tmp_path, [a, b], cmap, r"a.csv \(0.000000 s to 1.499000 s\) and .*b.csv .* overlap in time")
    (tmp_path / "old.mcap").write_bytes(b"an earlier import")
    _refused(
        tmp_path,
        [a],
        cmap,
        r"old.mcap already exists: choose another name or pass --overwrite",
        out="old.mcap",
    )
    assert (tmp_path / "old.mcap").read_bytes() == b"an earlier import"
    (tmp_path / "a.mcap").symlink_to(a)
    _refused(tmp_path, [a], cmap, r"is the input .*a.csv under another name", out="a.mcap", overwrite=True)
