"""The torque/position offset: a log with a known delay gives it back within a sample period (and says
it resolved it); a log that cannot tell says so and fits with none."""

import pytest
from axisflow.identification.refit import IdentifySettings, identify
from axisflow.identification.report import report_json

from .conftest import NOMINAL, PLANT, brisk_motion, write_foreign_log

SETTINGS = IdentifySettings(topic="/robot/joint_states", joint="slider_motor", joint_kind="motor")


@pytest.mark.parametrize("delay_s", [0.0, 0.0005, 0.002])
def test_a_known_delay_is_found_within_a_sample_period(tmp_path, delay_s):
    path = write_foreign_log(tmp_path / "log.mcap", 30.0, delay_s=delay_s, kinematics=brisk_motion)
    ident = identify([path], NOMINAL, SETTINGS)
    assert ident.delay is not None and ident.delay.resolvable, ident.delay
    assert ident.delay_s == pytest.approx(delay_s, abs=0.25e-3)  # a quarter of the 1 ms period
    assert abs(ident.delay.estimate_s - delay_s) < 4 * ident.delay.std_s + 2e-5
    assert ident.fit.values.M_eq == pytest.approx(PLANT.M_eq, rel=2e-3)


def test_a_log_that_cannot_tell_the_delay_says_so_and_fits_with_none(tmp_path):
    """Slow motion and noisy torque: the offset's σ exceeds a third of a sample period."""
    path = write_foreign_log(tmp_path / "slow.mcap", 30.0, noise_nm=0.05, delay_s=0.0005)
    ident = identify([path], NOMINAL, SETTINGS)
    assert ident.delay is not None and not ident.delay.resolvable
    assert ident.delay_s == 0.0 and 3 * ident.delay.std_s > 1e-3
    report = report_json(ident)
    assert report["torque_delay_s"]["resolvable"] is False
    assert any(w.startswith("the torque/position offset is not resolvable") for w in report["warnings"])


def test_a_given_delay_is_used_as_it_is(tmp_path):
    path = write_foreign_log(tmp_path / "log.mcap", 20.0)
    ident = identify([path], NOMINAL, IdentifySettings(**{**SETTINGS.__dict__, "torque_delay_s": 3e-4}))
    assert ident.delay is None and ident.delay_s == 3e-4
    assert report_json(ident)["torque_delay_s"] == {
        "value": 3e-4, "estimated": False, "estimate": None, "std": None, "resolvable": None,
        "period": pytest.approx(1e-3),
    }  # fmt: skip
