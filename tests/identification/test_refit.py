"""identify on logs axisflow did not write: other topic and joint names, interleaved topics, a joint of
another kind, holdout; and the refit file drives the planner."""

import json

import numpy as np
import pytest
from axisflow.identification.refit import IdentifySettings, identify
from axisflow.identification.report import params_file, report_json, report_markdown
from axisflow.model import load_params

from .conftest import NOMINAL, PLANT, write_foreign_log

SETTINGS = IdentifySettings(
    topic="/robot/joint_states", joint="slider_motor", joint_kind="motor", torque_delay_s=0.0
)


def test_a_foreign_bag_refits_to_its_plant(foreign_log):
    ident = identify([foreign_log], NOMINAL, SETTINGS)
    truth = {"M_eq": PLANT.M_eq, "a1": PLANT.a1, "a2": PLANT.a2, "a3": PLANT.a3, "a4": PLANT.a4}
    for name in ident.fit.fitted:
        value = ident.fit.values.as_dict()[name]
        assert value == pytest.approx(truth[name], rel=0.01), name
        assert abs(value - truth[name]) < 4 * ident.uncertainty.std[name], name
    assert ident.errors["fit"].rms < 0.005 < ident.errors["fit_nominal"].rms


def test_the_delay_is_estimated_near_zero_for_a_log_without_one(foreign_log):
    ident = identify(
        [foreign_log], NOMINAL, IdentifySettings(**{**SETTINGS.__dict__, "torque_delay_s": None})
    )
    assert abs(ident.delay_s) < 2e-4 and ident.delay_estimated


def test_holdout_validates_on_the_end_of_the_log_and_reports_both_parameter_sets(foreign_log):
    ident = identify([foreign_log], NOMINAL, IdentifySettings(**{**SETTINGS.__dict__, "holdout": 0.25}))
    report = report_json(ident)
    assert report["validation"]["samples"] > 1000 and report["validation"]["rms_nm"] < 0.005
    assert report["validation_nominal"]["rms_nm"] > 5 * report["validation"]["rms_nm"]
    assert "the last 25% of each log" in report["validation_source"]
    assert report["fit"]["samples"] + report["validation"]["samples"] <= report["samples"]["used"]
    keys = {"parameters", "correlation", "condition_number", "fit", "validation", "solver", "timing_s", "log"}
    assert keys <= set(report)
    assert set(report["parameters"]["a1"]) >= {"value", "std", "initial"}
    assert set(report["timing_s"]) == {"read", "prepare", "select", "solve", "judge", "total"}
    assert set(report["log"]) >= {"paths", "topic", "joint", "samples", "duration_s"}
    assert "| a1 [N] |" in report_markdown(json.loads(json.dumps(report)))


def test_a_carriage_joint_reports_newtons(tmp_path):
    def carriage(t_ns, pos, vel, eff):
        k = PLANT.i_r / PLANT.r
        return t_ns, pos / k, vel / k, eff * k  # the same axis measured on the cart: m, m/s, N

    path = write_foreign_log(tmp_path / "cart.mcap", 30.0, joints=("carriage",), slider=0, edit=carriage)
    settings = IdentifySettings(topic="/robot/joint_states", joint="carriage", torque_delay_s=0.0)
    report = report_json(identify([path], NOMINAL, settings))
    assert "rms_n" in report["fit"] and "rms_nm" not in report["fit"]
    assert report["parameters"]["a2"]["value"] == pytest.approx(PLANT.a2, rel=0.01)


def test_the_refit_file_is_a_parameter_file_with_the_refit_values(foreign_log, tmp_path):
    ident = identify([foreign_log], NOMINAL, SETTINGS)
    path = tmp_path / "params.toml"
    path.write_text(params_file(ident))
    loaded = load_params(path)
    assert loaded.M_eq == pytest.approx(ident.fit.values.M_eq, rel=1e-12)
    assert (loaded.a1, loaded.a4) == (ident.fit.values.a1, ident.fit.values.a4)
    assert (loaded.r, loaded.i_r, loaded.tau_max) == (NOMINAL.r, NOMINAL.i_r, NOMINAL.tau_max)


@pytest.mark.parametrize("compression", ["lz4", "none"])
def test_other_compressions_read_the_same(tmp_path, compression, foreign_log):
    path = write_foreign_log(tmp_path / f"{compression}.mcap", compression=compression)
    a = identify([path], NOMINAL, SETTINGS).fit.values.as_dict()
    b = identify([foreign_log], NOMINAL, SETTINGS).fit.values.as_dict()
    assert np.allclose(list(a.values()), list(b.values()), rtol=0, atol=0)


def test_jittery_stamps_are_placed_on_the_drive_grid(tmp_path):
    """A bag whose stamps jitter by ±50 µs (taken when messages were handled, not when sampled) fits
    as well as one with exact stamps: derivatives are taken on the uniform grid."""

    def jitter(t_ns, pos, vel, eff):
        return t_ns + np.random.default_rng(2).integers(-50_000, 50_000, t_ns.size), pos, vel, eff

    path = write_foreign_log(tmp_path / "jitter.mcap", edit=jitter)
    ident = identify([path], NOMINAL, SETTINGS)
    assert 40e-6 < report_json(ident)["log"]["stamp_jitter_s"] < 60e-6
    assert ident.errors["fit"].rms < 0.005
    assert ident.fit.values.M_eq == pytest.approx(PLANT.M_eq, rel=0.01)


def test_a_log_without_velocities_works_from_the_position_alone(tmp_path):
    path = write_foreign_log(tmp_path / "novel.mcap", velocity=False)
    ident = identify([path], NOMINAL, SETTINGS)
    report = report_json(ident)
    assert report["velocity"]["logged"] is False and report["velocity"]["logged_lag_s"] is None
    assert "the log has none" in report_markdown(report)
    with_velocity = identify([write_foreign_log(tmp_path / "vel.mcap")], NOMINAL, SETTINGS)
    for name, value in ident.fit.values.as_dict().items():  # the fit never used the velocity
        assert value == with_velocity.fit.values.as_dict()[name], name


def test_lost_samples_are_counted_and_the_fit_stays_where_the_whole_log_puts_it(tmp_path):
    def lose(t_ns, pos, vel, eff):
        keep = np.random.default_rng(9).random(t_ns.size) > 0.001
        keep[0] = keep[-1] = True
        return t_ns[keep], pos[keep], vel[keep], eff[keep]

    lossy = identify([write_foreign_log(tmp_path / "lossy.mcap", edit=lose)], NOMINAL, SETTINGS)
    whole = identify([write_foreign_log(tmp_path / "whole.mcap")], NOMINAL, SETTINGS)
    report = report_json(lossy)
    expected = int(np.count_nonzero(np.random.default_rng(9).random(40_000) <= 0.001))
    assert report["samples"]["missing"] == expected > 10
    assert report["samples"]["near_holes"] > 0 and report["samples"]["total"] == 40_000
    for name in lossy.fit.fitted:
        value = lossy.fit.values.as_dict()[name]
        assert abs(value - whole.fit.values.as_dict()[name]) < 2 * lossy.uncertainty.std[name], name
        assert value == pytest.approx(getattr(PLANT, name), rel=0.01), name
