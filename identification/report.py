"""The report of a refit: ``report.json`` (the record), ``report.md`` (for people), ``params.toml``.

report.json keys: ``parameters`` {name: {value, std, initial, unit}} (eq. (1)'s fitted parameters),
``coulomb_combination`` {name, value, std, initial, unit} (a1 + a3·π/2: the Coulomb force at speed,
what a log always determines, even when it cannot separate a1 from a3), ``extra_terms`` {stroke
{terms, stretch_m, coefficients {c_k: {value, std, unit}}, variation_pct}, cogging {order:
{amplitude_nm, phase_rad, std_nm, found_in_residual}}}, ``correlation`` {names, matrix} (every
estimated term), ``condition_number``,
``fit`` and ``validation`` (and their ``*_nominal`` twins: the nominal parameters' error on the same
samples) each {rms_nm, max_abs_nm, nrmse_pct, samples, rms_unfiltered_nm} — ``_n`` instead of ``_nm``
for a carriage joint —, ``unexplained`` {rms_nm, rms_filtered_nm, noise_floor_nm,
noise_density_nm2_per_hz, floor_band_hz, fit_over_floor, validation_over_floor, peaks_hz
[{frequency_hz, rms_nm, ratio}], peaks_order [{cycles_per_rev, rms_nm, ratio}], segments,
order_segments}, ``solver`` {method, status, iterations, time_s}, ``timing_s`` {read, prepare,
select (the model selection), solve (offset searches and fits), judge (errors and residual
analyses), total}, ``log`` {paths,
topic, joint, joint_kind, samples,
duration_s, truncated, stamp_jitter_s, window (null: whole logs, else {start_s, end_s, origin_ns}),
drive (per log: what drove the axis, as its bridge recorded it; null if it did not)}, ``samples`` {total
(grid points), used, fitted, stationary, saturated, trimmed, non_finite, missing, holes, longest_hole_s,
near_holes}, ``velocity`` {used, logged, logged_lag_s}, ``uncertainty`` {method, samples,
effective_samples, flagged}, ``torque_delay_s`` {value, estimated, estimate, std, resolvable, period},
``preparation`` (the filter and exclusion settings), ``warnings``; ``structure`` and ``selection``
(:mod:`.selection_report`); ``effort_table`` {file, rows} (:mod:`.effort_table`).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from ..model import params_to_toml
from .effort_table import EFFORT_TABLE
from .fit import PARAMETER_UNITS
from .preparation import logged_velocity_lag_s
from .refit import Identification
from .selection_report import selection_json, selection_markdown, structure_json
from .signals import JointKind, recorded_drive

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
        "terms": _terms(ident),
        "coulomb_combination": _coulomb_combination(ident),
        "extra_terms": _extra_terms(ident),
        "correlation": {"names": list(unc.names), "matrix": unc.correlation.round(6).tolist()},
        "condition_number": unc.condition_number,
        "effort_table": {
            "file": EFFORT_TABLE,
            "rows": sum(log.signals.t_s.size for log in logs + ident.validation_logs),
        },
        "structure": structure_json(ident),
        "selection": selection_json(ident),
    }
    for key, stats in ident.errors.items():
        out[key] = stats.to_json(kind)
    if "validation" not in out:
        out["validation"] = None
    out["validation_source"] = ident.validation_source or None
    out["unexplained"] = _unexplained(ident)
    delay = ident.delay
    grids = [log.signals.grid for log in logs]
    lags = [logged_velocity_lag_s(log) for log in logs]
    known = [lag for lag in lags if lag is not None]
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
                "drive": [recorded_drive(log.signals.source, log.signals.topic) for log in logs],
            },
            "samples": {
                "total": sum(len(log.signals.t_s) for log in logs),
                "used": used,
                "fitted": unc.samples,
                "stationary": sum(log.stationary for log in logs),
                "saturated": sum(log.saturated for log in logs),
                "trimmed": sum(log.trimmed for log in logs),
                "non_finite": sum(log.signals.dropped for log in logs),
                "missing": sum(g.lost for g in grids),
                "holes": sum(len(g.holes) for g in grids),
                "longest_hole_s": max(g.longest_hole * g.period_ns * 1e-9 for g in grids),
                "near_holes": sum(log.near_holes for log in logs),
            },
            "velocity": {
                "used": "derivative of the zero-phase filtered position "
                f"({ident.settings.preparation.cutoff_hz:g} Hz); the log's own velocity is not used",
                "logged": all(log.signals.velocity_logged for log in logs),
                "logged_lag_s": float(np.mean(known)) if len(known) == len(lags) else None,
            },
            "uncertainty": {
                "method": unc.method,
                "samples": unc.samples,
                "effective_samples": unc.effective_samples,
                "flagged": [{"a": a, "b": b, "correlation": rho} for a, b, rho in unc.flagged],
            },
            "torque_delay_s": {
                "value": ident.delay_s,
                "estimated": ident.delay_estimated,
                "estimate": None if delay is None else delay.estimate_s,
                "std": None if delay is None or not math.isfinite(delay.std_s) else delay.std_s,
                "resolvable": None if delay is None else delay.resolvable,
                "period": 1.0 / min(log.signals.rate_hz for log in logs),
            },
            "preparation": dataclasses.asdict(ident.settings.preparation),
            "warnings": list(unc.warnings) + _delay_warning(ident) + _bound_warnings(ident),
        }
    )
    return out


def _coulomb_combination(ident: Identification) -> dict[str, Any] | None:
    """a1 + a3·π/2 with its σ (from the covariance of a1 and a3), or None when neither was fitted."""
    fit, unc = ident.fit, ident.uncertainty
    if "a1" not in fit.fitted and "a3" not in fit.fitted:
        return None
    w = {"a1": 1.0, "a3": 0.5 * math.pi}
    values, initial = fit.values.as_dict(), fit.initial.as_dict()
    names = [n for n in ("a1", "a3") if n in unc.names]
    index = [unc.names.index(n) for n in names]
    std = np.array([unc.std[n] for n in names])
    corr = unc.correlation[np.ix_(index, index)]
    weights = np.array([w[n] for n in names])
    variance = float(weights @ (corr * np.outer(std, std)) @ weights)
    return {
        "name": "a1 + a3·π/2",
        "value": values["a1"] + w["a3"] * values["a3"],
        "std": math.sqrt(max(variance, 0.0)),
        "initial": initial["a1"] + w["a3"] * initial["a3"],
        "unit": "N",
    }


def _extra_terms(ident: Identification) -> dict[str, Any]:
    extra, std = ident.fit.extra, ident.uncertainty.std
    terms = ident.extra
    out: dict[str, Any] = {"stroke": None, "cogging": None}
    if terms.stroke_terms:
        names = [f"c{k}" for k in range(1, terms.stroke_terms + 1)]
        lo, hi = ident.stretch_m
        xi = np.linspace(-1.0, 1.0, 201)
        profile = np.polynomial.legendre.legval(xi, np.r_[0.0, [extra[n] for n in names]])
        a1 = ident.fit.values.a1
        out["stroke"] = {
            "terms": terms.stroke_terms,
            "stretch_m": [lo, hi],
            "coefficients": {n: {"value": extra[n], "std": std[n], "unit": "N"} for n in names},
            "variation_pct": float(np.max(np.abs(profile)) / a1 * 100.0) if a1 > 0 else None,
        }
    if terms.cogging_orders:
        cogging = {}
        for order in terms.cogging_orders:
            s, c = extra[f"cog{order}_sin"], extra[f"cog{order}_cos"]
            cogging[str(order)] = {
                "amplitude_nm": math.hypot(s, c),
                "phase_rad": math.atan2(c, s),
                "std_nm": max(std[f"cog{order}_sin"], std[f"cog{order}_cos"]),
                "found_in_residual": order in ident.cogging_found,
            }
        out["cogging"] = cogging
    return out


def _unexplained(ident: Identification) -> dict[str, Any]:
    r, u = ident.residuals, ident.kind.effort_key
    floor = r.noise_floor

    def over(key: str) -> float | None:
        e = ident.errors.get(key)
        return e.rms / floor if e is not None and math.isfinite(floor) and floor > 0 else None

    def number(x: float) -> float | None:
        return x if math.isfinite(x) else None

    fit = ident.errors.get("fit")
    return {
        f"rms_{u}": fit.rms_unfiltered if fit is not None else None,
        f"rms_filtered_{u}": fit.rms if fit is not None else None,
        f"noise_floor_{u}": number(floor),
        f"noise_density_{u}2_per_hz": number(r.noise_density),
        "floor_band_hz": list(r.floor_band_hz),
        "fit_over_floor": over("fit"),
        "validation_over_floor": over("validation"),
        "peaks_hz": [{"frequency_hz": p.frequency, f"rms_{u}": p.rms, "ratio": p.ratio} for p in r.peaks_hz],
        "peaks_order": [
            {"cycles_per_rev": p.frequency, f"rms_{u}": p.rms, "ratio": p.ratio} for p in r.peaks_order
        ],
        "segments": r.segments,
        "order_segments": r.order_segments,
    }


def _terms(ident: Identification) -> dict[str, Any]:
    """The law's terms on, what was fitted and held (with the held values), what the choice switched
    off, and the fitted parameters stuck at their lower bound."""
    choice = ident.choice
    values = ident.fit.values.as_dict()
    held = choice.held if choice is not None else ()
    return {
        "on": list(choice.terms if choice is not None else ident.params.terms),
        "fitted": list(ident.fit.fitted),
        "held": {name: values[name] for name in held},
        "switched_off": list(choice.switched_off if choice is not None else ()),
        "at_bound": list(ident.at_bound),
    }


def _bound_warnings(ident: Identification) -> list[str]:
    std = ident.uncertainty.std
    return [
        f"{name} = 0 {PARAMETER_UNITS[name]} is at its lower bound (σ {std.get(name, math.nan):.3g} "
        f"{PARAMETER_UNITS[name]}): the log does not support this term, or the model lacks another one"
        for name in ident.at_bound
    ]


def _delay_warning(ident: Identification) -> list[str]:

    delay = ident.delay
    if delay is None or delay.resolvable:
        return []
    return [f"the torque/position offset is {delay.describe()}"]


def report_markdown(report: dict[str, Any]) -> str:
    """The report for people: parameters with σ, errors refit against nominal, warnings, the log."""
    kind = JointKind(report["log"]["joint_kind"])
    unit, key = kind.effort_unit, kind.effort_key
    log = report["log"]
    lines = [
        "# Friction refit",
        "",
        f"Log: {', '.join(log['paths'])}, topic `{log['topic']}`, joint `{log['joint']}` "
        f"({log['samples']} samples, {log['duration_s']:.1f} s{_window_text(log.get('window'))})"
        + _drive_text(log.get("drive"))
        + ".",
        "",
        "| parameter | refit | σ | nominal | change |",
        "|---|---:|---:|---:|---:|",
    ]
    for name, p in report["parameters"].items():
        change = f"{(p['value'] - p['initial']) / p['initial'] * 100.0:+.2f} %" if p["initial"] else "–"
        lines.append(
            f"| {name} [{p['unit']}] | {p['value']:.6g} | {p['std']:.3g} | {p['initial']:.6g} | {change} |"
        )
    terms = report.get("terms")
    if terms:
        held = ", ".join(f"{k} = {v:.6g}" for k, v in terms["held"].items()) or "none"
        off = f"; switched off (nothing fitted or given): {', '.join(terms['switched_off'])}"
        lines += [
            "",
            f"Terms of the friction law on: {', '.join(terms['on']) or 'none'}; held at your values: {held}"
            + (off if terms["switched_off"] else "")
            + ".",
        ]
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
    lines += (
        _extra_lines(report) + _unexplained_lines(report, unit, key) + selection_markdown(report, unit, key)
    )
    s, delay, solver = report["samples"], report["torque_delay_s"], report["solver"]
    unc, velocity = report["uncertainty"], report["velocity"]
    if delay["estimated"] and delay["resolvable"]:
        delay_text = f"{delay['value'] * 1e3:.3f} ± {delay['std'] * 1e3:.3f} ms (estimated)"
    elif delay["estimated"]:
        shown = "∞" if delay["std"] is None else f"{delay['std'] * 1e3:.3f}"
        delay_text = (
            f"not resolvable from this log ({delay['estimate'] * 1e3:.3f} ± {shown} ms against a sample "
            f"period of {delay['period'] * 1e3:.3g} ms); 0 used"
        )
    else:
        delay_text = f"{delay['value'] * 1e3:.3f} ms (given)"
    lag = velocity["logged_lag_s"]
    logged = (
        "the log has none"
        if not velocity["logged"]
        else "the log's own velocity is not used"
        + (f" (it lags that derivative by {lag * 1e3:.2f} ms)" if lag is not None else "")
    )
    lines += [
        "",
        f"Samples: {s['used']} of {s['total']} used ({s['stationary']} stationary, {s['saturated']} "
        f"saturated, {s['trimmed']} trimmed at the edges, {s['non_finite']} not finite, {s['missing']} "
        f"missing in {s['holes']} holes (longest {s['longest_hole_s'] * 1e3:.0f} ms) and {s['near_holes']} "
        f"within a filter's reach of one); {s['fitted']} fitted after decimation.",
        f"Velocity: {velocity['used'].split(';')[0]}; {logged}.",
        f"Torque/position offset: {delay_text}.",
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
    table = report.get("effort_table")
    if table:
        lines += [
            "",
            f"Every sample's kinematics, measured and model force and each term's share: {table['file']} "
            f"({table['rows']} rows; pandas, polars or duckdb read it).",
        ]
    t = report["timing_s"]
    lines += [
        "",
        f"Timing: read {t['read']:.2f} s, prepare {t['prepare']:.2f} s, select {t.get('select', 0.0):.2f} s, "
        f"solve {t['solve']:.2f} s, "
        f"judge {t.get('judge', 0.0):.2f} s, total {t['total']:.2f} s.",
    ]
    return "\n".join(lines) + "\n"


def _extra_lines(report: dict[str, Any]) -> list[str]:
    lines = []
    combination = report.get("coulomb_combination")
    if combination:
        lines += [
            "",
            f"Coulomb force at speed, {combination['name']} = {combination['value']:.6g} ± "
            f"{combination['std']:.3g} N (nominal {combination['initial']:.6g} N): determined even where a1 "
            "and a3 are not separately.",
        ]
    stroke = report["extra_terms"]["stroke"]
    if stroke:
        lo, hi = stroke["stretch_m"]
        terms = ", ".join(
            f"{n} {c['value']:+.3g} ± {c['std']:.2g}" for n, c in stroke["coefficients"].items()
        )
        lines += [
            "",
            f"Coulomb friction along the stroke (Legendre terms over {lo:.3f}…{hi:.3f} m, a1 is their "
            f"average): {terms} N; it varies by up to {stroke['variation_pct']:.2f} % of a1.",
        ]
    cogging = report["extra_terms"]["cogging"]
    if cogging:
        parts = ", ".join(
            f"order {n}: {c['amplitude_nm'] * 1e3:.2f} ± {c['std_nm'] * 1e3:.2f} mN·m "
            f"at {c['phase_rad']:+.2f} rad"
            + (" (found in the residual)" if c.get("found_in_residual") else "")
            for n, c in cogging.items()
        )
        lines += ["", f"Cogging, fitted beside eq. (1): {parts}."]
    return lines


def _unexplained_lines(report: dict[str, Any], unit: str, key: str) -> list[str]:
    u = report["unexplained"]
    floor = u[f"noise_floor_{key}"]
    if floor is None:
        return ["", "Unexplained effort: no stretch of the log was long enough for a spectrum."]
    lo, hi = u["floor_band_hz"]
    lines = [
        "",
        f"Unexplained effort: RMS {u[f'rms_{key}']:.4g} {unit} unfiltered, {u[f'rms_filtered_{key}']:.4g} "
        f"{unit} filtered; noise floor {floor:.4g} {unit} (filtered; the residual's median level over "
        f"{lo:g}–{hi:g} Hz through the filter)"
        + (f"; fit error / floor {u['fit_over_floor']:.2f}" if u["fit_over_floor"] is not None else "")
        + (
            f", validation error / floor {u['validation_over_floor']:.2f}"
            if u["validation_over_floor"] is not None
            else ""
        )
        + ".",
    ]
    if u["peaks_hz"]:
        peaks = ", ".join(
            f"{p['frequency_hz']:.1f} Hz ({p[f'rms_{key}']:.3g} {unit}, ×{p['ratio']:.1f})"
            for p in u["peaks_hz"]
        )
        lines.append(f"Residual peaks in time: {peaks}.")
    if u["peaks_order"]:
        peaks = ", ".join(
            f"{p['cycles_per_rev']:.1f}/rev ({p[f'rms_{key}']:.3g} {unit}, ×{p['ratio']:.1f})"
            for p in u["peaks_order"]
        )
        lines.append(
            f"Residual peaks in cycles per motor revolution: {peaks} (cogging or torque ripple; what is "
            "fitted is fitted below the filter's cut-off, the raw torque keeps it above)."
        )
    return lines


def params_file(ident: Identification) -> str:
    """``params.toml``: a complete parameter file with the refit values (every ``--params`` takes it)."""
    fitted = ", ".join(ident.fit.fitted)
    sources = ", ".join(log.signals.source for log in ident.logs)
    head = (
        f"# Refit by `axisflow identify` from {sources}: {fitted}.\n"
        "# A refit M_eq is written as the cart mass m (rotor, gearbox and pulley inertias stay nominal).\n"
    )
    return head + params_to_toml(ident.params)


def _drive_text(drives: list[str | None] | None) -> str:
    known = sorted({d for d in drives or [] if d})
    return f"; recorded on the {', '.join(known)}" if known else ""


def _window_text(window: dict[str, Any] | None) -> str:
    if not window:
        return ""
    start = "the start" if window["start_s"] is None else f"{window['start_s']:g} s"
    end = "the end" if window["end_s"] is None else f"{window['end_s']:g} s"
    origin = "each log's first sample" if window["origin_ns"] is None else f"stamp {window['origin_ns']} ns"
    return f" from {start} to {end} after {origin}"
