"""The one Table 2 record: its totals against numbers worked out by hand, the JSON round trip, the
refusals of a bad file (the key named), and the Markdown of an offline and of a measured table."""

from __future__ import annotations

import dataclasses
import json
import math

import pytest
from axisflow.model import EnergyAccounting, default_params
from axisflow.planner import DEFAULT_OMEGA, Case

from axisflow.experiment.paper import PAPER_TABLE2, PAPER_WAYPOINTS
from axisflow.experiment.table2_markdown import table_markdown, write_table2
from axisflow.experiment.table2_record import (
    LimitColumns,
    MeasuredColumns,
    PlannedColumns,
    Table2,
    Table2Error,
    Table2Row,
    read_table2,
)


def _planned(n: int = 3) -> PlannedColumns:
    return PlannedColumns(
        durations_s=tuple(0.5 + 0.25 * k for k in range(n)),
        energies_j=tuple(10.0 + k for k in range(n)),
        objectives=tuple(1.0 + k for k in range(n)),
        solve_times_s=tuple(1e-3 * (k + 1) for k in range(n)),
        statuses=("converged",) * (n - 1) + ("stopped-at-cap",),
        violations=(0.0,) * (n - 1) + (2e-4,),
    )


MEASURED = MeasuredColumns(
    energies_j=(9.0, None, 11.0),
    completed=(True, True, True),
    state_samples_missing=(0, 4, 0),
    idle_ticks=(0, 7),
    setpoint_samples_missing=2,
)
LIMITS = LimitColumns(time_limits_s=(0.4, 0.5, 0.6), energy_limits_j=(8.0, 9.0, 10.0))


def _table(*rows: Table2Row, **kw) -> Table2:
    waypoints = tuple(0.1 * k for k in range(rows[0].planned.moves + 1))
    return Table2("Table 2, a test", EnergyAccounting.POSITIVE, waypoints, rows, **kw)


def test_the_totals_are_the_formulas_of_the_paper():
    row = Table2Row(
        Case.MIN_TIME_ENERGY, "poly5", "exact", DEFAULT_OMEGA, _planned(), "run", MEASURED, LIMITS
    )
    p = row.planned
    assert (p.moves, p.total_time_s, p.energy_model_j, p.objective_total) == (3, 2.25, 33.0, 6.0)
    # solve times 1, 2, 3 ms: mean 2 ms, sample standard deviation 1 ms
    assert (p.t_opt_ms_mean, p.t_opt_ms_std) == pytest.approx((2.0, 1.0))
    assert p.max_violation == 2e-4 and p.status_counts == {"converged": 2, "stopped-at-cap": 1}
    # E% over the measured moves only (the second has no E_exp): E_th 10 + 12, E_exp 9 + 11
    assert row.measured.energy_measured_j == 20.0 and row.measured.moves_measured == 2
    assert row.energy_error_pct == pytest.approx((22.0 - 20.0) / 22.0 * 100.0)
    assert row.time_limit_ratio == pytest.approx(2.25 / 1.5) and row.energy_limit_ratio == pytest.approx(
        33 / 27
    )
    offline = Table2Row(Case.MIN_TIME, "poly5", "exact", None, _planned(1))
    assert (offline.planned.t_opt_ms_std, offline.energy_error_pct, offline.time_limit_ratio) == (
        0.0,
        None,
        None,
    )


def test_e_percent_is_none_when_nothing_was_measured():
    nothing = dataclasses.replace(MEASURED, energies_j=(None, None, None))
    row = Table2Row(Case.MIN_TIME, "poly3", "exact", None, _planned(), measured=nothing)
    assert row.energy_error_pct is None and row.measured.energy_measured_j == 0.0


@pytest.mark.parametrize(
    "table",
    [
        _table(
            Table2Row(Case.MIN_TIME, "poly3", "ipopt", None, _planned(), limits=LIMITS),
            seed=4,
            params=default_params(),
        ),
        _table(
            Table2Row(Case.MIN_TIME_ENERGY, "poly7", "exact", 0.5, _planned(), "nominal", MEASURED),
            source="logs/run.mcap",
        ),
    ],
    ids=["offline", "measured"],
)
def test_a_table_round_trips_through_its_json_file(tmp_path, table):
    json_path, md_path = write_table2(table, tmp_path / "out", "t2")
    assert (json_path.name, md_path.name) == ("t2.json", "t2.md")
    assert read_table2(json_path) == table
    assert md_path.read_text() == table_markdown(table)
    assert not [p for p in (tmp_path / "out").iterdir() if p.suffix == ".part"]


def _encoded() -> dict:
    row = Table2Row(Case.MIN_TIME, "poly3", "exact", None, _planned(), measured=MEASURED, limits=LIMITS)
    return json.loads(json.dumps(_table(row, params=default_params()).encode()))


def _edit(path: tuple, value: object = None, delete: bool = False):
    def apply(data: dict) -> dict:
        node = data
        for key in path[:-1]:
            node = node[key]
        if delete:
            del node[path[-1]]
        else:
            node[path[-1]] = value
        return data

    return apply


@pytest.mark.parametrize(
    ("edit", "match"),
    [
        (
            _edit(("rows", 0, "planned", "energies_j"), delete=True),
            r"rows\[0\]\.planned: missing key\(s\) energies_j",
        ),
        (_edit(("rows", 0, "measured", "colour"), "red"), r"rows\[0\]\.measured: unknown key\(s\) colour"),
        (_edit(("rows", 0, "case"), "fastest"), "case 'fastest' is not one of min-time, min-time-energy"),
        (
            _edit(("rows", 0, "limits", "time_limits_s"), [0.4]),
            r"limits\.time_limits_s has 1 entries for 3 moves",
        ),
        (_edit(("rows", 0, "planned", "durations_s"), []), "at least one planned move"),
        (_edit(("energy_accounting",), "regenerative"), "energy_accounting = 'regenerative' is not one of"),
        (_edit(("rows", 0, "planned"), [1, 2]), r"rows\[0\]\.planned is a list, not an object"),
        (_edit(("params", "m"), -3.0), "table2.json params: .*m = -3.0 kg"),
    ],
    ids=["missing", "unknown", "case", "length", "empty", "accounting", "not-object", "params"],
)
def test_a_bad_file_is_refused_naming_the_key(edit, match):
    with pytest.raises(Exception, match=match) as exc:
        Table2.decode(edit(_encoded()))
    assert isinstance(exc.value, ValueError)  # Table2Error, or the parameters' own ParameterError


def test_the_totals_in_the_file_are_recomputed_not_trusted():
    data = _encoded()
    data["rows"][0]["planned"]["total_time_s"] = 999.0
    assert Table2.decode(data).rows[0].planned.total_time_s == 2.25


def test_a_file_that_is_not_json_is_one_clear_error(tmp_path):
    (tmp_path / "t.json").write_text("{ nope")
    with pytest.raises(Table2Error, match=r"t\.json cannot be read as JSON"):
        read_table2(tmp_path / "t.json")
    with pytest.raises(Table2Error, match=r"missing\.json does not exist"):
        read_table2(tmp_path / "missing.json")


def _header(md: str) -> list[str]:
    """the cells of the first table's header line"""
    line = next(line for line in md.splitlines() if line.startswith("| case |"))
    return [cell.strip() for cell in line.split("|")[1:-1]]


def test_the_markdown_shows_the_measured_columns_only_when_measured():
    offline = table_markdown(
        _table(Table2Row(Case.MIN_TIME, "poly3", "exact", None, _planned(), limits=LIMITS))
    )
    assert "E_exp [J]" not in offline and "idle ticks" not in offline
    assert "## Against the physical limit" in offline
    assert (
        "| min-time | poly3 | exact | 3 | 2.25 | 33 | 2.000 ± 1.000 | converged 2, stopped-at-cap 1 |"
        in offline
    )
    assert not [h for h in _header(offline) if "paper" in h or "Δ" in h]  # no row of the paper's size
    measured = table_markdown(
        _table(
            Table2Row(Case.MIN_TIME, "poly3", "exact", None, _planned(), measured=MEASURED), source="r.mcap"
        )
    )
    assert _header(measured)[6:8] == ["E_exp [J]", "E%"]
    assert "| 3/3 |" in measured and "| +9.09 |" in measured and "recorded in r.mcap" in measured
    assert "4 state samples within 1 moves" in measured and "2 setpoint samples" in measured
    assert "Against the physical limit" not in measured


def test_rows_of_the_papers_size_show_its_figures_and_the_deviations():
    n = PAPER_WAYPOINTS - 1
    planned = dataclasses.replace(
        _planned(n), durations_s=(50.53 / n,) * n, energies_j=(14858 * 1.1 / n,) * n
    )
    row = Table2Row(Case.MIN_TIME, "poly5", "exact", None, planned)
    paper = PAPER_TABLE2["min-time", "poly5"]
    assert row.paper == paper
    md = table_markdown(_table(row))
    assert f"| {n} | 50.53 | 50.53 | +0.0 | 16344 | 14858 | +10.0 |" in md
    assert f"| {paper.t_opt_ms_mean:.2f} ± {paper.t_opt_ms_std:.2f} |" in md
    assert math.isclose(row.planned.energy_model_j, 14858 * 1.1)
