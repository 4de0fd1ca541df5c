"""The units of logged signals: factors to SI against their definitions, sides, aliases, counts; an
unknown unit lists the known ones."""

import math

import pytest
from axisflow.model import ParameterError
from axisflow.model.units import CARRIAGE_SIDE, MOTOR_SIDE, SIGNAL_UNITS, signal_unit


@pytest.mark.parametrize(
    ("quantity", "name", "si_per_unit", "side"),
    [
        ("time", "ms", 1e-3, None),
        ("time", "µs", 1e-6, None),
        ("position", "mm", 1e-3, CARRIAGE_SIDE),
        ("position", "deg", math.pi / 180, MOTOR_SIDE),
        ("position", "rev", 2 * math.pi, MOTOR_SIDE),
        ("velocity", "m/min", 1 / 60, CARRIAGE_SIDE),
        ("velocity", "rpm", 2 * math.pi / 60, MOTOR_SIDE),
        ("velocity", "1/min", 2 * math.pi / 60, MOTOR_SIDE),
        ("effort", "kN", 1e3, CARRIAGE_SIDE),
        ("effort", "Nm", 1.0, MOTOR_SIDE),
        ("effort", "mNm", 1e-3, MOTOR_SIDE),
    ],
)
def test_each_unit_converts_by_its_definition(quantity, name, si_per_unit, side):
    unit = signal_unit(quantity, name)
    assert unit.si_per_unit == pytest.approx(si_per_unit, rel=1e-15) and unit.side == side


def test_a_voltage_has_no_side_and_needs_a_scale():
    unit = signal_unit("effort", "V")
    assert unit.side is None and unit.needs_scale and unit.si == ""


def test_counts_take_the_side_and_size_of_their_unit():
    motor = signal_unit("position", "counts", (131072, "rev"))
    assert motor.side == MOTOR_SIDE and motor.si_per_unit == pytest.approx(2 * math.pi / 131072)
    linear = signal_unit("velocity", "counts/s", (20, "um"))  # a 50 nm linear encoder
    assert linear.side == CARRIAGE_SIDE and linear.si_per_unit == pytest.approx(50e-9) and linear.si == "m/s"
    with pytest.raises(ParameterError, match=r"needs the counts per unit of position \(e\.g\. 131072/rev"):
        signal_unit("position", "counts")


def test_an_unknown_unit_lists_the_known_ones():
    with pytest.raises(ParameterError, match=r"position unit 'inch' is not one of the known ones: m, mm, um"):
        signal_unit("position", "inch")
    assert set(SIGNAL_UNITS) == {"time", "position", "velocity", "effort"}
