"""Write docs/refusals.md, the page of what axisflow refuses, from the catalogue of bad inputs
(tests/bad_input/). Run from the repository's root: ``python tools/write_refusals_page.py``."""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from axisflow.model.files import write_atomic  # noqa: E402

from tests.bad_input.page import REFUSALS_PAGE, refusals_page  # noqa: E402

if __name__ == "__main__":
    write_atomic(REFUSALS_PAGE, refusals_page())
    print(f"wrote {REFUSALS_PAGE.relative_to(ROOT)}")
