"""The simulated axis: plant file validation, encoder resolution, saturation, holding and tracking."""

import math

import numpy as np
import pytest
from axisflow.acquisition import MoveCommand, MoveQueue, PlantError, Setpoint, SimulatedAxis, load_plant
from axisflow.acquisition.drives.sim_axis import plant_from_mapping
from axisflow.model import AxisParams, default_params, params_to_toml

# a fixed axis (the paper's geometry), so the tests do not depend on the packaged defaults
PARAMS = AxisParams(
    m=20.0, J_m=1.5e-4, J_g=5e-5, J_p=2e-4, r=0.03, i_r=10.0, L=0.8,
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


def test_the_plants_scalar_friction_is_the_models_law():
    import numpy as np
    from axisflow.acquisition.drives.sim_axis import moving_friction
    from axisflow.model import default_params, friction_force

    p = default_params().replace(a1=61.0, a2=190.0, a3=150.0, a4=9.0)
    v = np.array([-1.3, -0.2, -1e-3, -1e-6, 1e-6, 1e-3, 0.2, 1.3])
    assert [moving_friction(float(x), p) for x in v] == pytest.approx(
        friction_force(v, p).tolist(), rel=1e-15
    )


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
