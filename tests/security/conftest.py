"""Fixtures for the security tests: a secure folder (CA, roles, Zenoh files) on a free loopback port, a
second folder of another CA, an in-process router, and ``axisflow`` subprocesses."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest
from axisflow.acquisition.zenoh_config import ZenohOptions, open_session

from axisflow.security import SecurityPlan, init_security

CLI = [sys.executable, "-c", "import sys; from axisflow.cli import main; sys.exit(main())"]
ENV = {**os.environ, "CI": "1", "RUST_LOG": "error"}


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@dataclass(frozen=True)
class Secure:
    """A folder written by ``security init`` (and the port its router listens on)."""

    directory: Path
    port: int

    def config(self, name: str) -> Path:
        return self.directory / f"{name}.json5"

    def options(self, name: str, **kw: object) -> ZenohOptions:
        return ZenohOptions(config_file=self.config(name), **kw)


@pytest.fixture(scope="module")
def secure(tmp_path_factory) -> Secure:
    port = free_port()
    directory = tmp_path_factory.mktemp("secure") / "axis-security"
    init_security(SecurityPlan(directory, port=port, days=2))
    return Secure(directory, port)


@pytest.fixture(scope="module")
def other_ca(tmp_path_factory, secure) -> Secure:
    """Certificates of another CA (same roles, same router address): never admitted by ``secure``."""
    directory = tmp_path_factory.mktemp("other") / "axis-security"
    init_security(SecurityPlan(directory, port=secure.port, days=2))
    return Secure(directory, secure.port)


@pytest.fixture(scope="module")
def router(secure):
    """The secure router, in-process (a Python session in router mode), for the module's tests."""
    with open_session(secure.options("router")) as session:
        yield session


class Cli:
    """``axisflow`` subprocesses; every started one is killed after the test if still running."""

    started: list[subprocess.Popen] = []  # noqa: RUF012 (shared on purpose)

    @staticmethod
    def start(*args: str) -> subprocess.Popen:
        proc = subprocess.Popen(
            [*CLI, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV
        )
        Cli.started.append(proc)
        return proc

    @staticmethod
    def run(*args: str, timeout: float = 60.0) -> subprocess.CompletedProcess:
        return subprocess.run([*CLI, *args], capture_output=True, text=True, timeout=timeout, env=ENV)

    @staticmethod
    def finish(proc: subprocess.Popen, timeout: float = 30.0) -> tuple[str, str]:
        try:
            return proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            proc.kill()
            out, err = proc.communicate()
            pytest.fail(f"process did not exit within {timeout} s\nstdout:\n{out}\nstderr:\n{err}")

    @staticmethod
    def kill_leftovers() -> None:
        for proc in Cli.started:
            if proc.poll() is None:
                proc.kill()
                proc.communicate()
        Cli.started.clear()


@pytest.fixture(scope="session")
def cli() -> Cli:
    return Cli()


@pytest.fixture(autouse=True)
def _no_leftover_processes():
    yield
    Cli.kill_leftovers()
