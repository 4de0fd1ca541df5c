"""One window identified by the fleet's adapter, without Dask: the row of a fit, of a window with too
little motion and of one that fails; the Coulomb friction's σ against its closed forms."""

from __future__ import annotations

import math

import pytest
from axisflow.acquisition.drives.plant import load_plant
from axisflow.acquisition.logs.synthetic_log import SyntheticLogSpec, write_synthetic_log
from axisflow.fleet.catalog import IndexSettings, index_file
from axisflow.fleet.window_fit import COULOMB_SPEED_M_S, FitSettings, coulomb_at_speed, fit_window_row
from axisflow.fleet.windows import WindowSpec, plan_windows
from axisflow.identification.refit import IdentifySettings, identify
from axisflow.model import default_params, forward_friction

NOMINAL = default_params()
TRUE = load_plant(None, NOMINAL).axis  # the default plant's true axis (scaled friction and inertia)


@pytest.fixture(scope="module")
def log(tmp_path_factory):
    path = tmp_path_factory.mktemp("wf") / "a0.mcap"
    write_synthetic_log(path, SyntheticLogSpec(duration_s=20.0, params=NOMINAL, true_params=TRUE))
    return path


@pytest.mark.slow
def test_a_window_s_row_has_the_fit_its_sigma_and_the_held_out_error(log):
    settings = FitSettings(NOMINAL)
    (window,) = plan_windows(
        index_file(log, NOMINAL, IndexSettings()), WindowSpec.parse("day"), settings.method()
    )
    row = fit_window_row(window, settings).row
    assert row.status == "ok" and row.reason == "" and row.samples == 20_000
    truth = float(forward_friction(COULOMB_SPEED_M_S, TRUE))
    assert abs(row.coulomb_n - truth) < 5 * row.coulomb_std_n
    assert abs(row.a2 - TRUE.a2) < 5 * row.a2_std
    assert row.heldout_rms > 0 and row.fit_rms > 0 and row.effort_unit == "N·m"
    assert row.energy_per_m_j > 0


@pytest.mark.slow
def test_the_coulomb_sigma_is_the_parameters_sigma_through_the_law(log):
    topic = "/axisflow/a0/state"
    only_a1 = identify([log], NOMINAL, IdentifySettings(topic=topic, fit=("a1",)))
    force, std = coulomb_at_speed(only_a1)
    assert std == pytest.approx(only_a1.uncertainty.std["a1"], rel=1e-12)  # ∂F/∂a1 = 1
    two = identify([log], NOMINAL, IdentifySettings(topic=topic, fit=("a1", "a2")))
    s, rho = two.uncertainty.std, two.uncertainty.correlation[0, 1]
    v = COULOMB_SPEED_M_S
    expected = math.sqrt(s["a1"] ** 2 + (v * s["a2"]) ** 2 + 2 * v * rho * s["a1"] * s["a2"])
    assert coulomb_at_speed(two)[1] == pytest.approx(expected, rel=1e-9)
    assert force == pytest.approx(float(forward_friction(v, only_a1.fit.values)))


def test_a_window_without_motion_is_a_row_saying_so_without_a_fit(log):
    settings = FitSettings(NOMINAL)
    (entry,) = index_file(log, NOMINAL, IndexSettings())
    still = entry.__class__(**{**entry.__dict__, "moving_s": 0.0, "reversals": 0, "speed_high_m_s": 0.0})
    (window,) = plan_windows([still], WindowSpec.parse("day"), settings.method())
    row = fit_window_row(window, settings).row
    assert row.status == "too_little_motion" and "moving 0.0 s < 5 s" in row.reason
    assert math.isnan(row.coulomb_n)


def test_a_window_whose_log_is_gone_is_a_failed_row_with_the_reason(log, tmp_path):
    settings = FitSettings(NOMINAL)
    (entry,) = index_file(log, NOMINAL, IndexSettings())
    gone = entry.__class__(**{**entry.__dict__, "path": str(tmp_path / "gone.mcap")})
    (window,) = plan_windows([gone], WindowSpec.parse("day"), settings.method())
    row = fit_window_row(window, settings).row
    assert row.status == "failed" and "gone.mcap" in row.reason
