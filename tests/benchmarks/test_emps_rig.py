"""The EMPS-like rig: the published friction, the closed loop, the log it writes, the textbook fit."""

from __future__ import annotations

import numpy as np
import pytest
from axisflow.acquisition import read_joint_states
from axisflow.benchmarks import emps_rig as rig
from axisflow.benchmarks.textbook_fit import fit_textbook, relative_force_error
from axisflow.identification.preparation import PreparationSettings, prepare
from axisflow.identification.signals import load_joint
from axisflow.model import default_params


@pytest.fixture(scope="module")
def one_lap() -> rig.RigLog:
    return rig.simulate(rig.RigSpec(laps=1))


def test_the_friction_is_the_published_table_at_its_bin_centres():
    speeds = np.linspace(-rig.TABLE_SPEED_M_S, rig.TABLE_SPEED_M_S, len(rig.FRICTION_TABLE_N))
    for v, f in zip(speeds, rig.FRICTION_TABLE_N, strict=True):
        if abs(v) > 1e-9:  # the middle bin is the stick, not a friction force
            assert rig.friction_n(float(v)) == pytest.approx(f, abs=1e-9)
    beyond = rig.friction_n(rig.TABLE_SPEED_M_S + 0.01) - rig.FRICTION_TABLE_N[-1]
    assert beyond == pytest.approx(rig.BEYOND_SLOPE_N_S_PER_M * 0.01)


def test_the_closed_loop_tracks_its_reference_within_a_millimetre(one_lap):
    assert one_lap.saturated == 0
    assert np.max(np.abs(one_lap.reference_m - one_lap.position_m)) < 1e-3
    assert np.max(np.abs(one_lap.true_velocity_m_s)) == pytest.approx(0.13, abs=0.01)
    steps = one_lap.position_m / rig.ENCODER_STEP_M
    assert np.allclose(steps, np.round(steps), atol=1e-6)  # the encoder's 50 nm


def test_the_log_has_one_joint_position_and_force_and_no_velocity(one_lap, tmp_path):
    path = rig.write_mcap(tmp_path / "emps.mcap", one_lap)
    joint = read_joint_states(path, rig.RIG_TOPIC).joint(rig.RIG_JOINT)
    assert np.array_equal(joint.stamp_ns, one_lap.stamp_ns)
    assert np.array_equal(joint.position, one_lap.position_m)
    assert np.allclose(joint.effort, rig.GTAU_N_PER_V * one_lap.vir_v)
    assert np.isnan(joint.velocity).all()


def test_the_textbook_fit_finds_the_rigs_inertia_and_scores_its_own_log(one_lap, tmp_path):
    path = rig.write_mcap(tmp_path / "emps.mcap", one_lap)
    nominal = default_params()
    signals = load_joint(path, rig.RIG_TOPIC, rig.RIG_JOINT, nominal)
    ls = fit_textbook([prepare(signals, PreparationSettings(), nominal.f_max)])
    assert ls.mass_kg == pytest.approx(rig.MASS_KG, rel=0.02)
    assert 15.0 < ls.coulomb_n < 30.0 and ls.offset_n < 0.0  # the table's level and its lean
    error = relative_force_error(signals, lambda log: ls.force_n(log.velocity_m_s, log.acceleration_m_s2))
    assert 0.01 < error < 0.1  # the friction is of no textbook shape: a few per cent are left
