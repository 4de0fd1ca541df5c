"""Plant files: the packaged profiles, building on a base profile, and what is refused (one line naming
the key, the value, the range and the unit)."""

import math
from pathlib import Path

import pytest
from axisflow.acquisition import PlantError
from axisflow.acquisition.drives.plant import (
    PROFILE_RESOURCES,
    BeltConfig,
    StrokeFrictionConfig,
    default_scale,
    load_plant,
    load_profile,
    plant_from_mapping,
)
from axisflow.model import default_params, load_params

NOMINAL = default_params()
FRICTION = {"a1", "a2", "a3", "a4"}
S = "[scale]\nm = 1.0\n"  # a true axis, for the rows below that spoil another section


def test_every_packaged_profile_loads_and_names_itself():
    for name in PROFILE_RESOURCES:
        plant = load_profile(name, NOMINAL)
        assert plant.profile == name
        assert PROFILE_RESOURCES[name] in plant.source
    assert load_plant(None, NOMINAL).profile == "ideal" and load_plant(None, NOMINAL).rigid


def test_the_realistic_profiles_build_on_the_ideal_true_axis():
    ideal, realistic, warm = (load_profile(n, NOMINAL) for n in ("ideal", "realistic", "warm-up"))
    assert realistic.axis == ideal.axis == warm.axis  # one [scale], in the ideal file
    assert realistic.scale == ideal.scale == default_scale()
    assert not realistic.rigid and realistic.drive is not None and realistic.belt is not None
    assert realistic.thermal is None and warm.thermal is not None and warm.wear is not None
    assert warm.drive == realistic.drive and warm.cogging == realistic.cogging


def test_the_default_scale_is_the_ideal_files_scale():
    scale = default_scale()
    plant = load_plant(None, NOMINAL)
    for key, factor in scale.items():
        assert getattr(plant.axis, key) == pytest.approx(getattr(NOMINAL, key) * factor, rel=1e-15)
    assert {"m", "a1", "a2", "a3", "a4"} <= set(scale)


@pytest.mark.parametrize("kind", ["ball-screw", "rack-pinion", "linear-motor"])
def test_every_packaged_profile_makes_a_true_axis_of_every_transmission_kind(kind):
    """The packaged [scale] scales the rotor of every kind that has one; a linear motor has none, and the
    factor on it scales nothing."""
    nominal = load_params(Path(__file__).parents[3] / "docs" / "axes" / f"{kind}.toml")
    for name in PROFILE_RESOURCES:
        plant = load_profile(name, nominal)
        assert plant.axis.kind == kind and set(plant.scale) <= {"m", *nominal.transmission.keys, *FRICTION}
        for key, factor in plant.scale.items():
            assert getattr(plant.axis, key) == pytest.approx(getattr(nominal, key) * factor, rel=1e-15)
        assert plant.axis.m == pytest.approx(1.05 * nominal.m, rel=1e-15)
        assert plant.axis.f0 == nominal.f0 and plant.axis.da1 == nominal.da1  # not scaled
    assert ("J_m" in load_profile("ideal", nominal).scale) is (kind != "linear-motor")


def test_a_user_file_builds_on_a_profile_and_overrides_single_keys(tmp_path):
    path = tmp_path / "plant.toml"
    path.write_text('profile = "hot belt"\nbase = "warm-up"\n[belt]\ndamping_ratio = 0.2\n')
    path.write_text(path.read_text() + "[scale]\na2 = 0.5\n")
    plant = load_plant(path, NOMINAL)
    warm = load_profile("warm-up", NOMINAL)
    assert plant.profile == "hot belt"
    assert plant.belt == BeltConfig(warm.belt.spring_rate_n, warm.belt.end_span_m, 0.2)
    assert plant.axis.a2 == pytest.approx(NOMINAL.a2 * 0.5) and plant.axis.a1 == warm.axis.a1
    assert plant.thermal == warm.thermal


def test_a_file_without_a_name_is_named_by_its_base_or_its_sections(tmp_path):
    path = tmp_path / "plant.toml"
    path.write_text(
        'base = "realistic"\n[cogging]\norders = [12]\namplitudes_nm = [0.01]\nphases_rad = [0.0]'
    )
    assert load_plant(path, NOMINAL).profile == "realistic"
    path.write_text("[scale]\nm = 1.1\n[belt]\nspring_rate_n = 2e6\n")
    assert load_plant(path, NOMINAL).profile == "custom"


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ('base = "cold"\n', r"base = 'cold' is not a packaged profile \(ideal, realistic, warm-up\)"),
        ('profile = ""\n[scale]\nm = 1.0\n', "profile = '' must be a non-empty name"),
        (S + "[drive]\n[encoder]\n", r"\[drive\] measures with the motor encoder"),
        (S + "[drive]\nrated_torque_nm = 0.0\n", "drive.rated_torque_nm = 0.0 N·m must be >= 0.001 N·m"),
        (S + "[drive]\ncounts_per_rev = 1.5\n", r"\[drive\] counts_per_rev = 1.5 must be an integer"),
        (S + "[sample_clock]\ndrop_fraction = 0.9\n", "sample_clock.drop_fraction = 0.9 must be <= 0.5"),
        (
            S + "[sample_clock]\njitter_ns = 2e6\n",
            r"\[sample_clock\] jitter_ns = 2000000.0 must be an integer",
        ),
        (S + "[sample_clock]\njitter_ns = 900000\n", "jitter_ns = 900000 ns must be <= 400000 ns"),
        (S + "[belt]\nspring_rate_n = -1.0\n", "belt.spring_rate_n = -1.0 N must be >= 1000.0 N"),
        (S + "[belt]\nstiffness = 3\n", r"unknown key\(s\) stiffness in \[belt\]"),
        (
            "[scale]\nm = 1.0\n[cogging]\norders = [24, 48]\namplitudes_nm = [0.01]\nphases_rad = [0, 0]\n",
            "must have the same length",
        ),
        (S + "[cogging]\norders = [2.5]\namplitudes_nm = [0.01]\nphases_rad = [0]\n", "orders"),
        (S + "[thermal]\ntime_constant_s = 0.0\n", "thermal.time_constant_s = 0.0 s must be >= 1.0 s"),
        (S + "[thermal]\nviscous_per_k = nan\n", "thermal.viscous_per_k = nan must be a finite"),
        (S + "[stroke_friction]\namplitudes = 0.1\n", "stroke_friction.amplitudes = 0.1 must be a list"),
        (S + "[wear]\ncoulomb_per_km = -1.0\n", "wear.coulomb_per_km = -1.0 1/km must be >= 0.0"),
        (S + "[current_loop]\ntorque_noise_std_nm = -0.1\n", "torque_noise_std_nm = -0.1 N·m"),
    ],
)
def test_bad_plant_files_are_refused_naming_the_key_and_the_range(tmp_path, text, match):
    path = tmp_path / "plant.toml"
    path.write_text(text)
    with pytest.raises(PlantError, match=match) as caught:
        load_plant(path, NOMINAL)
    assert "\n" not in str(caught.value) and str(path) in str(caught.value)


def test_the_stroke_profile_averages_to_one_over_whole_cycles():
    s = StrokeFrictionConfig(amplitudes=(0.04, 0.02), cycles=(1.0, 2.0), phases_rad=(0.7, 2.1))
    assert s.mean_factor(0.0, 0.8, 0.8) == pytest.approx(1.0, abs=1e-15)
    xs = [0.1 + 0.5 * i / 20000 for i in range(20001)]
    numeric = sum(s.factor(x, 0.8) for x in xs) / len(xs)
    assert s.mean_factor(0.1, 0.6, 0.8) == pytest.approx(numeric, rel=1e-6)
    assert max(abs(s.factor(x, 0.8) - 1.0) for x in xs) <= 0.06 + 1e-12


def test_the_belt_is_stiffest_near_the_drive_pulley():
    belt = BeltConfig(spring_rate_n=1.0e6, end_span_m=0.1)
    k = [belt.stiffness_n_m(x, 0.8) for x in (0.0, 0.4, 0.8)]
    assert k[0] > k[1] and k[2] > 0 and math.isfinite(k[2])
    assert k[1] == pytest.approx(1.0e6 / 0.5 + 1.0e6 / 1.5)


def test_a_mapping_with_both_axis_and_scale_is_refused():
    with pytest.raises(PlantError, match="exactly one of them"):
        plant_from_mapping({"scale": {"m": 1.0}, "axis": {}}, NOMINAL)


def _documented() -> dict[str, dict[str, object]]:
    """docs/plant.md's tables of file values, by the heading above them: ``| [section] key | value |``."""
    import re
    import tomllib
    from pathlib import Path

    text = (Path(__file__).resolve().parents[3] / "docs" / "plant.md").read_text("utf-8")
    tables: dict[str, dict[str, object]] = {}
    heading = ""
    for line in text.splitlines():
        if line.startswith("## "):
            heading = line[3:].strip()
        m = re.match(r"\| \[(\w+)\] (\w+) \| ([^|]+) \|", line)
        if m:
            section, key, value = m.groups()
            tables.setdefault(heading, {})[f"{section}.{key}"] = tomllib.loads(f"v = {value.strip()}")["v"]
    return tables


def _own_values(resource: str) -> dict[str, object]:
    """The values a packaged file gives itself (not those of its base), as ``section.key``."""
    import tomllib
    from importlib import resources

    data = tomllib.loads(resources.files("axisflow.acquisition.drives").joinpath(resource).read_text("utf-8"))
    return {f"{s}.{k}": v for s, table in data.items() if isinstance(table, dict) for k, v in table.items()}


def test_the_docs_state_every_number_of_the_packaged_plant_files():
    """docs/plant.md is checked against the files, so the files stay the one home of the numbers."""
    docs = _documented()
    ideal = _own_values(PROFILE_RESOURCES["ideal"])
    scale = {k: v for k, v in ideal.items() if k.startswith("scale.")}
    assert docs["The true axis (all profiles): `[scale]` of `plant_ideal.toml`"] == scale
    assert docs["`ideal`"] == {k: v for k, v in ideal.items() if not k.startswith("scale.")}
    assert docs["`realistic`"] == _own_values(PROFILE_RESOURCES["realistic"])
    assert docs["`warm-up`"] == _own_values(PROFILE_RESOURCES["warm-up"])
