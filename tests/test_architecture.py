"""docs/architecture.md is what tools/import_graph.py reads from the source today, and it knows every
package the install has."""

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _tool():
    spec = importlib.util.spec_from_file_location("import_graph", ROOT / "tools" / "import_graph.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_architecture_page_is_current():
    tool = _tool()
    assert tool.PAGE.read_text(encoding="utf-8") == tool.architecture_page(), (
        "docs/architecture.md is out of date: run python tools/import_graph.py"
    )


def test_every_package_folder_is_installed():
    """A folder of Python modules under a package's folder that pyproject.toml does not list would be
    left out of an install (the editable one finds it anyway)."""
    installed = {folder for folder in _tool().packages().values()}
    found = {
        init.parent.relative_to(ROOT)
        for top in {folder.parts[0] for folder in installed}
        for init in (ROOT / top).rglob("__init__.py")
    }
    assert found <= installed, f"not in pyproject.toml's packages: {sorted(map(str, found - installed))}"
