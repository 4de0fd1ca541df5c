"""Bad input of foreign logs: `axisflow import`, and identify given CSV, Parquet or MATLAB files."""

from __future__ import annotations

from pathlib import Path

from .case import case

_SCOPE_MAP = (
    "--time",
    "t",
    "--position",
    "x",
    "--position-unit",
    "mm",
    "--effort",
    "f",
    "--effort-unit",
    "N",
)
CASES = [
    case(
        "import: a missing column",
        "import",
        "scope.csv",
        "--out",
        "new.mcap",
        "--time",
        "t",
        "--position",
        "pos",
        says=("scope.csv has no position column 'pos'", "its columns: t, x, f"),
        untouched=("new.mcap",),
    ),
    case(
        "import: time that goes backwards",
        "import",
        "backwards.csv",
        "--out",
        "new.mcap",
        *_SCOPE_MAP,
        says=("time goes back at line 5: 0.0015 s after 0.002 s at line 4", "time must increase"),
        untouched=("new.mcap",),
    ),
    case(
        "import: a run of missing values",
        "import",
        "nan-run.csv",
        "--out",
        "new.mcap",
        *_SCOPE_MAP,
        says=("1 run(s) of 2 or more rows with missing values", "the longest 3 rows from line 4 (in f)"),
        untouched=("new.mcap",),
    ),
    case(
        "import: an unknown unit",
        "import",
        "scope.csv",
        "--out",
        "new.mcap",
        "--time",
        "t",
        "--position",
        "x",
        "--position-unit",
        "inch",
        says=("position unit 'inch'", "m, mm, um, nm, rad, deg, rev, counts"),
        untouched=("new.mcap",),
    ),
    case(
        "import: an effort in volts without a scale",
        "import",
        "scope.csv",
        "--out",
        "new.mcap",
        *_SCOPE_MAP[:6],
        "--effort",
        "f",
        "--effort-unit",
        "V",
        says=("effort 'f' in V is not a force", "N per V"),
        untouched=("new.mcap",),
    ),
    case(
        "import: neither a time column nor a rate",
        "import",
        "scope.csv",
        "--out",
        "new.mcap",
        "--position",
        "x",
        says=("--time COL, or --rate HZ",),
        untouched=("new.mcap",),
    ),
    case(
        "import: an empty file",
        "import",
        "empty.csv",
        "--out",
        "new.mcap",
        *_SCOPE_MAP,
        says=("empty.csv is empty (0 bytes)",),
        untouched=("new.mcap",),
    ),
    case(
        "import: a .mat variable that is not a vector",
        "import",
        "emps.mat",
        "--out",
        "new.mcap",
        "--time",
        "t",
        "--position",
        "M",
        "--position-unit",
        "m",
        says=("position 'M' is a 3×4 matrix, not a vector",),
        untouched=("new.mcap",),
    ),
    case(
        "import: columns of different lengths",
        "import",
        "emps.mat",
        "--out",
        "new.mcap",
        "--time",
        "t",
        "--position",
        "short",
        "--position-unit",
        "m",
        says=("differ in length (time 't' 2000, position 'short' 1999 values)",),
        untouched=("new.mcap",),
    ),
    case(
        "import: a scale variable that is not a scalar",
        "import",
        "emps.mat",
        "--out",
        "new.mcap",
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
        "--effort-scale",
        "vir",
        says=("effort scale 'vir' is a vector of 2000 values, not a scalar",),
        untouched=("new.mcap",),
    ),
    case(
        "import: files that overlap in time",
        "import",
        "scope.csv",
        "scope-again.csv",
        "--out",
        "new.mcap",
        *_SCOPE_MAP,
        says=("scope.csv (0.000000 s to 0.009000 s)", "overlap in time"),
        untouched=("new.mcap",),
    ),
    case(
        "import: an output that exists",
        "import",
        "scope.csv",
        "--out",
        "existing.mcap",
        *_SCOPE_MAP,
        says=("existing.mcap already exists", "--overwrite"),
        untouched=("existing.mcap",),
    ),
    case(
        "import: an output that is an input",
        "import",
        "scope.csv",
        "--out",
        "scope-link.mcap",
        "--overwrite",
        *_SCOPE_MAP,
        says=("scope-link.mcap is the input scope.csv under another name",),
    ),
    case(
        "identify: a CSV log without its columns",
        "identify",
        "scope.csv",
        "--out",
        "ident",
        says=("needs its position column: --position COL",),
        untouched=("ident",),
    ),
    case(
        "identify: column options for MCAP logs",
        "identify",
        "still.mcap",
        "--out",
        "ident",
        "--position",
        "x",
        says=("--position map the columns of .csv", "these logs are MCAP"),
        untouched=("ident",),
    ),
]


def write_foreign_logs(d: Path) -> None:
    """The foreign logs the cases above name: a scope's CSV (1 kHz, 10 rows), one whose time goes back,
    one with a run of empty values, an empty one, and an EMPS-like MATLAB file."""
    import numpy as np
    from scipy.io import savemat

    rows = [f"{k / 1000!r};{400 + k};{10.0 * k!r}" for k in range(10)]
    (d / "scope.csv").write_text("t;x;f\n" + "\n".join(rows) + "\n")
    (d / "scope-again.csv").write_text("t;x;f\n" + "\n".join(rows) + "\n")
    back = [*rows[:3], "0.0015;402;1.0", *rows[4:]]
    (d / "backwards.csv").write_text("t;x;f\n" + "\n".join(back) + "\n")
    holes = [r if not 2 <= k < 5 else r.rsplit(";", 1)[0] + ";" for k, r in enumerate(rows)]
    (d / "nan-run.csv").write_text("t;x;f\n" + "\n".join(holes) + "\n")
    (d / "empty.csv").write_bytes(b"")
    t = np.arange(2000) * 1e-3
    mat = {
        "t": t,
        "qm": 0.1 * np.sin(t),
        "short": t[:-1],
        "vir": np.cos(t),
        "gtau": 35.15,
        "M": np.ones((3, 4)),
    }
    savemat(d / "emps.mat", mat)
    (d / "scope-link.mcap").symlink_to("scope.csv")
