"""The fleet end to end on a real Dask LocalCluster (two worker processes on 127.0.0.1): a tiny
fleet simulated on it, indexed with an unreadable log among the good ones, identified on it (each
axis calibrated first), done again with nothing new, the fits of the axes without wear within their
σ of the truth, and the wearing axis alarmed — the only alarm."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest
from axisflow.fleet.axis_calibration import calibrated_windows, read_calibrations
from axisflow.fleet.catalog import index_logs
from axisflow.fleet.cluster import fleet_client
from axisflow.fleet.fits import read_fits
from axisflow.fleet.job import identify_windows, pending
from axisflow.fleet.simulate import FleetSpec, WearSpec, default_nominal, simulate_fleet
from axisflow.fleet.trend import DetectorSettings
from axisflow.fleet.trend_job import trend_fleet
from axisflow.fleet.window_fit import COULOMB_SPEED_M_S, FitSettings
from axisflow.fleet.windows import NS_PER_DAY, WindowSpec, plan_windows
from axisflow.model import forward_friction

NOMINAL = default_nominal()
SPEC = FleetSpec(axes=3, days=6, wear=(WearSpec("a1", 3, 25),))
"""days of the fleet's full program (35 s of motion): on shorter ones a window's σ is wide enough to
hide the bias of an offset held at 0"""


@pytest.mark.slow
@pytest.mark.timeout(600)
def test_a_tiny_fleet_on_a_local_cluster(tmp_path):
    logs, catalog = tmp_path / "logs", tmp_path / "catalog"
    settings = FitSettings(NOMINAL)
    with fleet_client(workers=2) as client:
        info = client.scheduler_info()
        assert len(info["workers"]) == 2 and info["address"].startswith("tcp://127.0.0.1:")
        assert all(w.startswith("tcp://127.0.0.1:") for w in info["workers"])
        fleet = simulate_fleet(SPEC, logs, client, NOMINAL)
        assert len(fleet.days) == 18 and (logs / "truth.json").exists()
        (logs / "a0" / "broken.mcap").write_bytes(b"\x89MCAP0\r\n and then nothing")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            indexed = index_logs([logs], catalog, NOMINAL)
        assert indexed.unreadable == 1 and sum(e.ok for e in indexed.entries) == 18
        windows = plan_windows(indexed.entries, WindowSpec.parse("day"), settings.method())
        first = identify_windows(client, windows, settings, catalog)
        assert len(first.new) == 18 and all(r.status == "ok" for r in first.new), [
            r.reason for r in first.new
        ]
        assert len({r.worker for r in first.new}) == 2  # both workers took windows
        again = index_logs([logs], catalog, NOMINAL)
        assert again.read == 0  # nothing changed: no log read again, no window to do again
        planned = plan_windows(again.entries, WindowSpec.parse("day"), settings.method())
        kept, todo = pending(calibrated_windows(planned, settings)[0], catalog)
        assert todo == [] and {r.key for r in kept} == {r.key for r in read_fits(catalog)}
    # each axis's offset held in all its windows, from its calibration
    calibrations = {c.axis: c for c in read_calibrations(catalog)}
    assert sorted(calibrations) == ["a0", "a1", "a2"] and all(c.ok for c in calibrations.values())
    for row in first.new:
        assert row.torque_delay_s == calibrations[row.axis].torque_delay_s
    # the Coulomb friction at 0.2 m/s of the axes without wear against the truth of its day, in units
    # of its σ against the truth (the window's and the calibration's): an offset held at 0 (each
    # window fitted alone) left 7 of these 12 within 2 σ, with a median of +1.6 σ
    z = []
    for row in first.new:
        if row.axis != "a1":
            day = (row.window_start_ns - SPEC.first_day_ns) // NS_PER_DAY
            truth = fleet.truth.params_on(row.axis, day, (row.stretch_low_m, row.stretch_high_m))
            z.append((row.coulomb_n - forward_friction(COULOMB_SPEED_M_S, truth)) / row.coulomb_truth_std_n)
    assert len(z) == 12
    assert sum(abs(e) <= 2.0 for e in z) >= 9 and abs(float(np.median(z))) < 1.0, z
    result = trend_fleet(catalog, DetectorSettings(baseline_windows=3))
    alarms = json.loads((catalog / "alarms.json").read_text())
    assert [(a["axis"], a["parameter"]) for a in alarms] == [("a1", "coulomb_n")]
    assert alarms[0]["onset"] == "2026-01-08T00:00:00Z"  # day 3
    # a1 and a3 up 25 %: the friction at 0.2 m/s by less (its viscous part does not wear)
    before, after = (forward_friction(COULOMB_SPEED_M_S, fleet.truth.params_on("a1", d)) for d in (2, 3))
    assert alarms[0]["change_pct"] == pytest.approx(100.0 * (after / before - 1.0), abs=1.0)
    assert (catalog / "trend.md").read_text().count("![") == 4 and (catalog / "trend.rrd").stat().st_size > 0
    assert len(result.alarms) == 1
