"""identify meets users where their logs are: a recording of one JointState topic of one joint needs
no names; a scope's CSV or a MATLAB file is read through the importer, with the same result as
importing it first (one path for the data); the plant's parameters come back; several topics or joints
are refused with their list."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from axisflow.model import cart_force

from axisflow.cli import main

from ..acquisition.foreign.foreign_files import write_csv, write_mat_v5, write_mat_v73
from .conftest import PLANT, brisk_motion, write_foreign_log

GTAU = 35.15
"""the amplifier's gain [N/V]: force = GTAU × the logged voltage, as in the EMPS logs"""
FAST = ("--cogging", "none", "--stroke-terms", "0", "--json")
CSV_MAP = ("--time", "Zeit", "--position", "Lage", "--effort", "Spannung", "--effort-scale", str(GTAU))


@pytest.fixture(scope="module")
def axis_log():
    """20 s of the PLANT's carriage at 1 kHz: position [m] (50 nm steps) and its force as a voltage."""
    t = np.arange(0.0, 20.0, 1e-3)
    x, v, a = brisk_motion(t)
    force = cart_force(v, a, PLANT) + np.random.default_rng(3).normal(0.0, 2.0, t.size)
    return t, np.round(x / 50e-9) * 50e-9, force / GTAU


def _fit(capsys, *args):
    assert main(["identify", *args, *FAST]) == 0, capsys.readouterr().err
    report = json.loads(capsys.readouterr().out)
    return report, {name: p["value"] for name, p in report["parameters"].items()}


def _close_to_the_plant(fitted):
    assert fitted["M_eq"] == pytest.approx(PLANT.M_eq, rel=0.01)
    assert fitted["a2"] == pytest.approx(PLANT.a2, rel=0.05)
    assert fitted["a1"] + fitted["a3"] * math.pi / 2 == pytest.approx(
        PLANT.a1 + PLANT.a3 * math.pi / 2, rel=0.02
    )


@pytest.mark.slow
def test_a_scope_csv_is_fitted_directly_as_if_imported_first(axis_log, tmp_path, capsys):
    t, x, volts = axis_log
    csv = write_csv(
        tmp_path / "scope.csv", ["Zeit", "Lage", "Spannung"], [t, x * 1e3, volts], units=["s", "mm", "V"]
    )
    direct, fitted = _fit(capsys, str(csv), *CSV_MAP, "--out", str(tmp_path / "direct"))
    _close_to_the_plant(fitted)
    assert direct["log"]["paths"] == [str(csv)]  # the report names the user's file
    assert main(["import", str(csv), *CSV_MAP, "--out", str(tmp_path / "scope.mcap")]) == 0
    capsys.readouterr()
    imported, _ = _fit(capsys, str(tmp_path / "scope.mcap"), "--out", str(tmp_path / "imported"))
    assert imported["parameters"] == direct["parameters"]  # the same samples, the same fit


@pytest.mark.slow
@pytest.mark.parametrize("writer", [write_mat_v5, write_mat_v73], ids=["v5", "v7.3"])
def test_an_emps_style_mat_file_is_fitted(axis_log, tmp_path, capsys, writer):
    t, x, volts = axis_log
    mat = writer(tmp_path / "emps.mat", {"t": t, "qm": x, "vir": volts, "gtau": GTAU})
    emps = (
        "--time",
        "t",
        "--position",
        "qm",
        "--position-unit",
        "m",
        "--effort",
        "vir",
        "--effort-unit",
        "V",
    )
    _report, fitted = _fit(
        capsys, str(mat), *emps, "--effort-scale", "gtau", "--out", str(tmp_path / "refit")
    )
    _close_to_the_plant(fitted)


@pytest.mark.slow
def test_one_topic_of_one_joint_needs_no_names(tmp_path, capsys):
    # a foreign recording: its only JointState topic and joint named as we never would
    log = write_foreign_log(
        tmp_path / "bag.mcap",
        20.0,
        topic="/rig/js",
        joints=("drive",),
        slider=0,
        kinematics=brisk_motion,
        others=False,
    )
    args = (str(log), "--joint-kind", "motor", "--out", str(tmp_path / "refit"))
    report, fitted = _fit(capsys, *args)
    assert (report["log"]["topic"], report["log"]["joint"]) == ("/rig/js", "drive")
    _close_to_the_plant(fitted)


def test_several_joint_state_topics_or_joints_are_refused_with_their_list(foreign_log, tmp_path, capsys):
    assert main(["identify", str(foreign_log), "--out", str(tmp_path / "a")]) == 2
    err = capsys.readouterr().err
    assert (
        "holds 2 JointState topics (/arm/joint_states, /robot/joint_states): choose one with --topic" in err
    )
    assert (
        main(["identify", str(foreign_log), "--topic", "/robot/joint_states", "--out", str(tmp_path / "b")])
        == 2
    )
    err = capsys.readouterr().err
    assert (
        "topic /robot/joint_states has 3 joints (base_yaw, slider_motor, gripper): choose one with --joint"
        in err
    )
    assert not (tmp_path / "a").exists() and not (tmp_path / "b").exists()


def test_column_options_on_mcap_logs_are_refused(foreign_log, tmp_path, capsys):
    assert main(["identify", str(foreign_log), "--position", "x", "--out", str(tmp_path / "a")]) == 2
    assert (
        "--position map the columns of .csv, .tsv, .parquet and .mat logs; these logs are MCAP"
        in capsys.readouterr().err
    )
