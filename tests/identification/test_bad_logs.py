"""Logs identify cannot use: one clear line, exit 2, nothing written (table-driven)."""

import json
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


def _mostly_missing(t_ns, pos, vel, eff):
    keep = np.ones(t_ns.size, bool)
    keep[2000:8000:2] = False  # every other sample of 6 s lost: 3000 of 20 000 (15 %) …
    keep[12000:15000] = False  # … and 3 s in one piece: 6000 (30 %) in all
    return t_ns[keep], pos[keep], vel[keep], eff[keep]


def _off_grid(t_ns, pos, vel, eff):
    t_ns = t_ns.copy()
    t_ns[10000:] = t_ns[10000] + (t_ns[10000:] - t_ns[10000]) * 13 // 10  # from 10 s on, 1.3 ms steps
    return t_ns, pos, vel, eff


def _doubled(t_ns, pos, vel, eff):
    t_ns = t_ns.copy()
    t_ns[4000] = t_ns[3999] + 200_000  # two samples 0.2 ms apart
    return t_ns, pos, vel, eff


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
    "mostly-missing": (
        _mostly_missing,
        FOREIGN,
        r"6000 of 20000 samples missing \(30.00%\) in 3001 holes, the longest 3000 ms: more than 20%",
    ),
    "off-grid": (
        _off_grid,
        FOREIGN,
        r"do not sit on a sampling grid: sample \d+ at [\d.]+ s is [\d.]+ ms from it, more than half",
    ),
    "doubled": (
        _doubled,
        FOREIGN,
        r"samples 3999 and 4000 are 0.200 ms apart, less than half the log's step",
    ),
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
    "doubled-inside-the-window": (  # samples named in the whole log
        _doubled,
        [*FOREIGN, "--start", "2", "--end", "8"],
        r"samples 3999 and 4000 are 0.200 ms apart",
    ),
    "empty-window": (
        None,
        [*FOREIGN, "--start", "30"],
        r"no sample in the window from 30 s to its end after the first sample: the log spans 0.000 s to 19",
    ),
    "reversed-window": (
        None,
        [*FOREIGN, "--start", "5", "--end", "2"],
        r"window end = 2 s must be after its start = 5 s",
    ),
}


@pytest.mark.parametrize("case", CASES)
@pytest.mark.slow
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


@pytest.mark.slow
def test_a_gap_is_fitted_around_with_a_window(tmp_path):
    from .conftest import PLANT

    reports = []
    for name, edit in (("whole", None), ("gapped", _gap)):  # the gap is in the first 5.1 s
        log = write_foreign_log(tmp_path / f"{name}.mcap", 30.0, edit=edit)
        out = tmp_path / f"refit-{name}"
        args = [*CLI, str(log), *FOREIGN, "--start", "5.1", "--json", "--out", str(out)]
        proc = subprocess.run(args, capture_output=True, text=True, timeout=120)
        assert proc.returncode == 0, proc.stderr
        reports.append(json.loads(proc.stdout))
    whole, gapped = reports
    assert gapped["log"]["window"] == {"start_s": 5.1, "end_s": None, "origin_ns": None}
    assert gapped["log"]["duration_s"] == pytest.approx(29.999 - 5.1, abs=1e-6)  # the last sample at 29.999 s
    assert "from 5.1 s to the end after each log's first sample" in (out / "report.md").read_text()
    for name, p in gapped["parameters"].items():  # what was cut away makes no difference
        assert p["value"] == pytest.approx(whole["parameters"][name]["value"], rel=1e-9), name
    a1 = gapped["parameters"]["a1"]
    assert abs(a1["value"] - PLANT.a1) < 3 * a1["std"]


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
