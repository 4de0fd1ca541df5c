"""A refit written to a folder: what ``axisflow identify`` and the demo hand to users."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

from ..identification.effort_table import EFFORT_TABLE, write_effort_table
from ..identification.refit import Identification, IdentifySettings, identify
from ..identification.report import params_file, report_json, report_markdown
from ..model import AxisParams
from ..model.files import atomic_path, ensure_dir, write_atomic_files
from ..viz.identification_figure import identification_png

REFIT_FILES = ("params.toml", "report.json", "report.md", "fit.png", EFFORT_TABLE)


def identify_to(
    out: str | Path,
    paths: Sequence[str | Path],
    nominal: AxisParams,
    settings: IdentifySettings | None = None,
    validate: Sequence[str | Path] = (),
) -> tuple[Identification, dict]:
    """Refit from ``paths`` and write :data:`REFIT_FILES` into ``out`` (together and atomically, after
    the whole refit succeeded: a failure or a signal writes none of them; the per-sample table is
    written beside the others first and renamed into place last). Returns the result and
    report.json's content."""
    ident = identify(paths, nominal, settings, validate)
    report = report_json(ident)
    markdown = report_markdown(report)
    figure = identification_png(ident.traces())
    contents = (params_file(ident), json.dumps(report, indent=1) + "\n", markdown, figure)
    folder = ensure_dir(out)
    with atomic_path(folder / EFFORT_TABLE) as part:
        write_effort_table(part, ident)
        write_atomic_files(folder, dict(zip(REFIT_FILES[:-1], contents, strict=True)))
    return ident, report
