"""The simulated drive: plant file validation, encoder resolution, saturation, holding and tracking (the
ideal profile); the realistic profiles' drive units, noise, sample clock and true parameters."""

import math

import numpy as np
import pytest
from axisflow.acquisition import MoveCommand, MoveQueue, PlantError, Setpoint, SimulatedAxis, load_plant
from axisflow.acquisition.drives.plant import plant_from_mapping
from axisflow.model import AxisParams, default_params, params_to_toml
from axisflow.model.transmission import Belt

# a fixed axis (the paper's geometry), so the tests do not depend on the packaged defaults
PARAMS = AxisParams(
    m=20.0, transmission=Belt(J_m=1.5e-4, J_g=5e-5, J_p=2e-4, r=0.03, i_r=10.0), L=0.8,
    a1=100.0, a2=50.0, a3=20.0, a4=50.0, v_max=1.0, tau_max=3.0,
)  # fmt: skip
T0 = 1_700_000_000_000_000_000


def _axis(**sim_overrides):
    plant = load_plant(None, PARAMS)
    if sim_overrides:
        plant = plant.__class__(
            axis=plant.axis,
            encoder=plant.encoder,
            torque_sensor=plant.torque_sensor,
            controller=plant.controller,
            simulation=plant.simulation.__class__(**{**plant.simulation.__dict__, **sim_overrides}),
        )
    return SimulatedAxis(plant, PARAMS, T0)


def test_default_plant_deviates_from_nominal():
    nominal = default_params()
    plant = load_plant(None, nominal)
    assert plant.axis.M_eq != pytest.approx(nominal.M_eq, rel=0.01)
    for name in ("a1", "a2", "a3"):
        rel = abs(getattr(plant.axis, name) / getattr(nominal, name) - 1)
        assert 0.05 <= rel <= 0.3, name


def _plant_text(extra: str = "") -> str:
    return "[axis]\n" + params_to_toml(default_params()) + extra


@pytest.mark.parametrize(
    ("extra", "match"),
    [
        ("[encoder]\ncounts_per_rev = 0\n", "counts_per_rev = 0 counts must be >= 1"),
        ("[encoder]\nresolution = 3\n", "unknown key.*resolution"),
        ("[simulation]\nsubsteps = 2.5\n", "substeps = 2.5 must be an integer"),
        ("[simulation]\ninitial_position_m = 2.0\n", "initial_position_m = 2.0 m is outside"),
        ("[torque_sensor]\nnoise_std_nm = -1.0\n", "noise_std_nm = -1.0 N·m must be >= 0"),
        ("[wheels]\nn = 4\n", "unknown section"),
        ("[scale]\nm = 1.1\n", "exactly one of them"),
    ],
)
def test_bad_plant_files_rejected(tmp_path, extra, match):
    path = tmp_path / "plant.toml"
    path.write_text(_plant_text(extra))
    with pytest.raises(PlantError, match=match):
        load_plant(path, PARAMS)


@pytest.mark.parametrize(
    ("scale", "match"),
    [
        ({"m": 0.0}, "m = 0.0 must be a finite factor > 0"),
        ({"L": 2.0}, r"unknown key\(s\) L in \[scale\]"),
    ],
)
def test_bad_scale_factors_rejected(scale, match):
    with pytest.raises(PlantError, match=match):
        plant_from_mapping({"scale": scale}, PARAMS)


def test_absolute_axis_table_is_used_as_given(tmp_path):
    path = tmp_path / "plant.toml"
    path.write_text(_plant_text())
    assert load_plant(path, PARAMS.replace(m=PARAMS.m * 2)).axis == default_params()


def test_missing_axis_section_and_missing_file(tmp_path):
    with pytest.raises(PlantError, match="exactly one of them"):
        plant_from_mapping({"encoder": {}}, PARAMS)
    with pytest.raises(PlantError, match="does not exist"):
        load_plant(tmp_path / "nope.toml", PARAMS)


def test_stamps_advance_exactly_one_ms():
    ax = _axis()
    stamps = []
    for _ in range(5):
        stamps.append(ax.read().stamp_ns)
        ax.apply(Setpoint(0.0, 0.0, 0.0, 0.0))
    assert np.diff(stamps).tolist() == [1_000_000] * 4


def test_encoder_quantises_position_to_counts():
    ax = _axis(initial_position_m=0.3)
    step = 2 * math.pi * PARAMS.r / 131072  # one count of the 17-bit pulley encoder
    x = ax.read().position_m
    assert x / step == pytest.approx(round(x / step), abs=1e-6)
    assert 0.0 <= 0.3 - x < step


def test_torque_saturates_at_tau_max():
    ax = _axis(initial_position_m=0.4)
    ax.apply(Setpoint(0.8, 0.0, 0.0, 1e6))  # absurd command
    assert ax.applied_torque_nm == PARAMS.tau_max


def test_holds_position_with_no_move():
    ax = _axis(initial_position_m=0.4)
    for _ in range(500):
        ax.read()
        ax.apply(Setpoint(0.4, 0.0, 0.0, 0.0))
    assert ax.read().position_m == pytest.approx(0.4, abs=5e-4)
    assert abs(ax.velocity_m_s) < 1e-3


def test_tracks_a_move_and_comes_to_rest_at_its_end():
    params = PARAMS
    ax = _axis(initial_position_m=0.1)
    queue = MoveQueue(params, 0.1, T0, "a0")
    queue.submit(MoveCommand(0, "a0", 1, 0, "poly5", 0.1, 0.6, 1.0), 0)
    errors, torques = [], []
    for k in range(1500):
        s = ax.read()
        sp = queue.setpoint(k)
        errors.append(abs(sp.position_m - s.position_m))
        torques.append(abs(s.motor_torque_nm))
        ax.apply(sp)
    assert max(errors) < 1e-3  # mm-level tracking with model feed-forward
    assert ax.position_m == pytest.approx(0.6, abs=5e-4)
    assert ax.velocity_m_s == 0.0
    assert max(torques) <= params.tau_max + 0.1  # measured torque: saturated command + noise


def test_a_plant_restarted_on_its_state_file_starts_where_the_axis_came_to_rest(tmp_path):
    from axisflow.model import stop_profile

    p = default_params()
    plant = load_plant(None, p)
    state = tmp_path / "plant.state"
    first = SimulatedAxis(plant, p, 0, state_path=state)
    first.position_m, first.velocity_m_s = 0.2, 0.0
    for _ in range(300):  # pushed at 2 N·m: moving when "killed" (no close)
        first.apply(Setpoint(0.8, 1.0, 0.0, 2.0 * p.i_r / p.r))
    x, v = first.position_m, first.velocity_m_s
    assert v > 0.1
    second = SimulatedAxis(plant, p, 0, state_path=state)
    coast = stop_profile(x, v, plant.axis, force_fraction=0.0)
    assert second.position_m == pytest.approx(coast.trajectory.x1_m) and second.velocity_m_s == 0.0
    assert x < second.position_m < p.L
    assert SimulatedAxis(plant, p, 0).position_m == plant.simulation.initial_position_m  # no file: as before
    second.close()


# ---- the realistic profiles --------------------------------------------------------------------------


def _realistic(profile="realistic", x0=0.4, **sections):
    """A packaged profile's plant (with sections replaced), starting at ``x0``."""
    import dataclasses

    from axisflow.acquisition.drives.plant import load_profile

    plant = load_profile(profile, default_params())
    sim = dataclasses.replace(plant.simulation, initial_position_m=x0)
    return dataclasses.replace(plant, simulation=sim, **sections)


def _sine_setpoints(p, n, amplitude=0.2, hz=0.5, center=0.4):
    from axisflow.model import cart_force

    out = []
    w = 2 * math.pi * hz
    for k in range(n):
        t = k * 1e-3
        x = center + amplitude * math.sin(w * t)
        v, a = amplitude * w * math.cos(w * t), -amplitude * w * w * math.sin(w * t)
        out.append(Setpoint(x, v, a, float(cart_force(v, a, p))))
    return out


def test_a_realistic_drive_reports_in_counts_and_per_mille():
    p = default_params()
    plant = _realistic()
    units = plant.drive.units(p)
    ax = SimulatedAxis(plant, p, T0)
    seen = 0
    for sp in _sine_setpoints(p, 3000):
        s = ax.read()
        ax.apply(sp)
        if s is None:
            continue
        seen += 1
        counts = s.position_m / units.metres_per_count
        assert counts == pytest.approx(round(counts), abs=1e-6)
        per_mille = s.motor_torque_nm / units.newton_metres_per_unit
        assert per_mille == pytest.approx(round(per_mille), abs=1e-6)
        speed = s.velocity_m_s / units.metres_per_count
        assert speed == pytest.approx(round(speed), abs=1e-6)
        assert s.motor_angle_rad == pytest.approx(s.position_m * p.i_r / p.r, rel=1e-12)
    assert seen > 2900


def test_the_sample_clock_jitters_stamps_and_loses_about_one_sample_in_a_thousand():
    p = default_params()
    ax = SimulatedAxis(_realistic(), p, T0)
    ax.read()
    assert ax.status().fresh  # the first sample is never lost: the bridge starts from it
    n, lost, deviations = 100_000, 0, []
    for k in range(n):
        s = ax.read()
        if not ax.status().fresh:
            lost += 1
            assert s.stamp_ns < T0 + k * 1_000_000 - 500_000  # the last sample that arrived, again
        else:
            deviations.append(s.stamp_ns - (T0 + k * 1_000_000))
        ax.apply(Setpoint(0.4, 0.0, 0.0, 0.0))
    assert 50 <= lost <= 150  # binomial(1e5, 1e-3): 100 ± 10
    assert max(abs(d) for d in deviations) <= 50_000
    assert np.std(deviations) == pytest.approx(100_000 / math.sqrt(12), rel=0.05)  # uniform ±50 µs


def test_a_realistic_run_is_reproducible_from_its_seed():
    p = default_params()
    runs = []
    for _ in range(2):
        ax = SimulatedAxis(_realistic("warm-up"), p, T0)
        samples = []
        for sp in _sine_setpoints(p, 2000):
            samples.append(ax.read())
            ax.apply(sp)
        runs.append(samples)
    assert runs[0] == runs[1]


def test_the_coloured_noise_has_its_std_and_its_corner():
    import random

    from axisflow.acquisition.drives.sim_axis import _ColouredNoise

    noise = _ColouredNoise(0.01, 20.0)
    rng = random.Random(3)
    x = np.array([noise.next(rng.gauss(0.0, 1.0)) for _ in range(400_000)])[1000:]
    rho = math.exp(-2 * math.pi * 20.0 * 1e-3)
    assert np.std(x) == pytest.approx(0.01, rel=0.05)
    assert np.corrcoef(x[:-1], x[1:])[0, 1] == pytest.approx(rho, abs=0.01)


def test_cogging_shows_in_the_current_the_loop_spends_against_it():
    """Moving slowly (cogging at ~1.9 Hz, well inside the 20 Hz loop), the drive's current cancels the
    cogging torque: the measured torque carries −A·sin(24·θ + φ) of the motor angle."""
    from axisflow.acquisition.drives.plant import CoggingConfig, TorqueSensorConfig

    p = default_params()
    cogging = CoggingConfig(orders=(24,), amplitudes_nm=(0.02,), phases_rad=(0.4,))
    plant = _realistic(x0=0.3, cogging=cogging, current_loop=None, belt=None, stroke_friction=None,
                       torque_sensor=TorqueSensorConfig(0.0, 1))  # fmt: skip
    ax = SimulatedAxis(plant, p, T0)
    v = 0.002
    angle, torque = [], []
    for k in range(10_000):
        s = ax.read()
        x = 0.3 + v * k * 1e-3
        ax.apply(Setpoint(x, v, 0.0, float(p.a1 + p.a2 * v + p.a3 * math.atan(p.a4 * v))))
        if s is not None and k > 2000:
            angle.append(ax.mechanics.motor_x * p.i_r / p.r)
            torque.append(s.motor_torque_nm)
    theta, tau = np.array(angle), np.array(torque) - np.mean(torque)
    basis = np.column_stack([np.sin(24 * theta + 0.4), np.cos(24 * theta + 0.4)])
    coef, *_ = np.linalg.lstsq(basis, tau, rcond=None)
    assert coef[0] == pytest.approx(-0.02, rel=0.15) and abs(coef[1]) < 0.005


def test_the_belt_stretches_by_the_friction_over_its_stiffness_at_constant_speed():
    p = default_params()
    plant = _realistic(x0=0.2, stroke_friction=None, cogging=None, current_loop=None)
    ax = SimulatedAxis(plant, p, T0)
    v = 0.3
    for k in range(1500):
        ax.read()
        ax.apply(Setpoint(0.2 + v * k * 1e-3, v, 0.0, float(p.a1 + p.a2 * v + p.a3 * math.atan(p.a4 * v))))
    truth = plant.axis
    friction = truth.a1 + truth.a2 * ax.velocity_m_s + truth.a3 * math.atan(truth.a4 * ax.velocity_m_s)
    k = plant.belt.stiffness_n_m(ax.position_m, truth.L)
    assert ax.velocity_m_s == pytest.approx(v, rel=0.01)
    assert ax.mechanics.stretch_m() == pytest.approx(friction / k, rel=0.03)


def test_the_warm_up_plant_warms_and_its_true_friction_falls():
    p = default_params()
    ax = SimulatedAxis(_realistic("warm-up"), p, T0)
    cold = ax.true_params()
    assert cold.a2 == ax.plant.axis.a2 and ax.temperature_c == 20.0
    for sp in _sine_setpoints(p, 30_000, amplitude=0.3, hz=0.6):
        ax.read()
        ax.apply(sp)
    now = ax.true_params()
    assert ax.temperature_c > 21.0
    assert now.a2 < cold.a2 and now.a1 != cold.a1 and now.a4 == cold.a4
    assert now.a2 == pytest.approx(cold.a2 * math.exp(-0.012 * (ax.temperature_c - 20.0)), rel=1e-12)


@pytest.mark.parametrize(
    ("x", "v", "match"),
    [
        (5.0, 0.0, r"holds x = 5 m, outside the stroke \[0, 0.8\] m"),
        (-0.1, 0.0, r"holds x = -0.1 m, outside the stroke \[0, 0.8\] m"),
        (0.4, 100.0, r"holds v = 100 m/s, beyond ±1.65 m/s \(v_max 1.5 m/s \+ 10%\)"),
    ],
)
def test_a_state_file_outside_the_stroke_or_the_speed_limit_is_refused_untouched(tmp_path, x, v, match):
    import struct

    p = default_params()
    state = tmp_path / "plant.state"
    state.write_bytes(struct.pack("<dd", x, v))
    before = state.read_bytes()
    with pytest.raises(PlantError, match=match):
        SimulatedAxis(load_plant(None, p), p, 0, state_path=state)
    assert state.read_bytes() == before


@pytest.mark.parametrize("profile", ["realistic", "warm-up"])
def test_a_realistic_linear_motor_has_no_belt_and_tracks_a_move(profile):
    """A linear motor's coil moves with its carriage: nothing on the motor side of a belt, so the
    realistic profiles' [belt] leaves it rigid; it runs their drive units, noise and clock all the same."""
    import dataclasses
    from pathlib import Path

    from axisflow.acquisition.drives.mechanics import RigidAxis
    from axisflow.acquisition.drives.plant import load_profile
    from axisflow.model import load_params

    p = load_params(Path(__file__).parents[3] / "docs" / "axes" / "linear-motor.toml")
    plant = load_profile(profile, p)
    plant = dataclasses.replace(
        plant, simulation=dataclasses.replace(plant.simulation, initial_position_m=0.1)
    )
    assert plant.belt is not None
    ax = SimulatedAxis(plant, p, T0)
    assert isinstance(ax.mechanics, RigidAxis)
    queue = MoveQueue(p, 0.1, T0, "a0")
    queue.submit(MoveCommand(0, "a0", 1, 0, "poly5", 0.1, 0.5, 0.5), 0)
    errors = []
    for k in range(1000):
        s = ax.read()
        sp = queue.setpoint(k)
        if s is not None:
            errors.append(abs(sp.position_m - s.position_m))
        ax.apply(sp)
    assert max(errors) < 1e-3 and ax.position_m == pytest.approx(0.5, abs=1e-3)
