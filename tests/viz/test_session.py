"""The log view: an .rrd written from real MCAP logs, read back with rerun's own reader and checked
bit for bit against the logs (the fast reader and mcap_ros2's decoder as references)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from axisflow.acquisition import read_joint_states
from axisflow.acquisition.wire.params_estimate import Decision, ParamsEstimate
from axisflow.model import EXECUTION_PERIOD_S, EnergyAccounting, default_params, trace_energy
from axisflow.model.files import OutputError
from axisflow.viz.entities import AxisEntities
from axisflow.viz.session import SessionLogs, write_session_rrd
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from rerun.chunk import RrdReader

from axisflow.experiment.table2 import table_from_recording

SIGNALS = (
    "position/measured",
    "position/setpoint",
    "velocity/measured",
    "velocity/setpoint",
    "torque/measured",
    "torque/feedforward",
    "power/measured",
    "tracking_error",
)


@pytest.fixture(scope="module")
def session_rrd(test_log, tmp_path_factory):
    out = tmp_path_factory.mktemp("rrd") / "session.rrd"
    return write_session_rrd([test_log.path], out, default_params())


def _decoded(path, topic):
    with open(path, "rb") as fh:
        reader = make_reader(fh, decoder_factories=[DecoderFactory()])
        return [d for _s, _c, _m, d in reader.iter_decoded_messages(topics=[topic])]


def test_every_signal_of_the_axis_is_an_entity(session_rrd, rrd_reader):
    data = rrd_reader(session_rrd)
    e = AxisEntities("a0")
    expected = {f"/{e.root}/{s}" for s in SIGNALS} | {
        f"/{p}"
        for p in (
            e.stroke,
            e.waypoints,
            e.velocity_limits,
            e.torque_limits,
            e.energy_measured,
            e.energy_planned,
            e.events,
        )
    }
    assert expected <= set(data)
    assert all(path.startswith("/axes/a0/") for path in data if path != "/__properties")
    assert [b.kind for b in RrdReader(session_rrd).blueprints()] == ["blueprint"]


def test_samples_and_stamps_equal_the_log_bit_for_bit(test_log, session_rrd, rrd_reader):
    data = rrd_reader(session_rrd)
    state = read_joint_states(test_log.path, "/axisflow/a0/state")
    setpoint = read_joint_states(test_log.path, "/axisflow/a0/setpoint")
    assert len(state) == len(setpoint) == test_log.ticks
    carriage, motor = state.joint("carriage"), state.joint("motor")
    sp_carriage, sp_motor = setpoint.joint("carriage"), setpoint.joint("motor")
    expected = {
        "position/measured": (state.stamp_ns, carriage.position),
        "velocity/measured": (state.stamp_ns, carriage.velocity),
        "torque/measured": (state.stamp_ns, motor.effort),
        "power/measured": (state.stamp_ns, motor.effort * motor.velocity),
        "position/setpoint": (setpoint.stamp_ns, sp_carriage.position),
        "velocity/setpoint": (setpoint.stamp_ns, sp_carriage.velocity),
        "torque/feedforward": (setpoint.stamp_ns, sp_motor.effort),
        "tracking_error": (state.stamp_ns, sp_carriage.position - carriage.position),
    }
    for signal, (stamps, values) in expected.items():
        entity = data[f"/axes/a0/{signal}"]
        assert len(entity.stamp_ns) == test_log.ticks, signal
        np.testing.assert_array_equal(entity.stamp_ns, stamps, err_msg=signal)
        assert entity.scalars().tobytes() == np.ascontiguousarray(values).tobytes(), signal


def test_samples_equal_an_independent_decoder(test_log, session_rrd, rrd_reader):
    data = rrd_reader(session_rrd)
    messages = _decoded(test_log.path, "/axisflow/a0/state")
    stamps = np.array([m.header.stamp.sec * 10**9 + m.header.stamp.nanosec for m in messages])
    np.testing.assert_array_equal(data["/axes/a0/position/measured"].stamp_ns, stamps)
    np.testing.assert_array_equal(
        data["/axes/a0/position/measured"].scalars(), [m.position[0] for m in messages]
    )
    np.testing.assert_array_equal(data["/axes/a0/torque/measured"].scalars(), [m.effort[1] for m in messages])


def test_limits_span_the_samples(test_log, session_rrd, rrd_reader):
    data = rrd_reader(session_rrd)
    p = default_params()
    first, last = test_log.start_ns, test_log.start_ns + (test_log.ticks - 1) * 1_000_000
    for path, high in (("position/stroke", p.L), ("velocity/limits", p.v_max), ("torque/limits", p.tau_max)):
        entity = data[f"/axes/a0/{path}"]
        assert entity.stamp_ns.tolist() == [first, last]
        low = 0.0 if path == "position/stroke" else -high
        assert entity.scalars().tolist() == [[high, low], [high, low]]


def test_moves_energy_equals_table2_and_waypoints_the_plans(test_log, session_rrd, rrd_reader):
    data = rrd_reader(session_rrd)
    completed = [m for m in test_log.moves if not m.dropped]
    ends = [test_log.start_ns + m.end_tick * 1_000_000 for m in completed]
    energy = data["/axes/a0/energy/measured"]
    assert energy.stamp_ns.tolist() == ends
    table = table_from_recording(test_log.path)
    reference = [
        energy
        for row in table.rows
        for energy, completed in zip(row.measured.energies_j, row.measured.completed, strict=True)
        if completed
    ]
    assert energy.scalars().tolist() == reference
    # and by hand: the trapezoid of τ_m·ω_m over the move's ticks, both ends included
    motor = read_joint_states(test_log.path, "/axisflow/a0/state").joint("motor")
    m = completed[0]
    by_hand = trace_energy(
        motor.velocity[m.start_tick : m.end_tick + 1],
        motor.effort[m.start_tick : m.end_tick + 1],
        EXECUTION_PERIOD_S,
        EnergyAccounting.POSITIVE,
    )
    assert energy.scalars()[0] == by_hand
    accepted = [test_log.start_ns + m.end_tick * 1_000_000 for m in test_log.moves]
    waypoints = data["/axes/a0/position/waypoints"]
    assert waypoints.stamp_ns.tolist() == sorted(accepted)
    by_end = dict(zip(accepted, (m.end_position_m for m in test_log.moves), strict=True))
    assert waypoints.scalars().tolist() == [by_end[t] for t in waypoints.stamp_ns.tolist()]
    planned = data["/axes/a0/energy/planned"]
    assert sorted(planned.scalars().tolist()) == sorted(m.energy_j for m in test_log.moves)


def test_move_statuses_are_a_text_log_at_their_drive_time(test_log, session_rrd, rrd_reader):
    events = rrd_reader(session_rrd)["/axes/a0/events"]
    assert len(events.stamp_ns) == 2 * len(test_log.moves)
    texts = [v[0] for v in events.values]
    assert "dropped move 3" in texts and "completed move 4" in texts
    completed = events.stamp_ns[texts.index("completed move 1")]
    assert completed == test_log.start_ns + test_log.moves[0].end_tick * 1_000_000


def test_several_axes_in_one_log_side_by_side(two_axis_log, tmp_path, rrd_reader):
    session = SessionLogs.open([two_axis_log.path])
    assert session.labels == ["a0", "a1"]
    out = write_session_rrd([two_axis_log.path], tmp_path / "two.rrd", default_params())
    data = rrd_reader(out)
    for axis in ("a0", "a1"):
        state = read_joint_states(two_axis_log.path, f"/axisflow/{axis}/state")
        entity = data[f"/axes/{axis}/position/measured"]
        np.testing.assert_array_equal(entity.stamp_ns, state.stamp_ns)
        np.testing.assert_array_equal(entity.scalars(), state.joint("carriage").position)


def test_several_logs_are_one_recording(test_log, two_axis_log, tmp_path, rrd_reader):
    out = write_session_rrd([test_log.path, two_axis_log.path], tmp_path / "both.rrd", default_params())
    data = rrd_reader(out)
    assert len(data["/axes/a0/position/measured"].stamp_ns) == test_log.ticks + two_axis_log.ticks
    assert len(data["/axes/a1/position/measured"].stamp_ns) == two_axis_log.ticks


def test_an_unwritable_output_is_refused_before_reading(test_log, tmp_path):
    with pytest.raises(OutputError, match="does not exist"):
        write_session_rrd([test_log.path], tmp_path / "missing" / "x.rrd", default_params())
    assert not (tmp_path / "missing").exists()


def test_viewing_a_log_does_not_load_zenoh(test_log, tmp_path):
    code = (
        "import sys; from axisflow.viz.session import write_session_rrd; "
        "from axisflow.model import default_params; "
        f"write_session_rrd([{str(test_log.path)!r}], {str(tmp_path / 'x.rrd')!r}, default_params()); "
        "print(sorted(m for m in sys.modules if m.split('.')[0] == 'zenoh'))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True
    )
    assert out.stdout.strip() == "[]"
    assert (tmp_path / "x.rrd").stat().st_size > 0


def _estimates(start_ns: int) -> list:
    """An adaptive node's records: version 0, two accepted estimates, one turned down."""
    p = default_params()
    nan = float("nan")

    def record(k, version, base, decision, values, std=(nan,) * 5):
        stamp = start_ns + k * 500_000_000
        terms = ("M_eq", "a2", "coulomb")
        return ParamsEstimate(stamp, "a0", version, base, decision, str(decision), terms, values, std)

    v0 = (p.M_eq, p.a1, p.a2, p.a3, p.a4)
    v1 = (p.M_eq * 1.01, p.a1 * 0.95, p.a2 * 0.9, p.a3 * 0.95, p.a4)
    v2 = (p.M_eq * 1.01, p.a1 * 0.9, p.a2 * 0.8, p.a3 * 0.9, p.a4)
    sigma = (0.2, 0.5, 2.0, 1.2, nan)
    return [
        record(0, 0, 0, Decision.INITIAL, v0),
        record(1, 1, 0, Decision.ACCEPTED, v1, sigma),
        record(2, 1, 1, Decision.NO_IMPROVEMENT, (p.M_eq, p.a1, p.a2 * 0.5, p.a3, p.a4), sigma),
        record(4, 2, 1, Decision.ACCEPTED, v2, sigma),
    ]


@pytest.fixture(scope="module")
def adapted(tmp_path_factory):
    from tests.viz.conftest import write_test_log

    folder = tmp_path_factory.mktemp("adapted")
    spec_start = write_test_log(folder / "probe.mcap", seconds=0.1, moves=False).start_ns
    records = _estimates(spec_start)
    log = write_test_log(folder / "adapted.mcap", estimates=records)
    rrd = write_session_rrd([log.path], folder / "adapted.rrd", default_params())
    return log, records, rrd


def test_each_moves_e_percent_is_drawn_at_its_end(adapted, rrd_reader):
    log, _records, rrd = adapted
    data = rrd_reader(rrd)
    from axisflow.experiment.table2 import move_energies, recorded_runs

    moves = [m for m in move_energies(recorded_runs(log.path)[0]) if m.energy_error_pct is not None]
    error = data["/axes/a0/energy_error"]
    assert error.stamp_ns.tolist() == [m.end_ns for m in moves]
    assert error.scalars() == pytest.approx([m.energy_error_pct for m in moves], rel=1e-12)


def test_the_adapted_parameters_their_band_and_the_friction_curves(adapted, rrd_reader):
    _log, records, rrd = adapted
    data = rrd_reader(rrd)
    accepted = [r for r in records if r.accepted]
    a2 = data["/axes/a0/params/a2"]
    assert a2.stamp_ns.tolist() == [r.stamp_ns for r in accepted]
    base = records[0].value_of["a2"]
    expected = [
        [(r.value_of["a2"] + s * np.nan_to_num(r.std_of["a2"])) / base * 100 - 100 for s in (0, 1, -1)]
        for r in accepted
    ]
    assert a2.scalars() == pytest.approx(np.array(expected), abs=1e-9)  # −10 % ± 1 % at version 1
    turned = data["/axes/a0/params/rejected/a2"]
    assert turned.stamp_ns.tolist() == [records[2].stamp_ns] and turned.scalars() == pytest.approx([-50.0])
    now = data["/axes/a0/friction/now"]
    assert now.stamp_ns.tolist() == [r.stamp_ns for r in accepted]
    curve = np.array(now.values[-1][0])  # the newest: version 2, at +v_max
    p = default_params()
    v2 = accepted[-1].value_of
    at_vmax = v2["a1"] + v2["a2"] * p.v_max + v2["a3"] * np.arctan(v2["a4"] * p.v_max)
    assert curve[-1] == pytest.approx([p.v_max, at_vmax], rel=1e-6)
    assert data["/axes/a0/friction/start"].static
    assert "/axes/a0/params/f0" not in data  # a term off in version 0 has no percentage to draw
