"""The packages load their public names on first use: importing a package (or one of its modules) loads
none of its other modules, every name it lists resolves, and the names a type checker sees (the imports
under ``TYPE_CHECKING``) are the names and homes that load at run time (``_HOMES``)."""

import ast
import importlib
import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

# package → its __init__.py
PACKAGES = {
    "axisflow.model": ROOT / "model" / "__init__.py",
    "axisflow.planner": ROOT / "planner" / "__init__.py",
    "axisflow.acquisition": ROOT / "acquisition" / "__init__.py",
    "axisflow.identification": ROOT / "identification" / "__init__.py",
    "axisflow.viz": ROOT / "viz" / "__init__.py",
    "axisflow.deploy.security": ROOT / "axisflow" / "deploy" / "security" / "__init__.py",
}


def _type_checking_homes(init: Path) -> dict[str, str]:
    """name → module (relative) of the ``from .module import name`` under ``if TYPE_CHECKING:``."""
    tree = ast.parse(init.read_text("utf-8"))
    blocks = [
        node
        for node in tree.body
        if isinstance(node, ast.If) and isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING"
    ]
    assert len(blocks) == 1, f"{init}: one `if TYPE_CHECKING:` block"
    homes = {}
    for node in blocks[0].body:
        assert isinstance(node, ast.ImportFrom) and node.level == 1, ast.unparse(node)
        for alias in node.names:
            assert alias.asname is None, ast.unparse(node)
            homes[alias.name] = node.module
    return homes


@pytest.mark.parametrize("package", sorted(PACKAGES))
def test_the_type_checker_sees_the_names_that_load(package):
    module = importlib.import_module(package)
    assert _type_checking_homes(PACKAGES[package]) == module._HOMES
    assert sorted(module.__all__) == sorted(module._HOMES)


@pytest.mark.parametrize("package", sorted(PACKAGES))
def test_every_public_name_resolves_from_its_home(package):
    module = importlib.import_module(package)
    for name, home in module._HOMES.items():
        value = getattr(module, name)
        assert value is getattr(importlib.import_module(f"{package}.{home}"), name), name
    with pytest.raises(AttributeError, match="no_such_name"):
        module.no_such_name  # noqa: B018


_PROBE = """
import json, sys
import {package}{use}
print(json.dumps(sorted(m for m in sys.modules if m.startswith("{package}."))))
"""


def _modules_loaded(package: str, use: str = "") -> list[str]:
    """The modules of ``package`` loaded in a fresh interpreter by importing it (and ``use``)."""
    code = _PROBE.format(package=package, use=use)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


@pytest.mark.parametrize("package", sorted(PACKAGES))
def test_importing_a_package_loads_none_of_its_modules(package):
    assert _modules_loaded(package) == []


def test_the_probe_sees_a_module_once_a_name_is_used():
    # the check above could pass by looking at the wrong thing: using a name does load its module
    assert _modules_loaded("axisflow.model", "; axisflow.model.AxisflowError") == ["axisflow.model.errors"]
