"""docs/refusals.md, the page of what axisflow refuses, as the catalogue says it: written by
``python tools/write_refusals_page.py``, held to the catalogue by tests/cli/test_bad_input.py."""

from __future__ import annotations

from pathlib import Path

from . import CASES

REFUSALS_PAGE = Path(__file__).resolve().parents[2] / "docs" / "refusals.md"
"""the page, in the repository's docs/"""


def refusals_page() -> str:
    """docs/refusals.md as the catalogue says it (``python tools/write_refusals_page.py`` writes it)."""
    lines = [
        "# What axisflow refuses, and why",
        "",
        "Generated from the catalogue of bad inputs, `tests/bad_input/` (write it again with",
        "`python tools/write_refusals_page.py`; a test fails when it is out of date). Every input below is",
        "refused with exit code 2 and exactly one line on stderr, no traceback, nothing on stdout, and",
        "every file that existed before byte for byte what it was, with no stray temporary file; the",
        "test checks each of these, and that the line names what the last column lists (the value, the",
        "limit and its unit, where there are some). How the catalogue is run, and the faults injected",
        "beside it: [trust.md](trust.md).",
        "",
        f"{len(CASES)} inputs over {len({c.args[0] for c in CASES})} commands.",
    ]
    for command in sorted({c.args[0] for c in CASES}):
        lines += ["", f"## axisflow {command}", "", "| what | input | the line names |", "|---|---|---|"]
        for c in (c for c in CASES if c.args[0] == command):
            what = c.id.split(": ", 1)[-1]
            shown = " ".join(a if len(a) <= 40 else a[:37] + "…" for a in c.args)
            names = "; ".join(f"`{s}`" for s in c.says)
            row = [what, f"`axisflow {shown}`", names]
            lines.append(
                "| " + " | ".join(cell.replace("|", "\\|").replace("\n", " ") for cell in row) + " |"
            )
    return "\n".join(lines) + "\n"
