"""The ``axisflow`` command: one program, a subcommand per task.

Each subcommand lives in its own module with ``register(subparsers)``, which adds its parser and sets
``func`` to a ``run(args) -> int``. User errors (:class:`axisflow.model.AxisflowError`) and errors of
the file system about a path the user named (an ``OSError`` with a file name: a name too long, no
permission, a full disk) are printed as one line on stderr with exit code 2; warnings
(:class:`axisflow.model.AxisflowWarning`, e.g. a damaged chunk of a log that was skipped) as one line
each. SIGTERM and SIGHUP unwind the command like Ctrl-C (:mod:`.interrupts`), so that no temporary
file stays behind. Nothing else is caught.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import os
import sys
import threading
import warnings
from collections.abc import Callable, Sequence
from typing import NoReturn, TextIO

from .. import __version__
from ..deploy.processes import follow_launcher
from ..model import AxisflowError, AxisflowWarning
from .interrupts import Terminated, signals_unwind

# command modules, in the order --help lists them
COMMAND_MODULES: tuple[str, ...] = (
    "demo_cmd",
    "params_cmd",
    "plan_cmd",
    "experiment_cmd",
    "pareto_cmd",
    "savings_cmd",
    "bench_cmd",
    "bridge_cmd",
    "drive_sim_cmd",
    "record_cmd",
    "excite_cmd",
    "import_cmd",
    "identify_cmd",
    "fleet_cmd",
    "planner_cmd",
    "adapt_cmd",
    "stop_cmd",
    "ros2_cmd",
    "table2_cmd",
    "replay_cmd",
    "recover_cmd",
    "security_cmd",
    "router_cmd",
    "cell_cmd",
    "view_cmd",
    "figures_cmd",
)

EXIT_USER_ERROR = 2
QUIET_LIBRARIES = ("canopen", "can")
"""libraries whose own log lines are shown only with -v"""


class _Parser(argparse.ArgumentParser):
    """argparse's parser, with its errors as one line like every other user error (no usage block)."""

    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_USER_ERROR, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="axisflow",
        description="Fast, energy-aware point-to-point motion for a belt-driven linear axis.",
    )
    parser.add_argument("--version", action="version", version=f"axisflow {__version__}")
    parser.add_argument("-v", "--verbose", action="count", default=0, help="more log output (-vv: debug)")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name in COMMAND_MODULES:
        importlib.import_module(f"{__name__}.{name}").register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    follow_launcher()  # a child of axisflow's launcher ends with it (axisflow/deploy/processes.py)
    try:
        return _main(argv)
    except BrokenPipeError:
        # the reader of our output went away (`axisflow … | head`): not an error of ours; keep the
        # interpreter's final flush from raising again
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


def _main(argv: Sequence[str] | None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    logging.basicConfig(
        level=logging.WARNING - 10 * min(args.verbose, 2),
        format="%(asctime)s %(levelname)s %(name)s: %(message)s",
    )
    if not args.verbose:
        # canopen and python-can log every SDO retry and abort they make; our errors say what they meant
        for name in QUIET_LIBRARIES:
            logging.getLogger(name).setLevel(logging.CRITICAL)
    with signals_unwind(), warnings.catch_warnings():
        warnings.simplefilter("default", AxisflowWarning)
        warnings.showwarning = _warning_printer(args.command, warnings.showwarning)
        try:
            return int(args.func(args) or 0)
        except AxisflowError as exc:
            print(f"axisflow {args.command}: error: {exc}", file=sys.stderr)
            return EXIT_USER_ERROR
        except OSError as exc:
            if exc.filename is None:
                raise
            print(f"axisflow {args.command}: error: {_os_error_line(exc)}", file=sys.stderr)
            return EXIT_USER_ERROR
        except Terminated as exc:
            print(f"axisflow {args.command}: stopped by {exc}", file=sys.stderr)
            return exc.exit_code
        except KeyboardInterrupt:
            print(f"axisflow {args.command}: interrupted", file=sys.stderr)
            return 130


def _os_error_line(exc: OSError) -> str:
    """An error of the file system about a path as one line: the path(s) and the system's reason."""
    path = f"{exc.filename}" + (f" → {exc.filename2}" if exc.filename2 is not None else "")
    return f"{path}: {exc.strerror or exc}"


def _warning_printer(command: str, fallback: Callable[..., None]) -> Callable[..., None]:
    """A ``warnings.showwarning`` that prints axisflow's warnings as one line each (others as usual).

    Readers warn from several threads at once: each line goes out in one write under a lock, so two
    warnings never run together into one line."""
    lock = threading.Lock()

    def show(
        message: Warning | str,
        category: type[Warning],
        filename: str,
        lineno: int,
        file: TextIO | None = None,
        line: str | None = None,
    ) -> None:
        if issubclass(category, AxisflowWarning):
            with lock:
                sys.stderr.write(f"axisflow {command}: warning: {message}\n")
                sys.stderr.flush()
        else:
            fallback(message, category, filename, lineno, file, line)

    return show
