"""Drive units ↔ SI: the conversions of model/drive_units.py, checked against hand-computed values
and by round trips."""

import math
from pathlib import Path

import numpy as np
import pytest
from axisflow.model import ParameterError, default_params, load_params
from axisflow.model.drive_units import INT16_MAX, DriveUnits
from axisflow.model.encoder import axis_resolution_m
from axisflow.model.transmission import LINEAR_SCALE_PERIOD_M

PARAMS = default_params()
UNITS = DriveUnits.for_axis(PARAMS, counts_per_rev=131072, rated_torque_nm=2.0, zero_counts=1000)


def test_one_count_is_the_cart_travel_of_one_motor_count_through_gearbox_and_pulley():
    expected = 2 * math.pi * PARAMS.r / (131072 * PARAMS.i_r)
    assert UNITS.metres_per_count == pytest.approx(expected, rel=1e-15)
    assert UNITS.position_m(1000) == 0.0
    assert UNITS.position_m(1000 + 131072 * PARAMS.i_r) == pytest.approx(2 * math.pi * PARAMS.r, rel=1e-14)


def test_per_mille_is_a_thousandth_of_the_rated_torque():
    assert UNITS.torque_nm(1000) == pytest.approx(2.0)
    assert UNITS.torque_nm(-1) == pytest.approx(-0.002)
    assert UNITS.per_mille(0.5) == 250


@pytest.mark.parametrize("x_m", [0.0, 1e-7, 0.123456789, 0.4, 0.8])
def test_position_round_trip_is_exact_to_half_a_count(x_m):
    back = UNITS.position_m(UNITS.counts(x_m))
    assert abs(back - x_m) <= 0.5 * UNITS.metres_per_count + 1e-15


@pytest.mark.parametrize("v", [-1.6, -0.01, 0.0, 0.37, 1.6])
def test_velocity_round_trip_is_exact_to_half_a_count_per_second(v):
    assert abs(UNITS.velocity_m_s(UNITS.counts_per_s(v)) - v) <= 0.5 * UNITS.metres_per_count + 1e-15


@pytest.mark.parametrize("tau", [-3.9, -0.0011, 0.0, 0.7777, 3.9])
def test_torque_round_trip_is_exact_to_half_a_per_mille(tau):
    assert abs(UNITS.torque_nm(UNITS.per_mille(tau)) - tau) <= 0.5 * UNITS.newton_metres_per_unit + 1e-15


def test_torque_saturates_at_the_signed_16_bit_range():
    assert UNITS.per_mille(1e9) == INT16_MAX
    assert UNITS.per_mille(-1e9) == -INT16_MAX


def test_quantisation_works_on_scalars_and_arrays_alike():
    xs = np.array([0.0, 0.1, 0.2])
    q = UNITS.quantise_position(xs)
    assert [UNITS.quantise_position(float(x)) for x in xs] == list(q)
    assert np.all(q <= xs) and np.all(xs - q < UNITS.metres_per_count)
    t = UNITS.quantise_torque(np.array([0.00149, -0.0015]))
    assert list(t) == pytest.approx([0.002, -0.002])


@pytest.mark.parametrize("a", [-9.0, -0.001, 0.0, 8.25])
def test_acceleration_round_trip_is_exact_to_half_a_count_per_second_squared(a):
    back = UNITS.acceleration_m_s2(UNITS.counts_per_s2(a))
    assert abs(back - a) <= 0.5 * UNITS.metres_per_count + 1e-15


def test_a_reversed_motor_flips_every_signed_quantity_but_not_distances():
    flipped = DriveUnits.for_axis(PARAMS, 131072, 2.0, zero_counts=1000, direction=-1)
    x, v, a, tau = 0.25, 0.4, 3.0, 1.5
    assert flipped.counts(x) - 1000 == -(UNITS.counts(x) - 1000)
    assert flipped.counts_per_s(v) == -UNITS.counts_per_s(v)
    assert flipped.counts_per_s2(a) == -UNITS.counts_per_s2(a)
    assert flipped.per_mille(tau) == -UNITS.per_mille(tau)
    for units in (UNITS, flipped):  # and each round-trips in its own frame
        assert abs(units.position_m(units.counts(x)) - x) <= 0.5 * units.metres_per_count + 1e-15
        assert abs(units.velocity_m_s(units.counts_per_s(v)) - v) <= 0.5 * units.metres_per_count + 1e-15
        assert abs(units.torque_nm(units.per_mille(tau)) - tau) <= 0.5 * units.newton_metres_per_unit + 1e-15
    assert flipped.distance_counts(0.005) == UNITS.distance_counts(0.005) == UNITS.distance_counts(-0.005)
    assert UNITS.distance_m(UNITS.distance_counts(0.005)) == pytest.approx(0.005, abs=UNITS.metres_per_count)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"direction": 0}, "direction = 0 must be 1 or -1"),
        ({"counts_per_rev": 0}, r"counts_per_rev = 0 counts must be in 1…2\^30 counts"),
        ({"counts_per_rev": 1.5}, "must be an integer"),
        ({"rated_torque_nm": 0.0}, r"rated_torque_nm = 0.0 N·m must be a finite number > 0"),
        ({"r": math.nan}, r"r = nan m must be a finite number > 0"),
    ],
)
def test_bad_units_are_refused_naming_the_value(kwargs, match):
    base = {"counts_per_rev": 4096, "rated_torque_nm": 1.0, "i_r": 10.0, "r": 0.04}
    with pytest.raises(ParameterError, match=match):
        DriveUnits(**{**base, **kwargs})


def test_the_encoder_count_is_the_one_at_or_below_the_position():
    for x in (0.0, 0.1234567, -0.0314, 0.8 - 1e-9):
        counts = UNITS.encoder_counts(x)
        assert UNITS.position_m(counts) <= x < UNITS.position_m(counts + 1) + 1e-15
        assert UNITS.position_m(counts) == pytest.approx(UNITS.quantise_position(x), abs=1e-15)


def test_a_reversed_encoder_counts_the_other_way_and_reads_back_within_a_count():
    reversed_units = DriveUnits.for_axis(
        PARAMS, counts_per_rev=131072, rated_torque_nm=2.0, zero_counts=1000, direction=-1
    )
    step = reversed_units.metres_per_count
    for x in (0.0, 0.1234567, -0.0314, 0.8 - 1e-9):
        counts = reversed_units.encoder_counts(x)
        assert counts == reversed_units.counts(x) or abs(counts - reversed_units.counts(x)) == 1
        assert x - 1e-15 <= reversed_units.position_m(counts) < x + step  # the count at or below, reversed


AXES = Path(__file__).parents[2] / "docs" / "axes"
KINDS = {
    # kind: (the file of docs/axes, travel per radian of the driven element [m] and reduction, by hand)
    "belt": ("belt.toml", 0.04, 10.0),
    "ball-screw": ("ball-screw.toml", 0.01 / (2 * math.pi), 1.0),
    "rack-pinion": ("rack-pinion.toml", 0.03, 5.0),
    "linear-motor": ("linear-motor.toml", LINEAR_SCALE_PERIOD_M / (2 * math.pi), 1.0),
}


@pytest.mark.parametrize("kind", KINDS)
def test_every_transmission_kind_maps_to_its_driven_elements_travel_and_counts_round_trip(kind):
    """A drive on each kind of axis: the driven element's travel per radian (a pulley's or pinion's
    radius, a screw's lead/2π, a linear motor's scale period/2π) and the reduction, one count the
    element's travel per turn over counts × i_r (what the encoder model resolves, model/encoder.py);
    positions, speeds and torques (a linear motor's: forces) round-trip to half a unit, and drive
    integers exactly."""
    name, per_radian, i_r = KINDS[kind]
    params = load_params(AXES / name)
    assert params.kind == kind
    counts_per_rev, rated = 131072, 0.4 * params.tau_max
    units = DriveUnits.for_axis(params, counts_per_rev, rated, zero_counts=-5000, direction=-1)
    assert (units.r, units.i_r) == (pytest.approx(per_radian, rel=1e-15), i_r)
    travel = params.transmission.output_travel_m
    assert units.metres_per_count == pytest.approx(travel / (counts_per_rev * i_r), rel=1e-14)
    assert units.metres_per_count == pytest.approx(axis_resolution_m(params, counts_per_rev) / i_r, rel=1e-14)
    for x in np.linspace(0.0, params.L, 7):
        assert abs(units.position_m(units.counts(x)) - x) <= 0.5 * units.metres_per_count + 1e-15
    for v in (-params.v_max, -1e-3, 0.0, 0.37 * params.v_max, params.v_max):
        assert abs(units.velocity_m_s(units.counts_per_s(v)) - v) <= 0.5 * units.metres_per_count + 1e-15
    for tau in (-params.tau_max, -1e-3 * rated, 0.0, 0.777 * params.tau_max, params.tau_max):
        assert abs(units.torque_nm(units.per_mille(tau)) - tau) <= 0.5 * units.newton_metres_per_unit + 1e-12
    for n in (-5000, 0, 123_457, -987_654):
        assert units.counts(units.position_m(n)) == n
    for p in (-2500, -1, 0, 1, 1000, 2500):
        assert units.per_mille(units.torque_nm(p)) == p
