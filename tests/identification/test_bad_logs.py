"""Logs identify cannot use: one clear line, exit 2, nothing written (table-driven)."""

import re
import subprocess
import sys

import numpy as np
import pytest

from .conftest import write_foreign_log

CLI = [sys.executable, "-m", "axisflow", "identify"]


def _gap(t_ns, pos, vel, eff):
    keep = np.ones(t_ns.size, bool)
    keep[5000:5012] = False  # 12 ms missing
    return t_ns[keep], pos[keep], vel[keep], eff[keep]


def _backwards(t_ns, pos, vel, eff):
    t_ns = t_ns.copy()
    t_ns[7000] = t_ns[6990]
    return t_ns, pos, vel, eff


def _nan(fraction):
    def spoil(t_ns, pos, vel, eff):
        eff = eff.copy()
        eff[np.random.default_rng(0).random(t_ns.size) < fraction, 1] = np.nan
        return t_ns, pos, vel, eff

    return spoil


def _still(t_ns, pos, vel, eff):
    return t_ns, np.full_like(pos, 100.0), np.zeros_like(vel), eff * 0.0


def _short(t_ns, pos, vel, eff):
    return t_ns[:1500], pos[:1500], vel[:1500], eff[:1500]


TOPIC = ["--topic", "/robot/joint_states"]
JOINT = ["--joint", "slider_motor", "--joint-kind", "motor"]
FOREIGN = [*TOPIC, *JOINT]
CASES = {  # how to spoil the log, the command's arguments, what the error says
    "missing-topic": (None, ["--topic", "/nope", *JOINT], r"/nope.*JointState topics.*/robot/joint_states"),
    "missing-joint": (
        None,
        [*TOPIC, "--joint", "wrist", "--joint-kind", "motor"],
        r"no joint 'wrist'.*base_yaw",
    ),
    "unknown-joint-kind": (
        None,
        [*TOPIC, "--joint", "base_yaw"],
        r"'base_yaw' is neither 'motor' nor 'carriage'",
    ),
    "gap": (_gap, FOREIGN, r"a gap in the time stamps: 13.000 ms between samples 4999 and 5000"),
    "backwards": (_backwards, FOREIGN, r"time stamps do not increase: sample 7000"),
    "too-many-nan": (_nan(0.05), FOREIGN, r"'slider_motor' have non-finite values \(more than 1%\)"),
    "no-motion": (_still, FOREIGN, r"the axis does not move in this log \(peak speed 0 m/s"),
    "too-short": (_short, FOREIGN, r"1.499 s of joint 'slider_motor' is too short \(at least 2 s\)"),
    "bad-fit-names": (
        None,
        [*FOREIGN, "--fit", "a1,a9"],
        r"--fit a1,a9: unknown a9; choose from M_eq, a1, a2",
    ),
    "bad-holdout": (None, [*FOREIGN, "--holdout", "1.5"], r"holdout = 1.5 must be a fraction in \[0, 0.9\)"),
}


@pytest.mark.parametrize("case", CASES)
def test_an_unusable_log_is_one_line_exit_2_and_nothing_written(case, tmp_path):
    edit, args, match = CASES[case]
    log = write_foreign_log(tmp_path / "log.mcap", 20.0, edit=edit)
    out = tmp_path / "refit"
    proc = subprocess.run(
        [*CLI, str(log), *args, "--out", str(out)], capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr and len(proc.stderr.strip().splitlines()) == 1, proc.stderr
    assert re.search(match, proc.stderr), proc.stderr
    assert not out.exists()


def test_a_few_nan_samples_are_dropped_and_counted(tmp_path):
    from axisflow.identification.refit import IdentifySettings, identify
    from axisflow.identification.report import report_json

    from .conftest import NOMINAL, PLANT

    log = write_foreign_log(tmp_path / "log.mcap", 30.0, edit=_nan(0.002))
    settings = IdentifySettings(topic="/robot/joint_states", joint="slider_motor", joint_kind="motor")
    report = report_json(identify([log], NOMINAL, settings))
    assert 40 < report["samples"]["non_finite"] < 80
    assert report["parameters"]["a1"]["value"] == pytest.approx(PLANT.a1, rel=0.02)


@pytest.mark.parametrize(
    ("content", "match"),
    [
        (None, r"recording .*missing.mcap does not exist"),
        (b"not an mcap file at all", r"is not an MCAP file"),
    ],
)
def test_a_missing_or_foreign_file(tmp_path, content, match):
    path = tmp_path / "missing.mcap"
    if content is not None:
        path.write_bytes(content)
    proc = subprocess.run(
        [*CLI, str(path), "--out", str(tmp_path / "o")], capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 2 and re.search(match, proc.stderr), proc.stderr
    assert not (tmp_path / "o").exists()
