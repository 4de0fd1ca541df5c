"""Parsing a command line loads none of the heavy libraries: each verb loads them in its ``run()``.

Checked in a fresh interpreter (this one has loaded everything already): importing ``axisflow.cli``
and building the whole parser — every verb's options, every benchmark's — leaves the heavy libraries
out of ``sys.modules``; so does asking every command and benchmark for its ``--help``, which loads
neither the libraries of the data path (mcap and its codecs, cryptography, json5) nor axisflow's own
machinery (the demo, the experiment, the move queue, the log reader, the refit, the solvers). The
start-up times themselves are measured by ``axisflow bench startup``.
"""

import argparse
import json
import subprocess
import sys

import pytest

from axisflow.cli import build_parser

HEAVY = ("scipy", "casadi", "zenoh", "rerun", "matplotlib", "can", "canopen", "pyarrow", "h5py")
DATA_PATH_LIBRARIES = ("mcap", "zstandard", "lz4", "zlib_ng", "cryptography", "json5")
"""what the parsers loaded before their constants found light homes (issue 23, goal 3)"""
MACHINERY = (
    "axisflow.demo.loop",
    "axisflow.experiment.offline",
    "axisflow.experiment.table2",
    "axisflow.acquisition.bridge.move_queue",
    "axisflow.acquisition.drives.drive",
    "axisflow.acquisition.drives.plant",
    "axisflow.acquisition.logs.mcap_writer",
    "axisflow.acquisition.logs.reader",
    "axisflow.acquisition.foreign",
    "axisflow.identification.refit",
    "axisflow.planner.exact",
    "axisflow.planner.reference_laws",
    "axisflow.deploy.security.certificates",
)
"""axisflow's own modules that a command runs but no parser needs"""

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


_HELP_PROBE = """
import contextlib, io, json, sys
from axisflow.cli import main

libraries, machinery = set(sys.argv[2].split(",")), set(sys.argv[3].split(","))
first = {}  # heavy module -> the first command whose --help loaded it
for words in json.loads(sys.argv[1]):
    with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit):
        main([*words, "--help"])
    for name in list(sys.modules):
        if name.split(".")[0] in libraries or name in machinery:
            first.setdefault(name, " ".join(["axisflow", *words, "--help"]))
print(json.dumps(first))
"""


def _command_words(parser=None, prefix=()):
    """The words of every command and sub-command (``("bench", "planner")``), from the parser."""
    parser = parser or build_parser()
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield [*prefix, name]
                yield from _command_words(sub, (*prefix, name))


def _loaded_by_help(
    commands: list[list[str]], libraries: tuple[str, ...], machinery: tuple[str, ...]
) -> dict:
    argv = [json.dumps(commands), ",".join(libraries), ",".join(machinery)]
    out = subprocess.run(
        [sys.executable, "-c", _HELP_PROBE, *argv], capture_output=True, text=True, timeout=300
    )
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_every_help_loads_no_heavy_library_and_no_machinery():
    commands = [[], *_command_words()]
    assert ["bench", "startup"] in commands and ["identify"] in commands  # the walk found them all
    loaded = _loaded_by_help(commands, HEAVY + DATA_PATH_LIBRARIES, MACHINERY)
    assert loaded == {}, "\n".join(f"{name} loaded by {command}" for name, command in sorted(loaded.items()))


def test_the_help_probe_sees_what_a_command_loads_when_it_runs(tmp_path):
    # the check above could pass by looking at the wrong thing: recover, run for real, loads the
    # log reader and the MCAP writer (and refuses the missing file)
    probe = _HELP_PROBE.replace('main([*words, "--help"])', "main(words)")
    out = subprocess.run(
        [
            sys.executable,
            "-c",
            probe,
            json.dumps([["recover", "no-such.mcap", "-o", "out.mcap"]]),
            "mcap",
            "",
        ],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=tmp_path,
    )
    assert out.returncode == 0, out.stderr
    assert list(tmp_path.iterdir()) == []  # it refused, writing nothing
    assert "mcap" in json.loads(out.stdout.strip().splitlines()[-1])


_BENCHMARKS_PROBE = """
import contextlib, io, json, sys
from axisflow.cli import main

loaded = []
for words in json.loads(sys.argv[1]):
    with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit):
        main(words)
    loaded.append(sorted(m for m in sys.modules if m.startswith("axisflow.benchmarks.")))
print(json.dumps(loaded))
"""


def test_a_benchmark_loads_when_it_is_named_and_not_before():
    commands = [["--help"], ["bench", "--help"], ["bench", "startup", "--help"]]
    out = subprocess.run(
        [sys.executable, "-c", _BENCHMARKS_PROBE, json.dumps(commands)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout) == [[], [], ["axisflow.benchmarks.startup"]]


def test_the_list_of_benchmarks_shows_each_docstring_as_its_module_has_it():
    import importlib

    from axisflow.cli.bench_cmd import BENCHMARKS, benchmark_docstring

    for module in BENCHMARKS.values():
        doc = importlib.import_module(f"axisflow.benchmarks.{module}").__doc__
        assert doc and benchmark_docstring(module) == doc, module
