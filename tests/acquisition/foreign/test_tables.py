"""Reading foreign files into tables: what a scope's CSV export holds (delimiters, decimal comma,
header, units and metadata rows, comments), Parquet, MATLAB v5 and v7.3; the refusals name the line,
the column or the variable."""

from __future__ import annotations

import numpy as np
import pytest
from axisflow.acquisition.foreign import CsvOptions, ForeignLogError, read_table

from .foreign_files import write_csv, write_mat_v5, write_mat_v73, write_parquet

T = np.arange(5) * 0.001
X = np.array([0.5, 0.25, -1.5e-3, 2.0, 7.125])


@pytest.mark.parametrize(
    ("delimiter", "decimal"), [(";", ","), ("\t", ","), (",", "."), (" ", "."), ("|", "."), (";", ".")]
)
def test_the_delimiter_and_decimal_mark_are_found_from_the_data(tmp_path, delimiter, decimal):
    path = write_csv(tmp_path / "s.csv", ["t", "x"], [T, X], delimiter=delimiter, decimal=decimal)
    table = read_table(path)
    assert list(table.columns) == ["t", "x"]
    assert np.array_equal(table.columns["x"], X)
    assert np.array_equal(table.columns["t"], T)


def test_a_scope_export_with_comments_metadata_and_a_units_row(tmp_path):
    preamble = ("# exported by a drive scope", "Device;X20 servo", "Sample time;1;ms", "", "// channels:")
    path = write_csv(
        tmp_path / "scope.csv",
        ["Time", "Position", "Torque"],
        [T, X, -X],
        units=["[s]", "mm", "Nm"],
        preamble=preamble,
    )
    table = read_table(path)
    assert table.units == {"Time": "s", "Position": "mm", "Torque": "Nm"}
    assert np.array_equal(table.columns["Torque"], -X)
    assert table.row_name(0) == "line 8"  # five preamble lines, header, units: the data start at line 8


def test_units_in_the_header_and_columns_by_name_or_number(tmp_path):
    path = write_csv(tmp_path / "h.csv", ["t [ms]", "Position (mm)"], [np.arange(5), X], decimal=".")
    table = read_table(path)
    assert table.units == {"t [ms]": "ms", "Position (mm)": "mm"}
    assert table.columns["t [ms]"].dtype == np.int64  # integers stay exact
    assert table.column("position", "position")[0] == "Position (mm)"  # bare and any case
    assert table.column("2", "position")[0] == "Position (mm)"


def test_without_a_header_the_columns_are_numbered(tmp_path):
    table = read_table(write_csv(tmp_path / "n.csv", None, [T, X]))
    assert list(table.columns) == ["1", "2"]


def test_given_options_win_over_the_guess(tmp_path):
    path = write_csv(tmp_path / "g.csv", ["a", "b"], [T, X], delimiter=";", decimal=".")
    assert np.array_equal(read_table(path, csv=CsvOptions(delimiter=";")).columns["b"], X)
    with pytest.raises(ForeignLogError, match=r"does not split at ','"):
        read_table(path, csv=CsvOptions(delimiter=","))


@pytest.mark.parametrize(
    ("text", "says"),
    [
        ("t;x\n0;1\n0,001;oops\n0,002;3\n", "line 3, column 2: 'oops' is not a number"),
        ("t;x\n0;1\n1;2;3\n2;3\n", "line 3 has 3 fields, the data lines 2"),
        ("# only a comment\n\n", "holds no data lines"),
    ],
)
def test_a_bad_csv_line_is_named(tmp_path, text, says):
    (tmp_path / "bad.csv").write_text(text)
    with pytest.raises(ForeignLogError, match=says):
        read_table(tmp_path / "bad.csv")


def test_a_missing_column_lists_the_columns_there_are(tmp_path):
    table = read_table(write_csv(tmp_path / "m.csv", ["t", "x"], [T, X]))
    with pytest.raises(ForeignLogError, match=r"has no effort column 'F'; its columns: t, x"):
        table.column("F", "effort")


def test_parquet_columns_and_time_stamps(tmp_path):
    stamps = np.array([1_700_000_000_000_000_123 + k for k in range(5)], dtype="datetime64[ns]")
    path = write_parquet(tmp_path / "p.parquet", {"stamp": stamps, "x": X, "n": np.arange(5)})
    table = read_table(path)
    assert table.units == {"stamp": "ns"}
    assert table.columns["stamp"][0] == 1_700_000_000_000_000_123  # exact
    assert table.columns["n"].dtype == np.int64


@pytest.mark.parametrize("writer", [write_mat_v5, write_mat_v73], ids=["v5", "v7.3"])
def test_mat_vectors_scalars_and_the_rest(tmp_path, writer):
    path = writer(tmp_path / "m.mat", {"t": T, "qm": X, "gtau": 35.15, "M": np.ones((3, 4))})
    table = read_table(path)
    assert set(table.columns) == {"t", "qm"} and table.scalars == {"gtau": 35.15}
    assert np.array_equal(table.columns["qm"], X)
    with pytest.raises(ForeignLogError, match=r"'M' is a 3×4 matrix, not a vector"):
        table.column("M", "position")
    with pytest.raises(ForeignLogError, match=r"'qm' is a vector of 5 values, not a scalar"):
        table.scalar("qm", "effort scale")
    with pytest.raises(ForeignLogError, match=r"its vectors: .*; its scalars: gtau"):
        table.column("nope", "time")


def test_a_mat_struct_gives_dotted_names(tmp_path):
    path = write_mat_v5(tmp_path / "s.mat", {"scope": {"time": T, "pos": X, "gain": 2.0}})
    table = read_table(path)
    assert set(table.columns) == {"scope.time", "scope.pos"} and table.scalars == {"scope.gain": 2.0}


@pytest.mark.parametrize("name", ["empty.csv", "empty.parquet", "empty.mat"])
def test_an_empty_file_is_named(tmp_path, name):
    (tmp_path / name).write_bytes(b"")
    with pytest.raises(ForeignLogError, match=rf"{name} is empty \(0 bytes\)"):
        read_table(tmp_path / name)


def test_a_file_that_is_not_what_its_suffix_says(tmp_path):
    (tmp_path / "x.parquet").write_text("t,x\n0,1\n")
    (tmp_path / "x.mat").write_text("t,x\n0,1\n")
    with pytest.raises(ForeignLogError, match="is not a Parquet file pyarrow can read"):
        read_table(tmp_path / "x.parquet")
    with pytest.raises(ForeignLogError, match=r"x\.mat"):
        read_table(tmp_path / "x.mat")
