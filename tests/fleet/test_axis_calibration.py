"""An axis's calibration: which windows it takes, how its key enters the window keys, its table on
disk; and a fits table of the older method read as none."""

from __future__ import annotations

import dataclasses
import math

import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from axisflow.fleet.axis_calibration import (
    AxisCalibration,
    calibrated_windows,
    plan_calibrations,
    read_calibrations,
    write_calibrations,
)
from axisflow.fleet.catalog import FORMAT_KEY
from axisflow.fleet.errors import FleetError
from axisflow.fleet.fits import FITS_FILE, read_fits
from axisflow.fleet.simulate import default_nominal
from axisflow.fleet.window_fit import FitSettings
from axisflow.fleet.windows import NS_PER_DAY, WindowSpec, plan_windows

from .test_windows import DAY0, _entry

SETTINGS = FitSettings(default_nominal())


def _windows(days: int, axis: str = "a0", still: tuple[int, ...] = (), digest: str = "h"):
    entries = []
    for d in range(days):
        e = _entry(f"/{axis}/{d}", DAY0 + d * NS_PER_DAY, 30, axis=axis, digest=f"{digest}{d}")
        if d in still:
            e = dataclasses.replace(e, moving_s=0.0, reversals=0)
        entries.append(e)
    return plan_windows(entries, WindowSpec.parse("day"), SETTINGS.method())


def test_an_axis_is_calibrated_on_its_first_windows_that_can_be_identified():
    windows = _windows(8, still=(1,)) + _windows(2, axis="a1")
    plans = plan_calibrations(windows, SETTINGS, count=5)
    assert [w.start_ns for w in plans["a0"].windows] == [DAY0 + d * NS_PER_DAY for d in (0, 2, 3, 4, 5)]
    assert len(plans["a1"].windows) == 2  # all it has, until it has more
    assert plans["a0"].key != plans["a1"].key


def test_the_calibration_keys_the_windows_a_later_window_changes_nothing_an_earlier_one_everything():
    keyed, plans = calibrated_windows(_windows(6), SETTINGS)
    assert all(w.key != raw.key for w, raw in zip(keyed, _windows(6), strict=True))
    longer, _ = calibrated_windows(_windows(7), SETTINGS)
    assert [w.key for w in longer[:6]] == [w.key for w in keyed]
    first_changed = _windows(6)
    first_changed[0] = dataclasses.replace(first_changed[0], key="another log")
    changed, changed_plans = calibrated_windows(first_changed, SETTINGS)
    assert changed_plans["a0"].key != plans["a0"].key
    assert all(a.key != b.key for a, b in zip(changed[1:], keyed[1:], strict=True))


def _calibration(axis: str, delay_s: float) -> AxisCalibration:
    return AxisCalibration(
        axis=axis,
        key=f"k{axis}",
        windows=5,
        start_ns=DAY0,
        end_ns=DAY0 + 5 * NS_PER_DAY,
        torque_delay_s=delay_s,
        torque_delay_std_s=2e-4,
        cogging_orders="24,48",
        M_eq_sys_std=0.09,
        a1_sys_std=0.01,
        a2_sys_std=0.4,
        a3_sys_std=0.05,
        a4_sys_std=0.005,
        coulomb_n_sys_std=0.03,
        status="ok" if math.isfinite(delay_s) else "failed",
        reason="" if math.isfinite(delay_s) else "the SQP did not converge",
        wall_s=3.2,
    )


def test_the_calibrations_table_round_trips(tmp_path):
    records = [_calibration("a1", 1.1e-3), _calibration("a0", math.nan)]
    write_calibrations(tmp_path, records)
    back = read_calibrations(tmp_path)
    assert [c.axis for c in back] == ["a0", "a1"]
    assert back[1] == records[0] and back[1].orders == (24, 48) and back[1].delay_s == 1.1e-3
    assert back[0].delay_s is None and not back[0].ok and math.isnan(back[0].torque_delay_s)
    assert back[1].systematic["coulomb_n"] == 0.03


def test_a_fits_table_of_the_older_method_counts_as_none_for_a_re_run_and_is_refused_otherwise(tmp_path):
    table = pa.table(
        {"key": ["x"]},
        schema=pa.schema([("key", pa.string())], metadata={FORMAT_KEY: b"axisflow.fleet.fits/1"}),
    )
    pq.write_table(table, tmp_path / FITS_FILE)
    assert read_fits(tmp_path, missing_ok=True) == []
    with pytest.raises(FleetError, match="fits/1"):
        read_fits(tmp_path)
