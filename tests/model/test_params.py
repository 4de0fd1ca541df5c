import json

import pytest
from axisflow.model import AxisParams, EnergyAccounting, ParameterError, default_params, load_params
from axisflow.model.params import FILE_KEYS, params_to_toml

JSON_KEYS = {
    "m",
    "J_m",
    "J_g",
    "J_p",
    "r",
    "i_r",
    "L",
    "a1",
    "a2",
    "a3",
    "a4",
    "v_max",
    "tau_max",
    "M_eq",
    "energy_accounting",
}


def _toml(**overrides):
    data = default_params().to_dict()
    data.pop("M_eq")
    data.update(overrides)
    lines = []
    for k, v in data.items():
        if v is None:
            continue
        lines.append(f'{k} = "{v}"' if isinstance(v, str) else f"{k} = {v!r}")
    return "\n".join(lines) + "\n"


def test_default_has_the_paper_gear_ratio_and_stroke():
    p = default_params()
    assert p.i_r == 10.0
    assert p.L == 0.8
    assert p.energy_accounting is EnergyAccounting.POSITIVE


def test_equivalent_mass_follows_eq_1():
    p = default_params().replace(m=10.0, J_m=1e-4, J_g=2e-4, J_p=3e-4, r=0.02, i_r=10.0)
    assert p.M_eq == pytest.approx(10.0 + ((1e-4 + 2e-4) * 100 + 2 * 3e-4) / 0.02**2)


def test_json_keys_are_exactly_the_documented_ones():
    data = default_params().to_dict()
    assert set(data) == JSON_KEYS
    json.dumps(data)  # JSON-ready


def test_toml_round_trip(tmp_path):
    p = default_params().replace(a1=12.5, energy_accounting="signed")
    f = tmp_path / "p.toml"
    f.write_text(params_to_toml(p))
    assert load_params(f) == p


@pytest.mark.parametrize(
    ("overrides", "match"),
    [
        ({"mass": 3.0}, r"unknown key\(s\) mass = 3.0"),
        ({"i_r": 0.0}, r"i_r = 0.0 is outside the physical range \[0.1, 1000\] \("),
        ({"a4": None}, r"the atan term's keys a3 and a4 go together: a4 is missing"),
        ({"m": None}, r"missing key\(s\) m \[kg\]"),
        ({"da1": 3.0}, r"the asymmetry term's keys da1 and da2 go together: da2 is missing"),
        ({"f0": 1500.0}, r"F_max = tau_max·i_r/r = 1000 N, not above the constant force \|f0\| = 1500 N"),
        ({"f0": 950.0}, r"not above the force c = a1 \+ da1 \+ f0 = 1022 N .* towards \+x"),
        ({"da1": 80.0, "da2": 0.0}, r"a1 = 72.0 N, da1 = 80.0 N give a negative friction"),
        ({"m": -1.0}, r"m = -1.0 kg is outside the physical range \[0.001, 10000\] kg \("),
        ({"m": 0.0}, r"m = 0.0 kg is outside the physical range \[0.001, 10000\] kg"),
        ({"m": 1e308}, r"m = 1e\+308 kg is outside the physical range \[0.001, 10000\] kg"),
        ({"r": 0.0}, r"r = 0.0 m is outside the physical range \[0.001, 0.5\] m"),
        ({"r": 40.0}, r"r = 40.0 m is outside the physical range \[0.001, 0.5\] m"),
        ({"J_p": -1e-4}, r"J_p = -0.0001 kg·m² is outside the physical range \[1e-08, 1\] kg·m²"),
        ({"J_g": 2.0}, r"J_g = 2.0 kg·m² is outside the physical range \[0, 1\] kg·m²"),
        ({"v_max": 0.0}, r"v_max = 0.0 m/s is outside the physical range \[0.001, 20\] m/s"),
        ({"tau_max": -3.0}, r"tau_max = -3.0 N·m is outside the physical range \[0.001, 10000\] N·m"),
        ({"L": 0.0}, r"L = 0.0 m is outside the physical range \[0.01, 50\] m"),
        ({"L": 800.0}, r"L = 800.0 m is outside the physical range \[0.01, 50\] m"),
        ({"a2": -5.0}, r"a2 = -5.0 N·s/m is outside the physical range \[0, 100000\] N·s/m"),
        ({"a4": 1e5}, r"a4 = 100000.0 s/m is outside the physical range \[0, 10000\] s/m"),
        ({"tau_max": 0.1}, r"F_max = tau_max·i_r/r = 25 N, not above the Coulomb friction a1 = 72.0 N"),
        ({"v_max": 20.0, "r": 0.001}, r"v_max·i_r/r = 200000 rad/s \(1.90986e\+06 rpm\), above the fastest"),
        ({"energy_accounting": "regen"}, r"energy_accounting = 'regen' is not one of"),
        ({"m": "heavy"}, r"m must be a number in kg"),
    ],
)
def test_bad_parameter_files_are_rejected_with_key_value_and_unit(tmp_path, overrides, match):
    f = tmp_path / "bad.toml"
    f.write_text(_toml(**overrides))
    with pytest.raises(ParameterError, match=match):
        load_params(f)


def test_a_missing_key_is_named_with_its_unit_and_a_dimensionless_one_bare(tmp_path):
    """The flat belt keys and a [transmission] table name what is missing the same way."""
    flat = tmp_path / "flat.toml"
    flat.write_text(_toml(r=None, i_r=None))
    with pytest.raises(ParameterError, match=r"missing key\(s\) r \[m\], i_r$"):
        load_params(flat)
    table = tmp_path / "table.toml"
    keys = {"J_m": 1e-4, "J_g": 1e-5, "J_p": 1e-4, "r": 0.03}
    body = _toml(**dict.fromkeys(("J_m", "J_g", "J_p", "r", "i_r")))
    table.write_text(
        body + '\n[transmission]\nkind = "rack-pinion"\n' + "".join(f"{k} = {v}\n" for k, v in keys.items())
    )
    with pytest.raises(
        ParameterError, match=r"\[transmission\] of kind rack-pinion is missing key\(s\) i_r$"
    ):
        load_params(table)


def test_non_finite_value_is_rejected(tmp_path):
    f = tmp_path / "nan.toml"
    f.write_text(_toml().replace("a1 = ", "a1 = nan #"))
    with pytest.raises(ParameterError, match="a1 = nan N is not finite"):
        load_params(f)


def test_missing_and_malformed_files(tmp_path):
    with pytest.raises(ParameterError, match="does not exist"):
        load_params(tmp_path / "nope.toml")
    f = tmp_path / "broken.toml"
    f.write_text("m = = 3\n")
    with pytest.raises(ParameterError, match="not valid TOML"):
        load_params(f)


def test_a_binary_file_is_named_as_not_text(tmp_path):
    f = tmp_path / "binary.toml"
    f.write_bytes(b"m = 3\n\xff\xfe\x00")
    with pytest.raises(ParameterError, match=r"binary.toml is not UTF-8 text \(byte 0xff at offset 6\)"):
        load_params(f)


def test_file_keys_cover_every_field():
    from axisflow.model.transmission import Belt

    fields = set(AxisParams.__dataclass_fields__) - {"terms"}
    assert set(FILE_KEYS) == fields | set(Belt.keys)


def test_the_ranges_in_the_docs_are_the_code_s():
    from pathlib import Path

    from axisflow.model.parameter_ranges import ranges_table

    docs = (Path(__file__).parents[2] / "docs" / "parameters.md").read_text("utf-8")
    for key, text, why in ranges_table():
        assert f"| {key} | {text} | {why} |" in docs, key


def test_a_new_equivalent_mass_goes_into_the_cart_mass():
    params = default_params()
    rotating = params.M_eq - params.m
    heavier = params.with_equivalent_mass(params.M_eq + 5.0)
    assert heavier.m == pytest.approx(params.m + 5.0, rel=1e-12)
    assert heavier.M_eq - heavier.m == pytest.approx(rotating, rel=1e-12)
    assert (heavier.J_m, heavier.J_g, heavier.J_p) == (params.J_m, params.J_g, params.J_p)
    with pytest.raises(ParameterError, match="M_eq = 1 kg is not above the rotating parts' share"):
        params.with_equivalent_mass(1.0)


def test_the_parameter_file_of_each_transmission_kind_in_the_docs_loads_and_round_trips(tmp_path):
    from pathlib import Path

    from axisflow.model.transmission import TRANSMISSION_KINDS

    axes = Path(__file__).parents[2] / "docs" / "axes"
    for kind in TRANSMISSION_KINDS:
        params = load_params(axes / f"{kind}.toml")
        assert params.kind == kind
        f = tmp_path / f"{kind}.toml"
        f.write_text(params_to_toml(params))
        assert load_params(f) == params
        k = params.transmission
        assert k.carriage_position(k.motor_angle(0.3)) == pytest.approx(0.3, rel=1e-15)
        assert k.force_per_torque * k.metres_per_radian == pytest.approx(1.0, rel=1e-15)
