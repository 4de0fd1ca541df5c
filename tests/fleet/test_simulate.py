"""The simulated fleet: wear and idle specs, truth.json round trip, and one day's log as the catalog
and identification see it."""

from __future__ import annotations

import json

import pytest
from axisflow.fleet.catalog import IndexSettings, index_file
from axisflow.fleet.errors import FleetValueError
from axisflow.fleet.simulate import (
    FleetSpec,
    FleetTruth,
    IdleSpec,
    WearSpec,
    axis_truth,
    default_nominal,
    simulate_day,
    write_truth,
)

NOMINAL = default_nominal()
SHORT = ((0.06, 0.5), (0.3, 0.5))
"""two bursts: a 12 s day"""


def test_wear_steps_or_ramps_from_its_day():
    step, ramp = WearSpec.parse("a03:10:25"), WearSpec.parse("a03:10:20:4")
    assert [step.factor(d) for d in (9, 10, 29)] == [1.0, 1.25, 1.25]
    assert [ramp.factor(d) for d in (9, 10, 11, 13, 20)] == pytest.approx([1.0, 1.05, 1.10, 1.20, 1.20])


@pytest.mark.parametrize(
    ("text", "says"),
    [
        ("a1:x:10", "whole days"),
        ("a1:3", "AXIS:DAY:PERCENT"),
        ("a1:3:500", r"500.0 % must be within \[-50, 200\] %"),
    ],
)
def test_a_bad_wear_is_refused_naming_it(text, says):
    with pytest.raises(FleetValueError, match=says):
        WearSpec.parse(text)


def test_a_wear_or_idle_day_outside_the_fleet_is_refused():
    with pytest.raises(FleetValueError, match="no such axis"):
        FleetSpec(axes=3, days=5, wear=(WearSpec("a7", 1, 10),))
    with pytest.raises(FleetValueError, match="outside the 5 days"):
        FleetSpec(axes=3, days=5, wear=(WearSpec("a1", 5, 10),))
    with pytest.raises(FleetValueError, match="outside the 5 days"):
        FleetSpec(axes=3, days=5, idle=(IdleSpec("a1", 7),))


def test_truth_json_round_trips_and_applies_the_wear(tmp_path):
    spec = FleetSpec(axes=3, days=6, wear=(WearSpec("a1", 2, 25),), idle=(IdleSpec("a2", 1),), bursts=SHORT)
    truth = write_truth(tmp_path, spec, NOMINAL)
    back = FleetTruth.from_json(json.loads((tmp_path / "truth.json").read_text()))
    assert back == truth
    before, after = back.params_on("a1", 1), back.params_on("a1", 2)
    assert after.a1 == pytest.approx(1.25 * before.a1) and after.a3 == pytest.approx(1.25 * before.a3)
    assert after.a2 == before.a2
    assert back.params_on("a0", 5).a1 == back.params_on("a0", 0).a1
    # each axis its own parameters, drawn around nominal
    a1s = {round(axis_truth(spec, i, NOMINAL).params["a1"], 6) for i in range(3)}
    assert len(a1s) == 3 and all(0.75 < a / NOMINAL.a1 < 1.25 for a in a1s)


@pytest.mark.slow
def test_a_day_s_log_moves_both_ways_at_several_speeds_and_loses_samples_like_the_realistic_plant(tmp_path):
    spec = FleetSpec(axes=2, days=1, bursts=SHORT)
    day = simulate_day(spec, 1, 0, tmp_path, NOMINAL)
    assert day.path == tmp_path / "a1" / "a1_2026-01-05.mcap"
    (entry,) = index_file(day.path, NOMINAL, IndexSettings())
    assert entry.ok and entry.axis == "a1" and entry.samples == day.samples
    assert entry.start_ns == pytest.approx(spec.day_start_ns(1, 0), abs=100_000)  # the clock's jitter
    assert 0 < entry.missing == day.lost < 0.005 * day.samples  # the realistic plant's 0.1 % lost
    assert entry.reversals >= 8 and entry.speed_high_m_s > 0.25 and entry.speed_low_m_s < 0.05
