"""The fleet end to end on a real Dask LocalCluster (two worker processes on 127.0.0.1): a tiny
fleet simulated on it, indexed with an unreadable log among the good ones, identified on it, done
again with nothing new, and the wearing axis alarmed — the only alarm."""

from __future__ import annotations

import json
import warnings

import pytest
from axisflow.fleet.catalog import index_logs
from axisflow.fleet.cluster import fleet_client
from axisflow.fleet.fits import read_fits
from axisflow.fleet.job import identify_windows, pending
from axisflow.fleet.simulate import FleetSpec, WearSpec, default_nominal, simulate_fleet
from axisflow.fleet.trend import DetectorSettings
from axisflow.fleet.trend_job import trend_fleet
from axisflow.fleet.window_fit import COULOMB_SPEED_M_S, FitSettings
from axisflow.fleet.windows import WindowSpec, plan_windows
from axisflow.model import forward_friction

NOMINAL = default_nominal()
SPEC = FleetSpec(axes=3, days=6, wear=(WearSpec("a1", 3, 25),), bursts=((0.15, 0.5), (0.3, 0.35)))


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
        kept, todo = pending(plan_windows(again.entries, WindowSpec.parse("day"), settings.method()), catalog)
        assert todo == [] and {r.key for r in kept} == {r.key for r in read_fits(catalog)}
    result = trend_fleet(catalog, DetectorSettings(baseline_windows=3))
    alarms = json.loads((catalog / "alarms.json").read_text())
    assert [(a["axis"], a["parameter"]) for a in alarms] == [("a1", "coulomb_n")]
    assert alarms[0]["onset"] == "2026-01-08T00:00:00Z"  # day 3
    # a1 and a3 up 25 %: the friction at 0.2 m/s by less (its viscous part does not wear)
    before, after = (forward_friction(COULOMB_SPEED_M_S, fleet.truth.params_on("a1", d)) for d in (2, 3))
    assert alarms[0]["change_pct"] == pytest.approx(100.0 * (after / before - 1.0), abs=1.0)
    assert (catalog / "trend.md").read_text().count("![") == 4 and (catalog / "trend.rrd").stat().st_size > 0
    assert len(result.alarms) == 1
