"""Bad input of the fleet: `axisflow fleet index|identify|trend|simulate`."""

from __future__ import annotations

from pathlib import Path

from axisflow.fleet.catalog import index_logs
from axisflow.model import default_params

from .case import case

CASES = [
    case(
        "fleet: a catalog that is not one",
        "fleet",
        "identify",
        "--catalog",
        "fake-cat",
        says=("fake-cat/catalog.parquet", "is not a fleet catalog"),
    ),
    case(
        "fleet: index into a catalog that is not one",
        "fleet",
        "index",
        "still.mcap",
        "--catalog",
        "fake-cat",
        says=("fake-cat/catalog.parquet", "is not a fleet catalog"),
        untouched=("fake-cat",),
    ),
    case(
        "fleet: a folder without a catalog",
        "fleet",
        "identify",
        "--catalog",
        "full",
        says=("full is not a fleet catalog", "no catalog.parquet"),
    ),
    case(
        "fleet: a scheduler that does not answer",
        "fleet",
        "identify",
        "--catalog",
        "cat",
        "--scheduler",
        "tcp://127.0.0.1:9",
        "--connect-timeout",
        "1",
        says=("scheduler tcp://127.0.0.1:9", "does not answer within 1 s"),
        untouched=("cat",),
    ),
    case(
        "fleet: a window shorter than 10 s",
        "fleet",
        "identify",
        "--catalog",
        "cat",
        "--window",
        "5",
        says=("--window 5 s", "at least 10 s"),
    ),
    case(
        "fleet: trend before identify",
        "fleet",
        "trend",
        "--catalog",
        "cat",
        says=("cat has no fits.parquet", "fleet identify"),
    ),
    case(
        "fleet: a baseline of one window",
        "fleet",
        "trend",
        "--catalog",
        "cat",
        "--baseline",
        "1",
        says=("--baseline 1 windows", "[2, 1000] windows"),
    ),
    case(
        "fleet: no log under the path",
        "fleet",
        "index",
        "full",
        "--catalog",
        "new-cat",
        says=("no MCAP log", "full"),
        untouched=("new-cat",),
    ),
    case(
        "fleet: wear of an axis the fleet lacks",
        "fleet",
        "simulate",
        "--axes",
        "3",
        "--days",
        "5",
        "--out",
        "sim",
        "--wear",
        "a7:2:10",
        says=("--wear a7", "no such axis", "a0…a2"),
        untouched=("sim",),
    ),
    case(
        "fleet: wear after the last day",
        "fleet",
        "simulate",
        "--axes",
        "3",
        "--days",
        "5",
        "--out",
        "sim",
        "--wear",
        "a1:9:10",
        says=("--wear a1: day 9", "outside the 5 days"),
        untouched=("sim",),
    ),
    case(
        "fleet: simulate into a simulated fleet",
        "fleet",
        "simulate",
        "--axes",
        "2",
        "--days",
        "2",
        "--out",
        "sim-fleet",
        says=("sim-fleet holds a simulated fleet already", "--overwrite"),
        untouched=("sim-fleet",),
    ),
]


def write_fleet_inputs(d: Path) -> None:
    """What the cases above name beside the shared inputs: a catalog that is not one, a catalog of
    still.mcap (which must exist already), a folder that holds a simulated fleet."""
    (d / "fake-cat").mkdir()
    (d / "fake-cat" / "catalog.parquet").write_text("not a catalog\n")
    index_logs([d / "still.mcap"], d / "cat", default_params())
    (d / "sim-fleet").mkdir()
    (d / "sim-fleet" / "truth.json").write_text("{}\n")
