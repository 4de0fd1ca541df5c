"""A refit written to a folder: what ``axisflow identify`` and the demo hand to users."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

from .identification.refit import Identification, IdentifySettings, identify
from .identification.report import params_file, report_json, report_markdown
from .model import AxisParams
from .model.files import ensure_dir, write_atomic
from .viz.identification_figure import identification_png

REFIT_FILES = ("params.toml", "report.json", "report.md", "fit.png")


def identify_to(
    out: str | Path,
    paths: Sequence[str | Path],
    nominal: AxisParams,
    settings: IdentifySettings | None = None,
    validate: Sequence[str | Path] = (),
) -> tuple[Identification, dict]:
    """Refit from ``paths`` and write :data:`REFIT_FILES` into ``out`` (each atomically, after the whole
    refit succeeded: a failure writes nothing). Returns the result and report.json's content."""
    ident = identify(paths, nominal, settings, validate)
    report = report_json(ident)
    markdown = report_markdown(report)
    figure = identification_png(ident.traces())
    folder = ensure_dir(out)
    write_atomic(folder / "params.toml", params_file(ident))
    write_atomic(folder / "report.json", json.dumps(report, indent=1) + "\n")
    write_atomic(folder / "report.md", markdown)
    write_atomic(folder / "fit.png", figure)
    return ident, report
