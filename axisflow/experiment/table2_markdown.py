"""Table 2 as Markdown (:func:`table_markdown`: the paper's figures beside rows of the paper's size),
and the record's two files, ``STEM.json`` and ``STEM.md``, written together (:func:`write_table2`)."""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from ..model.files import ensure_dir, write_atomic_files
from .paper import PAPER_WAYPOINTS, PaperRow
from .table2_record import MeasuredColumns, Table2, Table2Row


def write_table2(table: Table2, folder: str | Path, stem: str = "table2") -> tuple[Path, Path]:
    """``table`` as ``STEM.json`` (:meth:`Table2.encode`) and ``STEM.md`` (:func:`table_markdown`) in
    ``folder``, created if needed, written atomically together; returns the two paths."""
    files = {
        f"{stem}.json": json.dumps(table.encode(), indent=1, allow_nan=False) + "\n",
        f"{stem}.md": table_markdown(table),
    }
    json_path, md_path = write_atomic_files(ensure_dir(folder), files)
    return json_path, md_path


def _dash(value: float | None, fmt: str) -> str:
    return "–" if value is None or not math.isfinite(value) else format(value, fmt)


def _dev(ours: float | None, paper: float | None) -> str | None:
    if ours is None or paper is None:
        return None
    return f"{(ours - paper) / paper * 100.0:+.1f}"


@dataclass(frozen=True)
class _Column:
    header: str
    cell: Callable[[Table2Row, PaperRow | None], str | None]
    """the cell's text (None: "–") for a row and the paper's row of the same size, if any"""
    numeric: bool = True
    measured: bool = False
    """shown only when some row has measured columns"""
    paper: bool = False
    """shown only when some row is of the paper's size"""


def _t_opt(row: Table2Row, _paper: PaperRow | None) -> str:
    return f"{row.planned.t_opt_ms_mean:.3f} ± {row.planned.t_opt_ms_std:.3f}"


def _measured(get: Callable[[Table2Row, MeasuredColumns], str | None]) -> Callable[..., str | None]:
    return lambda row, _paper: None if row.measured is None else get(row, row.measured)


_COLUMNS = (
    _Column("case", lambda row, _p: row.case.value, numeric=False),
    _Column("law", lambda row, _p: row.law, numeric=False),
    _Column("solver", lambda row, _p: row.solver, numeric=False),
    _Column(
        "moves",
        lambda row, _p: (
            str(row.planned.moves)
            if row.measured is None
            else f"{row.measured.moves_completed}/{row.planned.moves}"
        ),
    ),
    _Column("T [s]", lambda row, _p: f"{row.planned.total_time_s:.2f}"),
    _Column("paper T [s]", lambda _row, p: p and f"{p.total_time_s:.2f}", paper=True),
    _Column("ΔT [%]", lambda row, p: p and _dev(row.planned.total_time_s, p.total_time_s), paper=True),
    _Column("E_th [J]", lambda row, _p: f"{row.planned.energy_model_j:.0f}"),
    _Column("paper E_th [J]", lambda _row, p: p and f"{p.energy_model_j:.0f}", paper=True),
    _Column("ΔE_th [%]", lambda row, p: p and _dev(row.planned.energy_model_j, p.energy_model_j), paper=True),
    _Column("E_exp [J]", _measured(lambda _row, m: f"{m.energy_measured_j:.0f}"), measured=True),
    _Column("paper E_exp [J]", lambda _row, p: p and f"{p.energy_measured_j:.0f}", measured=True, paper=True),
    _Column("E%", lambda row, _p: _dash(row.energy_error_pct, "+.2f"), measured=True),
    _Column("paper E%", lambda _row, p: p and f"{p.energy_error_pct:+.2f}", measured=True, paper=True),
    _Column("t_opt [ms]", _t_opt),
    _Column(
        "paper t_opt [ms]", lambda _row, p: p and f"{p.t_opt_ms_mean:.2f} ± {p.t_opt_ms_std:.2f}", paper=True
    ),
    _Column("idle ticks", _measured(lambda _row, m: str(m.idle_ticks_total)), measured=True),
    _Column(
        "statuses",
        lambda row, _p: ", ".join(f"{k} {v}" for k, v in row.planned.status_counts.items()),
        numeric=False,
    ),
    _Column("max violation", lambda row, _p: f"{row.planned.max_violation:.2e}"),
)

_LIMIT_COLUMNS = (
    _Column("case", lambda row, _p: row.case.value, numeric=False),
    _Column("law", lambda row, _p: row.law, numeric=False),
    _Column("solver", lambda row, _p: row.solver, numeric=False),
    _Column("objective Σ", lambda row, _p: f"{row.planned.objective_total:.2f}"),
    _Column("T [s]", lambda row, _p: f"{row.planned.total_time_s:.2f}"),
    _Column("T_limit [s]", lambda row, _p: row.limits and f"{row.limits.total_time_limit_s:.2f}"),
    _Column("T/T_limit", lambda row, _p: _dash(row.time_limit_ratio, ".3f")),
    _Column("E_th [J]", lambda row, _p: f"{row.planned.energy_model_j:.0f}"),
    _Column("E_limit [J]", lambda row, _p: row.limits and f"{row.limits.energy_limit_j:.0f}"),
    _Column("E/E_limit", lambda row, _p: _dash(row.energy_limit_ratio, ".3f")),
)

_NOTES = {
    "planned": "T: Σ planned durations of the moves; E_th: Σ model energy of the plans (eq. 3) under the "
    "accounting above; t_opt: wall time of each solve, mean ± std (measured on the machine that planned); "
    "statuses: the solver's status of each move; max violation: worst relative excess over the velocity "
    "or torque limit at the 1 kHz execution samples.",
    "measured": "E_exp: Σ ∫ g(τ_m·ω_m) dt of the measured motor torque and speed over each move's ticks, "
    "g the same accounting; E% = (E_th − E_exp)/E_th over the measured moves; idle ticks: setpoint "
    "samples between consecutive moves; moves: completed/planned.",
    "paper": f"paper: the paper's figures, and Δ the deviation from them, for runs of {PAPER_WAYPOINTS} way "
    "points.",
    "limits": "T_limit: Σ of each move's time-optimal (bang–cruise–bang) duration under the same velocity "
    "and torque limits and the full friction model; E_limit: Σ of the least energy of a limit-respecting "
    "profile (full-force ramps, cruise, coast, full braking) at each move's planned duration.",
}


def _table(columns: Sequence[_Column], rows: Sequence[Table2Row]) -> list[str]:
    lines = [
        "| " + " | ".join(c.header for c in columns) + " |",
        "|" + "|".join("---:" if c.numeric else "---" for c in columns) + "|",
    ]
    for row in rows:
        paper = row.paper
        cells = [c.cell(row, paper) for c in columns]
        lines.append("| " + " | ".join(cell or "–" for cell in cells) + " |")
    return lines


def table_markdown(table: Table2) -> str:
    """The table as Markdown: the rows with the paper's figures beside those of the paper's size, the
    rows against the physical limit when computed, the definitions, and the samples a recording lost."""
    measured = any(row.measured is not None for row in table.rows)
    paper = any(row.paper is not None for row in table.rows)
    columns = [c for c in _COLUMNS if (measured or not c.measured) and (paper or not c.paper)]
    where = [f"{len(table.waypoints_m)} way points"]
    if table.seed is not None:
        where.append(f"seed {table.seed}")
    if table.source is not None:
        where.append(f"recorded in {table.source}")
    lines = [
        f"# {table.title}",
        "",
        f"{', '.join(where)}; energy accounting: {table.accounting.value}.",
        "",
        *_table(columns, table.rows),
        "",
        " ".join(
            [
                _NOTES["planned"],
                *([_NOTES["measured"]] if measured else []),
                *([_NOTES["paper"]] if paper else []),
            ]
        ),
    ]
    with_limits = [row for row in table.rows if row.limits is not None]
    if with_limits:
        lines += [
            "",
            "## Against the physical limit",
            "",
            *_table(_LIMIT_COLUMNS, with_limits),
            "",
            _NOTES["limits"],
        ]
    for row in table.rows:
        m = row.measured
        if m is None:
            continue
        left_out = m.moves_completed - m.moves_measured
        if left_out or m.setpoint_samples_missing:
            lines += [
                "",
                f"**Samples lost by the recording** in {row.case.value} {row.law}: "
                f"{m.state_samples_missing_total} state samples within {left_out} moves (left out of "
                f"E_exp and E%, with their E_th), {m.setpoint_samples_missing} setpoint samples (idle "
                "ticks counted from those recorded).",
            ]
    return "\n".join(lines) + "\n"
