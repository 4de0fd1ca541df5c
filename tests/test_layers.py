"""The layers of the README hold: every import (module level or inside a function) points down, the
top floor's rooms each have their place, and the records-and-logs layer loads no zenoh."""

import ast
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

# package folder → its layer. The floors below the top one (model … viz) are the library; the top
# floor, axisflow/, is rooms of their own, in order: experiment < nodes < deploy < savings < demo, then the
# benchmarks and the command line. A folder of axisflow/ missing here fails
# test_every_room_of_the_top_floor_has_its_place.
FOLDERS = {
    "model": "model",
    "planner": "planner",
    "acquisition": "acquisition",
    "identification": "identification",
    "viz": "viz",
    "fleet": "fleet",
    "benchmarks": "benchmarks",
    "axisflow/experiment": "experiment",
    "axisflow/nodes": "nodes",
    "axisflow/deploy": "deploy",
    "axisflow/savings": "savings",
    "axisflow/demo": "demo",
    "axisflow/cli": "cli",
    "axisflow": "loose",
}
# the loose modules of axisflow/ (at most six) and their layers
LOOSE = {"__init__": "package", "__main__": "cli", "arguments": "arguments"}
MAX_LOOSE = 6
FLOORS = {"model", "planner", "acquisition", "identification", "viz"}
# what each layer may import (besides itself); the README's layout table says the same
ALLOWED = {
    "model": set(),
    "planner": {"model"},
    "acquisition": {"model"},
    "identification": {"model", "acquisition"},
    "viz": {"model", "planner", "acquisition", "identification"},
    "fleet": {"model", "acquisition", "identification"},
    "experiment": FLOORS,
    "nodes": FLOORS | {"experiment"},
    "deploy": FLOORS | {"experiment", "nodes"},
    "savings": FLOORS | {"experiment", "nodes", "deploy"},
    "demo": FLOORS | {"experiment", "nodes", "deploy", "savings"},
    "arguments": FLOORS | {"experiment"},
    "benchmarks": FLOORS | {"fleet", "experiment", "nodes", "deploy", "savings", "demo", "arguments"},
    "cli": FLOORS
    | {"fleet", "experiment", "nodes", "deploy", "savings", "demo", "arguments", "benchmarks", "package"},
    "package": set(),
}
# the sub-package a dotted name under axisflow belongs to
SUBPACKAGES = {
    "model": "model",
    "planner": "planner",
    "acquisition": "acquisition",
    "identification": "identification",
    "viz": "viz",
    "fleet": "fleet",
    "benchmarks": "benchmarks",
    "experiment": "experiment",
    "nodes": "nodes",
    "deploy": "deploy",
    "savings": "savings",
    "demo": "demo",
    "cli": "cli",
    "arguments": "arguments",
    "__main__": "cli",
}
# acquisition's Zenoh side: the only acquisition modules that may use zenoh (folders, or folder/module)
NETWORK = {"bus", "bridge/bridge", "bridge/admission", "bridge/move_intake", "logs/recorder", "logs/replay"}


def _is_network(module: str) -> bool:
    """Whether a dotted module name under axisflow.acquisition is on the Zenoh side."""
    parts = module.split(".")[2:]
    return bool(parts) and (parts[0] in NETWORK or "/".join(parts[:2]) in NETWORK)


def _modules() -> list[tuple[Path, str, str]]:
    """(file, dotted module name, layer) of every module of the package."""
    out = []
    for folder, layer in FOLDERS.items():
        base = ROOT / folder
        pattern = "*.py" if folder == "axisflow" else "**/*.py"
        for path in sorted(base.glob(pattern)):
            rel = path.relative_to(base).with_suffix("")
            package = "axisflow" if folder == "axisflow" else f"axisflow.{folder.split('/')[-1]}"
            parts = [p for p in rel.parts if p != "__init__"]
            placed = LOOSE.get(path.stem, "unplaced") if layer == "loose" else layer
            out.append((path, ".".join([package, *parts]), placed))
    return out


def _layer_of(dotted: str) -> str | None:
    parts = dotted.split(".")
    if parts[0] != "axisflow":
        return None
    if len(parts) == 1 or parts[1] == "__version__":
        return "package"
    return SUBPACKAGES.get(parts[1], "unplaced")


def _imports(path: Path, module: str) -> list[tuple[int, str]]:
    """(line, absolute dotted target) of every import in a file."""
    tree = ast.parse(path.read_text("utf-8"))
    package = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            found.append((node.lineno, target))
            found += [(node.lineno, f"{target}.{alias.name}") for alias in node.names]
    return found


def test_every_import_points_down_the_layers():
    wrong = []
    modules = _modules()
    assert len(modules) > 40  # the walk found the package
    for path, module, layer in modules:
        for line, target in _imports(path, module):
            target_layer = _layer_of(target)
            if target_layer is None or target_layer == layer:
                continue
            if target_layer not in ALLOWED.get(layer, set()):
                wrong.append(f"{path.relative_to(ROOT)}:{line} ({layer}) imports {target} ({target_layer})")
    assert not wrong, "\n".join(wrong)


def test_every_room_of_the_top_floor_has_its_place():
    rooms = {p.parent.name for p in (ROOT / "axisflow").glob("*/__init__.py")}
    assert rooms == {folder.split("/")[1] for folder in FOLDERS if folder.startswith("axisflow/")}
    loose = sorted(p.stem for p in (ROOT / "axisflow").glob("*.py"))
    assert len(loose) <= MAX_LOOSE, f"axisflow/ has {len(loose)} loose modules (at most {MAX_LOOSE}): {loose}"
    assert set(loose) <= set(LOOSE), f"a loose module of axisflow/ without a layer: {set(loose) - set(LOOSE)}"


def test_only_the_network_modules_of_acquisition_touch_zenoh():
    wrong = []
    for path, module, layer in _modules():
        if layer != "acquisition" or _is_network(module) or module == "axisflow.acquisition":
            continue
        for line, target in _imports(path, module):
            network_module = target.startswith("axisflow.acquisition.") and _is_network(target)
            if target.split(".")[0] == "zenoh" or network_module:
                wrong.append(f"{path.relative_to(ROOT)}:{line} imports {target}")
    assert not wrong, "\n".join(wrong)


@pytest.mark.parametrize(
    "modules",
    [
        ["axisflow.acquisition"],
        [
            "axisflow.acquisition.logs.reader",
            "axisflow.acquisition.logs.synthetic_log",
            "axisflow.acquisition.logs.recover",
            "axisflow.acquisition.wire.messages",
            "axisflow.acquisition.drives.sim_axis",
            "axisflow.acquisition.bridge.move_queue",
        ],
        ["axisflow.identification", "axisflow.viz"],
    ],
)
def test_reading_logs_does_not_load_zenoh(modules):
    loaded = "sorted(m for m in sys.modules if m.split('.')[0] == 'zenoh')"
    code = f"import sys, {', '.join(modules)}; print({loaded})"
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True
    )
    assert out.stdout.strip() == "[]", out.stdout


def test_the_network_layer_is_loaded_on_first_use():
    code = (
        "import sys, axisflow.acquisition as a; before = 'zenoh' in sys.modules; a.MoveSender; "
        "print(before, 'zenoh' in sys.modules)"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True
    )
    assert out.stdout.split() == ["False", "True"]
