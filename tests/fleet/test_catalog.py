"""The catalog: its record through Parquet and back, the motion figures against closed forms, the
incremental scan, and a file that cannot be read among good ones."""

from __future__ import annotations

import math
import os
import warnings

import numpy as np
import pyarrow.parquet as pq
import pytest
from axisflow.acquisition.logs.synthetic_log import SyntheticLogSpec, write_synthetic_log
from axisflow.fleet.catalog import (
    CATALOG_FILE,
    CatalogEntry,
    IndexSettings,
    index_logs,
    motion_summary,
    read_catalog,
    write_catalog,
)
from axisflow.fleet.errors import FleetError, FleetWarning
from axisflow.model import default_params

NOMINAL = default_params()


def _entry(**changes) -> CatalogEntry:
    base = dict(
        path="/logs/a0/x.mcap",
        axis="a0",
        topic="/axisflow/a0/state",
        joint="motor",
        joint_kind="motor",
        size_bytes=123,
        mtime_ns=1_700_000_000_123_456_789,
        content_hash="00ff" * 8,
        start_ns=1_767_600_000_000_000_001,
        end_ns=1_767_600_035_000_000_000,
        samples=35_000,
        holes=3,
        missing=4,
        speed_low_m_s=0.008,
        speed_high_m_s=0.5,
        reversals=30,
        moving_s=25.5,
        status="ok",
        reason="",
    )
    return CatalogEntry(**{**base, **changes})


def test_an_entry_goes_through_parquet_and_back_unchanged(tmp_path):
    rows = [
        _entry(),
        _entry(path="/logs/b.mcap", axis="b", status="unreadable", reason="not MCAP", speed_low_m_s=math.nan),
    ]
    write_catalog(tmp_path, rows)
    back = read_catalog(tmp_path)
    assert back[0] == rows[0]
    assert back[1].reason == "not MCAP" and math.isnan(back[1].speed_low_m_s)
    table = pq.read_table(tmp_path / CATALOG_FILE)  # plain Parquet: any reader sees the same columns
    assert table.column("start_ns").to_pylist() == [r.start_ns for r in rows]


@pytest.mark.parametrize("content", [b"", b"PAR1 not really", b"hello\n"])
def test_a_folder_whose_catalog_is_not_one_is_refused_naming_it(tmp_path, content):
    (tmp_path / CATALOG_FILE).write_bytes(content)
    with pytest.raises(FleetError, match="is not a fleet catalog"):
        read_catalog(tmp_path)


def test_another_parquet_file_is_not_a_catalog(tmp_path):
    import pyarrow as pa

    pq.write_table(pa.table({"x": [1, 2]}), tmp_path / CATALOG_FILE)
    with pytest.raises(FleetError, match="no axisflow format mark"):
        read_catalog(tmp_path)


def test_the_motion_of_a_sine_is_counted_as_its_closed_form():
    # x = A·sin(2π f t) for 10 s at 1 kHz: speed A·2πf·|cos|, 2·f·10 reversals
    t = np.arange(10_000) * 1e-3
    amplitude, f = 0.1, 0.5
    x = amplitude * np.sin(2 * math.pi * f * t)
    stamps = (1_000_000_000_000 + t * 1e9).astype(np.int64)
    low, high, reversals, moving_s = motion_summary(stamps, x)
    peak = amplitude * 2 * math.pi * f
    assert high == pytest.approx(peak, rel=0.01)
    assert reversals == 2 * f * 10  # v ∝ cos(2π f t) changes sign at t = (k + ½)/(2f)
    # |v| > 5 mm/s except within arcsin(0.005/peak)/ω of each reversal
    still = 2 * f * 10 * 2 * math.asin(0.005 / peak) / (2 * math.pi * f)
    assert moving_s == pytest.approx(10.0 - still, abs=0.05)
    assert 0.0 < low < 0.1 * peak


def test_a_still_log_has_no_motion():
    stamps = np.arange(5000, dtype=np.int64) * 1_000_000
    assert motion_summary(stamps, np.full(5000, 0.4))[2:] == (0, 0.0)


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    d = tmp_path_factory.mktemp("logs")
    for k, axis in enumerate(("a0", "a1")):
        (d / axis).mkdir()
        write_synthetic_log(d / axis / "day1.mcap", SyntheticLogSpec(duration_s=4.0, axis=axis, seed=k))
    return d


def test_a_second_scan_reads_only_what_changed(logs, tmp_path):
    first = index_logs([logs], tmp_path / "cat", NOMINAL)
    assert (first.read, first.unchanged) == (2, 0)
    assert sorted(e.axis for e in first.entries) == ["a0", "a1"]
    e = next(e for e in first.entries if e.axis == "a0")
    assert e.samples == 4000 and e.holes == 0 and e.reversals > 2 and e.moving_s > 3.0
    again = index_logs([logs], tmp_path / "cat", NOMINAL)
    assert (again.read, again.unchanged) == (0, 2)
    assert set(again.entries) == set(first.entries)
    st = (logs / "a1" / "day1.mcap").stat()
    os.utime(logs / "a1" / "day1.mcap", ns=(st.st_atime_ns, st.st_mtime_ns + 1_000_000))
    touched = index_logs([logs], tmp_path / "cat", NOMINAL)
    assert (touched.read, touched.unchanged) == (1, 1)
    a1 = [e for e in touched.entries if e.axis == "a1"]
    assert (
        len(a1) == 1 and a1[0].content_hash == next(e for e in first.entries if e.axis == "a1").content_hash
    )


def test_an_unreadable_log_is_a_row_with_its_reason_and_the_others_are_indexed(logs, tmp_path):
    bad = tmp_path / "logs" / "a2"
    bad.mkdir(parents=True)
    (bad / "day1.mcap").write_bytes(b"this is no MCAP file")
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        result = index_logs([logs, tmp_path / "logs"], tmp_path / "cat", NOMINAL)
    assert result.unreadable == 1 and len(result.entries) == 3
    (row,) = [e for e in result.entries if not e.ok]
    assert (
        row.status == "unreadable"
        and "is not an MCAP file" in row.reason
        and row.path.endswith("a2/day1.mcap")
    )
    assert [w for w in seen if issubclass(w.category, FleetWarning)]


def test_a_foreign_log_is_named_by_its_folder_or_the_pattern(logs, tmp_path):
    by_folder = IndexSettings(topic="/axisflow/a0/state")
    assert index_logs([logs / "a0"], tmp_path / "c1", NOMINAL, by_folder).entries[0].axis == "a0"
    pattern = IndexSettings(axis_pattern=r"/(?P<axis>a\d)/day", topic="/axisflow/a1/state")
    assert index_logs([logs / "a1"], tmp_path / "c2", NOMINAL, pattern).entries[0].axis == "a1"
