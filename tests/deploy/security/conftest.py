"""Fixtures for the security tests: a secure folder (CA, roles, Zenoh files) on a free loopback port, a
second folder of another CA, an in-process router (``axisflow`` subprocesses: the `cli` fixture of
tests/conftest.py)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import pytest
from axisflow.acquisition.bus.session import ZenohOptions, open_session

from axisflow.deploy.security import SecurityPlan, init_security
from axisflow.deploy.security.roles import DEFAULT_ROLES

from ...conftest import free_port


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
    init_security(SecurityPlan(directory, port=port, days=2, roles=(*DEFAULT_ROLES, "adapter")))
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
