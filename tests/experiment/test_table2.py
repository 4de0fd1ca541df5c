"""Table 2 from a recording, on a recording made here whose measured energy is known in closed form."""

import json
import math

import numpy as np
import pytest
from axisflow.acquisition import (
    JOINT_STATE_TYPE,
    MOVE_STATUS_TYPE,
    PLAN_TYPE,
    AxisSample,
    MoveState,
    MoveStatus,
    PlanRecord,
)
from axisflow.acquisition.logs.mcap_writer import Ros2McapWriter
from axisflow.model import EXECUTION_PERIOD_NS, AxisflowError
from axisflow.planner import Case

from axisflow.experiment.per_move import read_move_energies
from axisflow.experiment.table2 import move_energies, recorded_runs, table_from_recording
from axisflow.experiment.table2_markdown import table_markdown
from axisflow.experiment.table2_record import Table2

T0 = 1_700_000_000_000_000_000
MS = EXECUTION_PERIOD_NS
SENDER = "cd" * 16
# three moves: (ticks, planned energy [J], motor speed amplitude [rad/s], torque amplitude [N·m])
MOVES = [(400, 10.0, 50.0, 1.0), (600, 12.0, 40.0, 2.0), (500, 8.0, 30.0, 1.5)]
GAP = 7  # idle ticks between move 2 and move 3


def _write(path, accounting="positive", lost=(), versions=(0, 0, 0), jitter_ns=0):
    """Moves back to back except a gap before the third; over each move ω(t) = W·sin(πt/T) and
    τ(t) = Q·cos(πt/T): power W·Q/2·sin(2πt/T), signed energy 0, positive energy W·Q·T/(2π). The
    samples of the ticks ``lost`` are not written (a recorder that missed them)."""
    w = Ros2McapWriter(path, "zstd", chunk_size=16384)
    state = w.channel_for("/axisflow/a0/state", JOINT_STATE_TYPE)
    setpoint = w.channel_for("/axisflow/a0/setpoint", JOINT_STATE_TYPE)
    event = w.channel_for("/axisflow/a0/event", MOVE_STATUS_TYPE)
    plan = w.channel_for("/axisflow/a0/plan", PLAN_TYPE)
    tick, spans = 100, []
    for k, (n, e_th, _w, _q) in enumerate(MOVES, start=1):
        if k == 3:
            tick += GAP
        spans.append((tick, tick + n))
        x0 = 0.1 * k
        record = PlanRecord(
            T0 + k, "a0", k, SENDER, "test", k, "min-time", "poly5", "exact", 0.9, x0, x0 + 0.1,
            n / 1000, e_th, accounting, n / 10, 0.0, "converged", 0, 1e-4 * k, {}, versions[k - 1],
        )  # fmt: skip
        w.add(plan, T0, T0, k, record.encode())
        st = MoveStatus(T0 + tick * MS, "a0", MoveState.ACCEPTED, k, tick, tick, tick + n, SENDER, "")
        w.add(event, T0, T0, 2 * k, st.encode())
        tick += n
    total = tick + 50
    omega = np.zeros(total)
    torque = np.zeros(total)
    moving = np.zeros(total, bool)
    for (start, end), (n, _e, amp_w, amp_q) in zip(spans, MOVES, strict=True):
        t = np.arange(n + 1) / n
        omega[start : end + 1] = amp_w * np.sin(math.pi * t)
        torque[start : end + 1] = amp_q * np.cos(math.pi * t)
        moving[start:end] = True
    for k in range(total):
        if k in lost:
            continue
        stamp = T0 + k * MS
        late = jitter_ns * (1 if k % 3 == 0 else -1 if k % 3 == 1 else 0)  # a host's clock: ± tens of µs
        sample = AxisSample(stamp + late, "a0", 0.0, 0.0, 0.0, 0.0, float(omega[k]), float(torque[k]))
        w.add(state, stamp, stamp, k, sample.encode())
        sp = AxisSample(stamp, "a0", 0.0, 0.1 if moving[k] else 0.0, 0.0, 0.0, 0.0, 0.0)
        w.add(setpoint, stamp, stamp, k, sp.encode())
    for k, (start, end) in enumerate(spans, start=1):
        done = MoveStatus(T0 + end * MS, "a0", MoveState.COMPLETED, k, end, start, end, SENDER, "")
        w.add(event, T0, T0, 10 + k, done.encode())
    w.finish()
    return path


def test_measured_energy_idle_ticks_and_the_row(tmp_path):
    table = table_from_recording(_write(tmp_path / "t.mcap"))
    (row,) = table.rows
    # ∫ max(P, 0) dt over each move: W·Q·T/(2π), T = n ms (the trapezoid at 1 kHz over the kink of
    # max(P, 0) at T/2: within 1e-4)
    expected = [amp_w * amp_q * (n / 1000) / (2 * math.pi) for n, _e, amp_w, amp_q in MOVES]
    m = row.measured
    assert m.energies_j == pytest.approx(expected, rel=1e-4)
    assert row.planned.energy_model_j == 30.0 and row.planned.total_time_s == pytest.approx(1.5)
    assert row.energy_error_pct == pytest.approx((30.0 - sum(expected)) / 30.0 * 100.0, rel=1e-4)
    assert m.idle_ticks == (0, GAP) and m.moves_completed == 3
    assert row.planned.t_opt_ms_mean == pytest.approx(0.2)
    assert (row.case, row.law, row.solver, row.label, row.omega) == (
        Case.MIN_TIME,
        "poly5",
        "exact",
        "test",
        None,
    )
    assert table.waypoints_m == pytest.approx((0.1, 0.2, 0.3, 0.4))
    assert table.source == str(tmp_path / "t.mcap")
    assert Table2.decode(json.loads(json.dumps(table.encode()))) == table
    assert "| min-time | poly5 | exact | 3/3 | 1.50 | 30 |" in table_markdown(table)


def test_lost_samples_are_counted_never_integrated_over(tmp_path):
    second = range(100 + 400 + 200, 100 + 400 + 205)  # five ticks inside the second move
    table = table_from_recording(_write(tmp_path / "lost.mcap", lost=set(second)))
    (row,) = table.rows
    m = row.measured
    assert m.state_samples_missing == (0, 5, 0)
    assert m.energies_j[1] is None and m.moves_measured == 2 and m.moves_completed == 3
    first, third = (amp_w * amp_q * (n / 1000) / (2 * math.pi) for n, _e, amp_w, amp_q in MOVES[::2])
    assert m.energy_measured_j == pytest.approx(first + third, rel=1e-4)
    assert row.energy_error_pct == pytest.approx((18.0 - first - third) / 18.0 * 100.0, rel=1e-4)
    assert m.setpoint_samples_missing == 5 and m.idle_ticks == (0, GAP)
    assert "5 state samples within 1 moves (left out of E_exp and E%" in table_markdown(table)


def test_jittered_stamps_belong_to_their_ticks(tmp_path):
    table = table_from_recording(_write(tmp_path / "j.mcap", jitter_ns=50_000))
    m = table.rows[0].measured
    expected = [amp_w * amp_q * (n / 1000) / (2 * math.pi) for n, _e, amp_w, amp_q in MOVES]
    assert m.state_samples_missing == (0, 0, 0)
    assert m.energies_j == pytest.approx(expected, rel=1e-4)


def test_a_drive_that_lost_a_sample_now_and_then_is_measured_across_the_holes(tmp_path):
    first = {100 + 50, 100 + 51, 100 + 300}  # two holes inside the first move: 2 ticks, then 1
    third = {100 + 400 + 600 + GAP + 500}  # the third move's end tick: where it ends is not known
    table = table_from_recording(_write(tmp_path / "h.mcap", lost=first | third, jitter_ns=20_000))
    m = table.rows[0].measured
    expected = [amp_w * amp_q * (n / 1000) / (2 * math.pi) for n, _e, amp_w, amp_q in MOVES]
    assert m.state_samples_missing == (3, 0, 1)
    assert m.energies_j[0] == pytest.approx(expected[0], rel=1e-4)
    assert m.energies_j[2] is None and m.moves_measured == 2


def test_the_accounting_is_the_plans(tmp_path):
    table = table_from_recording(_write(tmp_path / "s.mcap", accounting="signed"))
    assert table.rows[0].measured.energies_j == pytest.approx([0, 0, 0], abs=1e-9)


def test_a_recording_without_plans_is_a_clear_error(tmp_path):
    path = _write(tmp_path / "t.mcap")
    with pytest.raises(AxisflowError, match="holds no plan records on /axisflow/a0/plan labelled 'other'"):
        table_from_recording(path, label="other")


def test_a_damaged_chunk_is_skipped_and_its_moves_left_unmeasured(tmp_path, damage, cli):
    import warnings

    from axisflow.acquisition import DamagedLogWarning

    whole, damaged = _write(tmp_path / "whole.mcap"), tmp_path / "damaged.mcap"
    damage.damage(whole, damaged, len(damage.chunks(whole)) // 2, "flip")
    reference = table_from_recording(whole).rows[0].measured
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        (row,) = table_from_recording(damaged).rows
    assert {str(w.message).rsplit(" messages of ", 1)[1].split()[0] for w in caught} == {
        "/axisflow/a0/state",
        "/axisflow/a0/setpoint",
    }
    assert all(issubclass(w.category, DamagedLogWarning) for w in caught)
    measured = row.measured
    assert measured is not None and reference is not None
    hit = [missing > 0 for missing in measured.state_samples_missing]
    assert any(hit) and not all(hit)  # the hole lies in some moves, not all
    for missing, energy, before in zip(
        measured.state_samples_missing, measured.energies_j, reference.energies_j, strict=True
    ):
        if missing:
            assert energy is None  # never integrated across the hole
        else:
            assert energy == before
    done = cli.run("table2", str(damaged), "--out", str(tmp_path / "t2"))
    assert done.returncode == 0, done.stderr
    assert [line.split(": warning: ")[0] for line in done.stderr.strip().splitlines()] == [
        "axisflow table2"
    ] * 2


def test_each_moves_energies_and_parameter_version_in_the_order_they_ran(tmp_path):
    second = range(100 + 400 + 200, 100 + 400 + 205)
    runs, _accounting = recorded_runs(_write(tmp_path / "m.mcap", lost=set(second), versions=(0, 3, 4)))
    moves = move_energies(runs)
    expected = [amp_w * amp_q * (n / 1000) / (2 * math.pi) for n, _e, amp_w, amp_q in MOVES]
    assert [m.move_id for m in moves] == [1, 2, 3] and [m.params_version for m in moves] == [0, 3, 4]
    assert [m.start_ns for m in moves] == [T0 + 100 * MS, T0 + 500 * MS, T0 + (1100 + GAP) * MS]
    assert moves[0].end_ns - moves[0].start_ns == 400 * MS
    assert moves[0].energy_measured_j == pytest.approx(expected[0], rel=1e-4)
    assert moves[1].energy_measured_j is None and moves[1].energy_error_pct is None  # it lost samples
    e_th, e_exp = MOVES[2][1], expected[2]
    assert moves[2].energy_error_pct == pytest.approx((e_th - e_exp) / e_th * 100.0, rel=1e-4)


def test_table2_per_move_writes_csv_and_json_that_read_back(tmp_path, cli):
    path = _write(tmp_path / "m.mcap", versions=(0, 1, 1))
    out = tmp_path / "out"
    done = cli.run("table2", str(path), "--out", str(out), "--per-move")
    assert done.returncode == 0, done.stderr
    moves = read_move_energies(out / "moves.json")
    assert moves == move_energies(recorded_runs(path)[0])
    lines = (out / "moves.csv").read_text().splitlines()
    assert lines[0].split(",")[-3:] == ["energy_planned_j", "energy_measured_j", "energy_error_pct"]
    assert len(lines) == 4 and lines[2].split(",")[9] == "1"  # the second move's params_version
    assert "moves.csv" in done.stdout
