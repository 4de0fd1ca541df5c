"""What an accurate model saves against a stale one's plans at equal cycle time (bench adapt's figure)."""

import pytest
from axisflow.acquisition.drives.plant import load_plant
from axisflow.model import default_params
from axisflow.planner.cycle_time import plan_at_omega

from axisflow.savings.study import equal_time_saving

MOVES = [(0.1, 0.62), (0.62, 0.55), (0.55, 0.02), (0.02, 0.3), (0.3, 0.79)]


@pytest.mark.slow
def test_the_accurate_models_plans_cost_no_more_at_the_stale_plans_cycle_time():
    stale_params = default_params()
    accurate = load_plant(None, stale_params).axis  # the simulated plant's truth: more Coulomb, less viscous
    stale = plan_at_omega(MOVES, "poly5", 0.9, stale_params)
    got = equal_time_saving(MOVES, "poly5", [r.duration_s for r in stale.results], accurate)
    assert got["match_status"] == "matched"
    assert got["cycle_time_s"] == pytest.approx(stale.total_time_s, rel=1e-12)
    assert got["saving_pct"] > 0.0
    # judged by the stale model itself, its own ω = 0.9 plans are already the optimum: nothing to save
    same = equal_time_saving(MOVES, "poly5", [r.duration_s for r in stale.results], stale_params)
    assert same["omega"] == pytest.approx(0.9, abs=1e-9)
    assert same["saving_pct"] == pytest.approx(0.0, abs=1e-9)
