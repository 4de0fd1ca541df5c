"""The adaptation experiment's settings are refused before anything starts (its run is `axisflow bench
adapt` and `axisflow demo --adapt`, measured in docs/adaptation.md)."""

import threading

import pytest
from axisflow.model import AxisflowError

from axisflow.demo.adaptation import AdaptationSettings, run_adaptation


@pytest.mark.parametrize(
    ("changes", "match"),
    [
        ({"minutes": 0.5}, r"--minutes 0\.5 must be in \[1, 600\] min of axis time"),
        ({"minutes": float("nan")}, r"--minutes nan must be in \[1, 600\]"),
        ({"waypoints": 1}, r"--waypoints 1 must be in \[2, 10000\]"),
        ({"adapt_from": "yesterday"}, r"adapt from 'yesterday' must be refit or nominal"),
    ],
)
def test_bad_settings_are_refused_before_anything_runs(tmp_path, changes, match):
    said = []
    settings = AdaptationSettings(out=tmp_path / "out", **changes)
    with pytest.raises(AxisflowError, match=match):
        run_adaptation(settings, said.append, threading.Event())
    assert said == [] and not (tmp_path / "out").exists()
