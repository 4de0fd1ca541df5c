"""The savings report: per move and per run, model and measurement, per cycle and per year.

:class:`SavingsReport` is the record ``savings.json`` holds (:meth:`SavingsReport.encode` /
:meth:`SavingsReport.decode`, round trip tested); ``savings.md`` is its text (:func:`markdown`).

What a plant's energy manager reads from it, per run (the baseline, axisflow at the baseline's
durations move by move, axisflow at the ω that matches the baseline's cycle time):

* cycle time [s]; energy per cycle [J], modelled and measured; the saving against the baseline [%];
* the peak motor torque [N·m] and the peak mechanical power [W] over the cycle (what the drive and the
  supply must deliver), the RMS motor torque over the cycle [N·m] (the motor's copper losses go with
  its square: mechanical energy does not count them);
* energy per year [kWh] = energy per cycle × cycles per day × days per year / 3.6 MJ, and its cost at
  the given price per kWh (the currency is the price's).

Assumptions, stated in the report itself (:data:`ASSUMPTIONS`): mechanical energy at the motor shaft
under the axis's energy accounting (``positive`` by default: braking energy is not regenerated, and
costs nothing); neither the motor's nor the drive's efficiency is modelled; standstill between cycles
costs nothing.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Any

from ..model import AxisflowError
from ..model.files import ensure_dir, read_json, write_atomic_files

J_PER_KWH = 3.6e6
ASSUMPTIONS: tuple[str, ...] = (
    "energy is mechanical: ∫ g(τ_m·ω_m) dt at the motor shaft; the motor's and the drive's efficiency "
    "(copper, iron and switching losses) are not modelled: the RMS torque shows the copper losses' trend",
    "accounting g = {accounting}: {accounting_text}",
    "standstill between cycles costs nothing (no holding torque, no drive stand-by power)",
    "a year is {cycles_per_day:g} cycles a day on {days_per_year:g} days",
)
ACCOUNTING_TEXT = {
    "positive": "power the drive delivers counts, braking power is neither regenerated nor charged",
    "signed": "braking power is regenerated in full and refunded",
    "absolute": "braking power costs as much as driving power",
}


class SavingsReportError(AxisflowError, ValueError):
    """A savings.json cannot be decoded (the field named)."""


@dataclass(frozen=True)
class MoveRow:
    """One move of one run: the model's figures and, where measured, the axis's."""

    index: int
    x0_m: float
    x1_m: float
    duration_s: float
    energy_model_j: float
    energy_measured_j: float | None
    peak_torque_model_nm: float
    peak_torque_measured_nm: float | None
    peak_power_model_w: float
    peak_power_measured_w: float | None
    torque_sq_model: float
    """∫τ_m² dt on the model [N²·m²·s]"""
    torque_sq_measured: float | None


@dataclass(frozen=True)
class RunRow:
    """One run of the comparison and its moves."""

    label: str
    law: str
    omega: float | None
    moves: tuple[MoveRow, ...]
    slower_moves: tuple[int, ...] = ()

    @property
    def cycle_time_s(self) -> float:
        return math.fsum(m.duration_s for m in self.moves)

    @property
    def energy_model_j(self) -> float:
        return math.fsum(m.energy_model_j for m in self.moves)

    @property
    def energy_measured_j(self) -> float | None:
        """The measured energy of the cycle; None unless every move was measured (zero moves cost 0)."""
        values = [m.energy_measured_j for m in self.moves if m.duration_s > 0.0]
        if any(v is None for v in values):
            return None
        return math.fsum(v for v in values if v is not None)

    @property
    def measured(self) -> bool:
        return self.energy_measured_j is not None

    def peak(self, name: str) -> float | None:
        """The largest of a move field over the cycle (None if a move lacks it)."""
        values = [getattr(m, name) for m in self.moves if m.duration_s > 0.0]
        if not values or any(v is None for v in values):
            return None
        return max(values)

    def rms_torque(self, measured: bool) -> float | None:
        """√(∫τ_m² dt / cycle time) [N·m] over the cycle."""
        name = "torque_sq_measured" if measured else "torque_sq_model"
        values = [getattr(m, name) for m in self.moves if m.duration_s > 0.0]
        if not values or any(v is None for v in values) or self.cycle_time_s == 0.0:
            return None
        return math.sqrt(math.fsum(values) / self.cycle_time_s)


@dataclass(frozen=True)
class SavingsReport:
    """Everything ``savings.json`` holds (see the module docstring)."""

    source: str
    """where the moves came from: a recording, a way-point file, or random way points and their seed"""
    params_source: str
    energy_accounting: str
    baseline: str
    limits: dict[str, float | None]
    law: str
    match_status: str
    runs: tuple[RunRow, ...]
    front: tuple[tuple[float, float, float], ...]
    """the law's Pareto front over the cycle: (ω, cycle time [s], energy [J])"""
    baseline_points: dict[str, tuple[float, float]]
    """each baseline law's (cycle time [s], energy [J]) under the limits, on the model"""
    cycles_per_day: float
    days_per_year: float
    price_per_kwh: float
    plant: str = ""
    """the simulated axis the runs were measured on ('' when they were not run)"""

    def run(self, label: str) -> RunRow:
        for r in self.runs:
            if r.label == label:
                return r
        raise KeyError(label)

    def saving_pct(self, label: str, measured: bool) -> float | None:
        """(E_baseline − E_run)/E_baseline·100 of a run against the baseline, model or measured."""
        base, run = self.run("baseline"), self.run(label)
        b = base.energy_measured_j if measured else base.energy_model_j
        e = run.energy_measured_j if measured else run.energy_model_j
        if b is None or e is None or b == 0.0:
            return None
        return (b - e) / b * 100.0

    def kwh_per_year(self, energy_per_cycle_j: float) -> float:
        return energy_per_cycle_j * self.cycles_per_day * self.days_per_year / J_PER_KWH

    def assumptions(self) -> list[str]:
        values = {
            "accounting": self.energy_accounting,
            "accounting_text": ACCOUNTING_TEXT.get(self.energy_accounting, ""),
            "cycles_per_day": self.cycles_per_day,
            "days_per_year": self.days_per_year,
        }
        return [a.format(**values) for a in ASSUMPTIONS]

    # ---- the record on disk ----------------------------------------------------------------------
    def encode(self) -> dict[str, Any]:
        out = asdict(self)
        out["summary"] = self.summary()
        return out

    def summary(self) -> dict[str, Any]:
        """The derived figures per run (what a reader of savings.json looks for first)."""
        rows = {}
        for r in self.runs:
            e_meas = r.energy_measured_j
            rows[r.label] = {
                "law": r.law,
                "omega": r.omega,
                "cycle_time_s": r.cycle_time_s,
                "energy_model_j": r.energy_model_j,
                "energy_measured_j": e_meas,
                "saving_model_pct": None if r.label == "baseline" else self.saving_pct(r.label, False),
                "saving_measured_pct": None if r.label == "baseline" else self.saving_pct(r.label, True),
                "peak_torque_model_nm": r.peak("peak_torque_model_nm"),
                "peak_torque_measured_nm": r.peak("peak_torque_measured_nm"),
                "peak_power_model_w": r.peak("peak_power_model_w"),
                "peak_power_measured_w": r.peak("peak_power_measured_w"),
                "rms_torque_model_nm": r.rms_torque(False),
                "rms_torque_measured_nm": r.rms_torque(True),
                "kwh_per_year_model": self.kwh_per_year(r.energy_model_j),
                "kwh_per_year_measured": None if e_meas is None else self.kwh_per_year(e_meas),
                "slower_moves": list(r.slower_moves),
            }
            for kind in ("model", "measured"):
                kwh = rows[r.label][f"kwh_per_year_{kind}"]
                rows[r.label][f"cost_per_year_{kind}"] = None if kwh is None else kwh * self.price_per_kwh
        return {"runs": rows, "assumptions": self.assumptions()}

    @classmethod
    def decode(cls, data: object, where: str = "savings.json") -> SavingsReport:
        if not isinstance(data, Mapping):
            raise SavingsReportError(f"{where}: not an object")
        values: dict[str, Any] = {}
        for f in fields(cls):
            if f.name not in data:
                raise SavingsReportError(f"{where}: no field {f.name!r}")
            values[f.name] = data[f.name]
        try:
            values["runs"] = tuple(
                RunRow(
                    r["label"],
                    r["law"],
                    r["omega"],
                    tuple(MoveRow(**m) for m in r["moves"]),
                    tuple(r["slower_moves"]),
                )
                for r in values["runs"]
            )
            values["front"] = tuple(tuple(p) for p in values["front"])
            values["baseline_points"] = {k: tuple(v) for k, v in values["baseline_points"].items()}
        except (KeyError, TypeError, AttributeError) as exc:
            raise SavingsReportError(f"{where}: runs, front or baseline points malformed: {exc!r}") from None
        return cls(**values)


def read_report(path: str | Path) -> SavingsReport:
    return SavingsReport.decode(read_json(path, SavingsReportError), str(path))


def write_report(
    report: SavingsReport, folder: Path, also: Mapping[str, str | bytes] | None = None
) -> list[Path]:
    """``savings.json``, ``savings.md`` and the files ``also`` ({name: content}: the figure) in
    ``folder`` (created if needed), written together atomically."""
    text = json.dumps(report.encode(), indent=1, allow_nan=False) + "\n"
    files = {"savings.json": text, "savings.md": markdown(report), **(also or {})}
    return write_atomic_files(ensure_dir(folder), files)


RUN_TITLES = {
    "baseline": "baseline",
    "equal-time": "axisflow, move by move",
    "matched-omega": "axisflow, matched ω",
}


def _num(value: float | None, fmt: str) -> str:
    return "–" if value is None else format(value, fmt)


def _pct(value: float | None) -> str:
    return "–" if value is None else f"{value:+.2f} %"


def markdown(report: SavingsReport) -> str:
    """The report as a page: the runs' table, the per-year table, the assumptions, the moves."""
    lines = [
        f"# Savings: axisflow's {report.law} against a {report.baseline}",
        "",
        f"Moves: {report.source}. Model: {report.params_source} (energy accounting "
        f"{report.energy_accounting}). Baseline limits: "
        + ", ".join(f"{k} {v:g}" for k, v in report.limits.items() if v is not None)
        + "."
        + (f" Measured on the simulated axis ({report.plant})." if report.plant else " Not run on an axis."),
        "",
        "| run | law | cycle time [s] | E model [J] | E measured [J] | saving model | saving measured | "
        "peak τ [N·m] | peak P [W] | RMS τ [N·m] |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in report.runs:
        law = r.law if r.omega is None else f"{r.law}, ω = {r.omega:.6f}"
        saving = [
            "–" if r.label == "baseline" else _num(report.saving_pct(r.label, m), "+.2f") + " %"
            for m in (False, True)
        ]
        measured = r.measured
        lines.append(
            f"| {RUN_TITLES.get(r.label, r.label)} | {law} | {r.cycle_time_s:.3f} | {r.energy_model_j:.1f} | "
            f"{_num(r.energy_measured_j, '.1f')} | {saving[0]} | {saving[1]} | "
            f"{_num(r.peak('peak_torque_measured_nm' if measured else 'peak_torque_model_nm'), '.3f')} | "
            f"{_num(r.peak('peak_power_measured_w' if measured else 'peak_power_model_w'), '.0f')} | "
            f"{_num(r.rms_torque(measured), '.3f')} |"
        )
    lines += [
        "",
        "Peak and RMS torque and peak power are measured where the run was measured, else the model's.",
    ]
    if report.match_status != "matched":
        lines.append(
            f"The matched ω is {report.match_status}: axisflow's {report.law} cannot meet the baseline's "
            "cycle time in total (too-slow: even ω = 1 takes longer; its row shows that fastest plan)."
        )
    slow = report.run("equal-time").slower_moves
    if slow:
        lines.append(
            "Moves the law cannot make as fast as the baseline (they take longer): "
            f"{', '.join(map(str, slow))}."
        )
    lines += [
        "",
        f"Per year ({report.cycles_per_day:g} cycles a day, {report.days_per_year:g} days, "
        f"{report.price_per_kwh:g} per kWh):",
        "",
        "| run | kWh/year model | kWh/year measured | cost/year model | cost/year measured |",
        "|---|---:|---:|---:|---:|",
    ]
    for r in report.runs:
        s = report.summary()["runs"][r.label]
        lines.append(
            f"| {RUN_TITLES.get(r.label, r.label)} | {s['kwh_per_year_model']:.2f} | "
            f"{_num(s['kwh_per_year_measured'], '.2f')} | {s['cost_per_year_model']:.2f} | "
            f"{_num(s['cost_per_year_measured'], '.2f')} |"
        )
    lines += ["", "Assumptions:", ""] + [f"* {a}" for a in report.assumptions()]
    lines += [
        "",
        "Each move: duration [s], energy model / measured [J] per run.",
        "",
        "| move | x0 → x1 [m] | " + " | ".join(f"{r.label} T | E | E meas" for r in report.runs) + " |",
        "|---:|---|" + "---:|---:|---:|" * len(report.runs),
    ]
    for k, first in enumerate(report.runs[0].moves):
        cells = []
        for r in report.runs:
            m = r.moves[k]
            cells.append(f"{m.duration_s:.3f} | {m.energy_model_j:.2f} | {_num(m.energy_measured_j, '.2f')}")
        lines.append(f"| {first.index} | {first.x0_m:.4f} → {first.x1_m:.4f} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"
