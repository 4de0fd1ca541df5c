"""Parsing a command line loads none of the heavy libraries: each verb loads them in its ``run()``.

Checked in a fresh interpreter (this one has loaded everything already): importing ``axisflow.cli``
and building the whole parser — every verb's options, every benchmark's — leaves the heavy libraries
out of ``sys.modules``. The start-up times themselves are measured by ``axisflow bench startup``.
"""

import json
import subprocess
import sys

import pytest

HEAVY = ("scipy", "casadi", "zenoh", "rerun", "matplotlib", "can", "canopen")

_PROBE = """
import json, sys
import axisflow.cli
axisflow.cli.build_parser()
print(json.dumps(sorted(m for m in sys.modules if m.split(".")[0] in {heavy})))
"""


def _loaded_after(code: str) -> list[str]:
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True
    ).stdout
    return json.loads(out.strip().splitlines()[-1])


def test_building_the_parser_loads_no_heavy_library():
    assert _loaded_after(_PROBE.format(heavy=set(HEAVY))) == []


@pytest.mark.parametrize("library", ["zenoh", "scipy"])
def test_the_probe_sees_a_heavy_library_once_loaded(library):
    # the check above could pass by looking at the wrong thing: a verb's run() does load them
    probe = _PROBE.replace("axisflow.cli.build_parser()", f"axisflow.cli.build_parser(); import {library}")
    assert library in _loaded_after(probe.format(heavy=set(HEAVY)))
