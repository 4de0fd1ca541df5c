"""A log with a chunk damaged on disk: identify skips it, says so in one line, and fits around the
hole — its samples come back as missing ones, and no fitted sample lies next to it."""

import json
import subprocess
import sys

import numpy as np
import pytest
from axisflow.acquisition import DamagedLogWarning, read_joint_states
from axisflow.identification.preparation import filter_reach_s
from axisflow.identification.refit import IdentifySettings, identify

from .conftest import NOMINAL, PLANT, write_foreign_log

TOPIC = "/robot/joint_states"
SETTINGS = IdentifySettings(topic=TOPIC, joint="slider_motor", joint_kind="motor")


@pytest.fixture(scope="module")
def logs(tmp_path_factory, damage):
    """(whole log, the same with its middle chunk's bytes flipped, that chunk's number from 1)."""
    folder = tmp_path_factory.mktemp("damaged")
    whole = write_foreign_log(folder / "whole.mcap", 40.0)
    middle = len(damage.chunks(whole)) // 2
    damage.damage(whole, folder / "damaged.mcap", middle, "flip")
    return whole, folder / "damaged.mcap", middle + 1


def test_the_hole_becomes_missing_samples_that_are_never_fitted(logs):
    whole, damaged, _chunk = logs
    with pytest.warns(DamagedLogWarning):
        (hole,) = read_joint_states(damaged, TOPIC).holes
        ident = identify([damaged], NOMINAL, SETTINGS)
    reference = identify([whole], NOMINAL, SETTINGS)
    signals, prepared = ident.logs[0].signals, ident.logs[0]
    assert signals.skipped == hole.messages > 500  # the chunk held ~1 s of the topic
    assert signals.dropped == 0  # not counted as non-finite values of the log
    # put back on the drive's grid (its period and phase are fitted: equal to well under a ns)
    assert np.allclose(signals.t_s, reference.logs[0].signals.t_s, rtol=0.0, atol=1e-10)
    missing = np.flatnonzero(~signals.observed)
    assert missing.size == hole.messages and np.all(np.diff(missing) == 1)  # one stretch
    prep = SETTINGS.preparation  # how far the filter carries a hole's filled values
    reach = round(filter_reach_s(prep.cutoff_hz, signals.rate_hz, prep.order) * signals.rate_hz)
    near = slice(missing[0] - reach, missing[-1] + reach + 1)
    assert not prepared.usable[near].any()  # nothing fitted in the hole or next to it
    # beyond the filter's reach the signals are the whole log's; the stationary and saturation
    # decisions taken within it still carry their guard further
    guard = round(prep.guard_s * signals.rate_hz)
    outside = np.ones(signals.t_s.size, bool)
    outside[missing[0] - reach - guard : missing[-1] + reach + guard + 1] = False
    assert np.array_equal(prepared.usable[outside], reference.logs[0].usable[outside])
    for name in ("a1", "a2", "a3", "a4"):
        assert ident.params.to_dict()[name] == pytest.approx(getattr(PLANT, name), rel=0.03), name


def test_identify_says_what_it_skipped_in_one_line_and_goes_on(logs, tmp_path):
    _whole, damaged, chunk = logs
    args = ["--topic", TOPIC, "--joint", "slider_motor", "--joint-kind", "motor", "--json"]
    cli = [sys.executable, "-m", "axisflow", "identify", str(damaged), *args, "--out", str(tmp_path / "o")]
    proc = subprocess.run(cli, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in proc.stderr, proc.stderr
    assert lines[0].startswith(f"axisflow identify: warning: {damaged}: chunk {chunk} at byte ")
    assert "skipped it: " in lines[0] and f"messages of {TOPIC}" in lines[0]
    report = json.loads(proc.stdout)
    assert report["parameters"]["a1"]["value"] == pytest.approx(PLANT.a1, rel=0.03)
    assert sorted(p.name for p in (tmp_path / "o").iterdir()) == [
        "effort.parquet",
        "fit.png",
        "params.toml",
        "report.json",
        "report.md",
    ]
