"""The report of a refit: ``report.json`` (the record), ``report.md`` (for people), ``params.toml``.

report.json keys: ``parameters`` {name: {value, std, initial, unit}}, ``correlation`` {names, matrix},
``condition_number``, ``fit`` and ``validation`` (and their ``*_nominal`` twins: the nominal
parameters' error on the same samples) each {rms_nm, max_abs_nm, nrmse_pct, samples,
rms_unfiltered_nm} — ``_n`` instead of ``_nm`` for a carriage joint —, ``solver`` {method, status,
iterations, time_s}, ``timing_s`` {read, prepare, solve, total}, ``log`` {paths, topic, joint,
joint_kind, samples, duration_s, truncated, stamp_jitter_s, window (null: whole logs, else {start_s,
end_s, origin_ns})}, ``samples`` {total, used, stationary,
saturated, trimmed, non_finite}, ``uncertainty`` {method, samples, effective_samples, flagged},
``torque_delay_s`` {value, estimated}, ``preparation`` (the filter and exclusion settings),
``warnings``.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from ..model import params_to_toml
from .fit import PARAMETER_UNITS
from .refit import Identification
from .signals import JointKind

SOLVER_METHOD = "CasADi sqpmethod (qrqp QP steps, Gauss–Newton Hessian)"


def report_json(ident: Identification) -> dict[str, Any]:
    """The JSON record of a refit (keys in the module docstring)."""
    fit, unc, kind = ident.fit, ident.uncertainty, ident.kind
    values, initial = fit.values.as_dict(), fit.initial.as_dict()
    logs = ident.logs
    used = sum(int(log.usable.sum()) for log in logs)
    out: dict[str, Any] = {
        "parameters": {
            name: {
                "value": values[name],
                "std": unc.std[name],
                "initial": initial[name],
                "unit": PARAMETER_UNITS[name],
            }
            for name in fit.fitted
        },
        "correlation": {"names": list(unc.names), "matrix": unc.correlation.round(6).tolist()},
        "condition_number": unc.condition_number,
    }
    for key, stats in ident.errors.items():
        out[key] = stats.to_json(kind)
    if "validation" not in out:
        out["validation"] = None
    out["validation_source"] = ident.validation_source or None
    out.update(
        {
            "solver": {
                "method": SOLVER_METHOD,
                "status": fit.status,
                "iterations": fit.iterations,
                "time_s": fit.solve_time_s,
            },
            "timing_s": ident.timing_s,
            "log": {
                "paths": [log.signals.source for log in logs],
                "topic": ident.settings.topic,
                "joint": ident.settings.joint,
                "joint_kind": kind.value,
                "samples": sum(len(log.signals.t_s) for log in logs),
                "duration_s": math.fsum(log.signals.duration_s for log in logs),
                "truncated": [log.signals.truncated for log in logs],
                "stamp_jitter_s": max(log.signals.stamp_jitter_s for log in logs),
                "window": None if ident.settings.window.whole else dataclasses.asdict(ident.settings.window),
            },
            "samples": {
                "total": sum(len(log.signals.t_s) for log in logs),
                "used": used,
                "fitted": unc.samples,
                "stationary": sum(log.stationary for log in logs),
                "saturated": sum(log.saturated for log in logs),
                "trimmed": sum(log.trimmed for log in logs),
                "non_finite": sum(log.signals.dropped for log in logs),
            },
            "uncertainty": {
                "method": unc.method,
                "samples": unc.samples,
                "effective_samples": unc.effective_samples,
                "flagged": [{"a": a, "b": b, "correlation": rho} for a, b, rho in unc.flagged],
            },
            "torque_delay_s": {"value": ident.delay_s, "estimated": ident.delay_estimated},
            "preparation": dataclasses.asdict(ident.settings.preparation),
            "warnings": list(unc.warnings),
        }
    )
    return out


def report_markdown(report: dict[str, Any]) -> str:
    """The report for people: parameters with σ, errors refit against nominal, warnings, the log."""
    kind = JointKind(report["log"]["joint_kind"])
    unit, key = kind.effort_unit, kind.effort_key
    log = report["log"]
    lines = [
        "# Friction refit",
        "",
        f"Log: {', '.join(log['paths'])}, topic `{log['topic']}`, joint `{log['joint']}` "
        f"({log['samples']} samples, {log['duration_s']:.1f} s{_window_text(log.get('window'))}).",
        "",
        "| parameter | refit | σ | nominal | change |",
        "|---|---:|---:|---:|---:|",
    ]
    for name, p in report["parameters"].items():
        change = (p["value"] - p["initial"]) / p["initial"] * 100.0 if p["initial"] else math.nan
        lines.append(
            f"| {name} [{p['unit']}] | {p['value']:.6g} | {p['std']:.3g} | {p['initial']:.6g} "
            f"| {change:+.2f} % |"
        )
    lines += [
        "",
        f"Effort error (measured − model, {unit}; both through the fit's zero-phase filter; unfiltered "
        "RMS beside it):",
        "",
        "| samples | parameters | RMS | max | NRMSE [%] | unfiltered RMS | n |",
        "|---|---|---:|---:|---:|---:|---:|",
    ]
    for part in ("fit", "validation"):
        for which, suffix in (("refit", ""), ("nominal", "_nominal")):
            e = report.get(part + suffix)
            if e is None:
                continue
            lines.append(
                f"| {part} | {which} | {e[f'rms_{key}']:.4g} | {e[f'max_abs_{key}']:.4g} "
                f"| {e['nrmse_pct']:.3g} | {e[f'rms_unfiltered_{key}']:.4g} | {e['samples']} |"
            )
    if report.get("validation_source"):
        lines += ["", f"Validation: {report['validation_source']}."]
    s, delay, solver = report["samples"], report["torque_delay_s"], report["solver"]
    unc = report["uncertainty"]
    lines += [
        "",
        f"Samples: {s['used']} of {s['total']} used ({s['stationary']} stationary, {s['saturated']} "
        f"saturated, {s['trimmed']} trimmed at the edges, {s['non_finite']} not finite); "
        f"{s['fitted']} fitted after decimation.",
        f"Torque/position offset: {delay['value'] * 1e3:.3f} ms "
        f"({'estimated' if delay['estimated'] else 'given'}).",
        f"Solver: {solver['method']}: {solver['status']} in {solver['iterations']} iterations, "
        f"{solver['time_s'] * 1e3:.1f} ms. Condition number {report['condition_number']:.3g}.",
        f"Uncertainty: {unc['method']} ({unc['effective_samples']:.0f} effective of {unc['samples']} "
        "samples).",
    ]
    if unc["flagged"]:
        pairs = ", ".join(f"{f['a']}–{f['b']} {f['correlation']:+.2f}" for f in unc["flagged"])
        lines.append(f"Correlated (|ρ| > 0.8): {pairs}.")
    if report["warnings"]:
        lines += ["", "## Warnings", ""] + [f"- {w}" for w in report["warnings"]]
    t = report["timing_s"]
    lines += [
        "",
        f"Timing: read {t['read']:.2f} s, prepare {t['prepare']:.2f} s, solve {t['solve']:.2f} s, "
        f"total {t['total']:.2f} s.",
    ]
    return "\n".join(lines) + "\n"


def params_file(ident: Identification) -> str:
    """``params.toml``: a complete parameter file with the refit values (every ``--params`` takes it)."""
    fitted = ", ".join(ident.fit.fitted)
    sources = ", ".join(log.signals.source for log in ident.logs)
    head = (
        f"# Refit by `axisflow identify` from {sources}: {fitted}.\n"
        "# A refit M_eq is written as the cart mass m (rotor, gearbox and pulley inertias stay nominal).\n"
    )
    return head + params_to_toml(ident.params)


def _window_text(window: dict[str, Any] | None) -> str:
    if not window:
        return ""
    start = "the start" if window["start_s"] is None else f"{window['start_s']:g} s"
    end = "the end" if window["end_s"] is None else f"{window['end_s']:g} s"
    origin = "each log's first sample" if window["origin_ns"] is None else f"stamp {window['origin_ns']} ns"
    return f" from {start} to {end} after {origin}"
