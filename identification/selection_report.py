"""The model selection's part of the report: the candidates' table, the choice and what the data support.

report.json gets ``structure`` {terms, chosen_by ("auto": the selection; "given": fixed terms),
dropped (terms the final fit did not support, dropped and fitted again without)} and ``selection``
(null with fixed terms) {rule, folds, validation_logs, samples, delay_s, chosen, best, threshold_<u>,
candidates [{terms, parameters, held_out_rms_<u>, held_out_se_<u>, fold_rms_<u>, validation_rms_<u>,
condition_number, parameters_std {name: σ}, estimates {name: value}, unsupported, eligible,
converged}], notes} with <u> the joint's effort unit key (``nm`` or ``n``).
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, Any

from .selection import RULE

if TYPE_CHECKING:
    from .refit import Identification


def structure_json(ident: Identification) -> dict[str, Any]:
    """The terms of the final fit: the law's that are on (fitted, or held at the file's value), then
    ``stroke`` and ``cogging`` if taken in."""
    law = ident.choice.terms if ident.choice is not None else ident.params.terms
    extra = ["stroke"] * bool(ident.extra.stroke_terms) + ["cogging"] * bool(ident.extra.cogging_orders)
    chosen_by = "auto" if ident.selection is not None else "given"
    return {"terms": [*law, *extra], "chosen_by": chosen_by, "dropped": list(ident.dropped)}


def selection_json(ident: Identification) -> dict[str, Any] | None:
    sel = ident.selection
    if sel is None:
        return None
    u = ident.kind.effort_key
    return {
        "rule": RULE,
        "folds": sel.folds,
        "validation_logs": sel.validation_logs,
        "samples": sel.samples,
        "delay_s": sel.delay_s,
        "chosen": sel.chosen.label,
        "best": sel.best.label,
        f"threshold_{u}": sel.threshold,
        "candidates": [
            {
                "terms": list(c.structure.terms),
                "parameters": c.parameters,
                f"held_out_rms_{u}": c.mean,
                f"held_out_se_{u}": c.standard_error,
                f"fold_rms_{u}": list(c.fold_rms),
                f"validation_rms_{u}": list(c.validation_rms),
                "condition_number": c.condition_number,
                "parameters_std": dict(c.std),
                "estimates": dict(c.estimates),
                "unsupported": list(c.unsupported),
                "eligible": c.eligible,
                "converged": c.converged,
            }
            for c in sel.candidates
        ],
        "notes": list(sel.notes),
    }


def selection_markdown(report: dict[str, Any], unit: str, key: str) -> list[str]:
    """The report.md lines of the selection (none with fixed terms)."""
    structure, sel = report.get("structure"), report.get("selection")
    lines = []
    if structure and structure["dropped"]:
        lines += [
            "",
            f"Dropped after the final fit (σ larger than the value): {', '.join(structure['dropped'])}.",
        ]
    if not sel:
        return lines
    scored = f"{sel['folds']} time-blocked folds" + (
        f" and {sel['validation_logs']} validation log{'s' * (sel['validation_logs'] > 1)}"
        if sel["validation_logs"]
        else ""
    )
    lines += [
        "",
        "## Model selection",
        "",
        f"Candidates fitted on {sel['samples']} samples and scored on held-out data ({scored}); "
        f"{sel['rule']}: the simplest eligible candidate within {sel[f'threshold_{key}']:.4g} {unit} (the "
        f"best's mean plus its standard error). Chosen: **{sel['chosen']}**.",
        "",
        f"| terms | parameters | held-out error [{unit}] | condition number | σ of each parameter | |",
        "|---|---:|---:|---:|---|---|",
    ]
    for c in sel["candidates"]:
        label = "+".join(c["terms"])
        stds = c["parameters_std"]
        std = ", ".join(f"{n} {s:.3g}" for n, s in stds.items() if not _is_extra(n))
        extra = [s for n, s in stds.items() if _is_extra(n)]
        if extra:
            std += f", extra terms' ≤ {max(extra):.3g}"
        mark = []
        if label == sel["chosen"]:
            mark.append("**chosen**")
        if label == sel["best"] and label != sel["chosen"]:
            mark.append("lowest error")
        if c["unsupported"]:
            mark.append("not supported: " + ", ".join(c["unsupported"]))
        if not c["converged"]:
            mark.append("did not converge")
        lines.append(
            f"| {label} | {c['parameters']} | {c[f'held_out_rms_{key}']:.4g} ± {c[f'held_out_se_{key}']:.2g} "
            f"| {c['condition_number']:.3g} | {std} | {'; '.join(mark)} |"
        )
    lines += ["", *(f"- {note}" for note in sel["notes"])]
    return lines


def _is_extra(name: str) -> bool:
    """A coefficient of the stroke (``c1``…) or cogging (``cog24_sin``…) terms."""
    return bool(re.fullmatch(r"c\d+|cog\d+_(sin|cos)", name))
