"""The quick stop at full speed, measured on the recorded samples of a bridge process against the
axis's physical minimum (tests/acquisition/test_quick_stop.py checks it step by step in-process)."""

import pytest
from axisflow.benchmarks.fault_scenarios.quick_stop import quick_stop


@pytest.mark.slow
def test_a_quick_stop_at_full_speed_is_close_to_the_physical_minimum(tmp_path):
    r = quick_stop(tmp_path, at_fraction=0.5)
    d_min, t_min = r.minimum
    assert r.braking_from[1] > 1.0
    # no faster than physics allows (2 % for the encoder and the velocity filter), within 35 % of it
    # (the bridge brakes with 0.9 of the force limit, planned with the nominal parameters)
    assert 0.98 * d_min <= r.distance_m <= 1.35 * d_min
    assert r.time_s <= 1.25 * t_min + 0.005
    assert 0.0 < r.rest_m < r.L and r.dropped == 1
    assert "physical minimum" in r.bridge_text
    assert r.end.telemetry_intact
