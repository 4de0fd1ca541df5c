"""Write docs/architecture.md: axisflow's packages, the folder each installs from, and the imports
between them, read from the source (every ``import`` and ``from … import``, at module level or inside a
function). Run from the repository's root: ``python tools/import_graph.py``; tests/test_architecture.py
fails when the page is out of date.

The repository keeps one top-level folder per concept (``model/``, ``acquisition/``, …) and installs
each as a sub-package of ``axisflow`` (``[tool.setuptools] package-dir`` in pyproject.toml). Tools that
read folders see ``from ..model import …`` in ``acquisition/`` point nowhere; this page is the map.
"""

from __future__ import annotations

import ast
import sys
import tomllib
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "architecture.md"

# the layers, bottom up, as tests/test_layers.py enforces them (a package belongs to its first-level one)
LAYERS = (
    ("model", "the shared model of the axis"),
    ("planner", "planning (beside acquisition)"),
    ("acquisition", "the data path (beside the planner)"),
    ("identification", "refits from recordings"),
    ("viz", "the views"),
    ("fleet", "a fleet of axes over months, on Dask (beside the top floor)"),
    ("experiment", "the top floor: the paper's experiment and its records"),
    ("nodes", "the top floor: programs that talk to a bridge"),
    ("deploy", "the top floor: processes, cells, security"),
    ("savings", "the top floor: what a user saves against the profiles drives run today"),
    ("demo", "the top floor: the demo and the adaptation experiment"),
    (
        "axisflow",
        "the loose modules of `axisflow/`: the version, the shared argument types, `python -m axisflow`",
    ),
    ("benchmarks", "the benchmarks and their rigs"),
    ("cli", "the command line"),
)


def packages() -> dict[str, Path]:
    """Every package of the install (pyproject.toml's ``packages``) and the folder it comes from."""
    tool = tomllib.loads((ROOT / "pyproject.toml").read_text("utf-8"))["tool"]["setuptools"]
    mapping: dict[str, str] = tool["package-dir"]
    out = {}
    for name in tool["packages"]:
        parts = name.split(".")
        # the longest mapped prefix gives the folder; the rest are folders below it
        for k in range(len(parts), 0, -1):
            prefix = ".".join(parts[:k])
            if prefix in mapping:
                out[name] = Path(mapping[prefix], *parts[k:])
                break
    return out


def _module_name(path: Path, package: str, folder: Path) -> str:
    rel = path.relative_to(ROOT / folder).with_suffix("")
    parts = [p for p in rel.parts if p != "__init__"]
    return ".".join([package, *parts])


def _imports(path: Path, module: str) -> list[str]:
    """The absolute dotted target of every import in a file (relative ones resolved)."""
    tree = ast.parse(path.read_text("utf-8"))
    package = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            found += [f"{target}.{alias.name}" for alias in node.names]
    return found


def _owner(dotted: str, names: list[str]) -> str | None:
    """The package (longest match) a dotted name belongs to, or None outside axisflow's packages."""
    for name in names:
        if dotted == name or dotted.startswith(name + "."):
            return name
    return None


def edges() -> tuple[dict[str, Path], Counter[tuple[str, str]], Counter[str]]:
    """(packages, imports between two packages counted per pair, modules per package)."""
    found = packages()
    names = sorted(found, key=len, reverse=True)
    pairs: Counter[tuple[str, str]] = Counter()
    modules: Counter[str] = Counter()
    for package, folder in found.items():
        for path in sorted((ROOT / folder).glob("*.py")):
            module = _module_name(path, package, folder)
            modules[package] += 1
            targets = {_owner(t, names) for t in _imports(path, module)}
            for target in sorted(t for t in targets if t is not None and t != package):
                pairs[(package, target)] += 1
    return found, pairs, modules


def _short(package: str) -> str:
    return package.removeprefix("axisflow.") if package != "axisflow" else "axisflow"


def _layer(package: str) -> str:
    parts = package.split(".")
    return parts[1] if len(parts) > 1 else "axisflow"


def architecture_page() -> str:
    """docs/architecture.md as the source says it."""
    found, pairs, modules = edges()
    order = [name for name, _what in LAYERS]
    ranked = sorted(found, key=lambda p: (order.index(_layer(p)) if _layer(p) in order else -1, p))
    lines = [
        "# Architecture: the packages and their imports",
        "",
        "Generated by `python tools/import_graph.py` from the source (a test fails when it is out of",
        "date). Each top-level folder of the repository installs as a sub-package of `axisflow`",
        "(`[tool.setuptools] package-dir` in pyproject.toml); the top floor's rooms are folders of",
        "`axisflow/`. Imports only go down the layers below (tests/test_layers.py checks every one).",
        "",
        "## Layers, bottom up",
        "",
        "| layer | what |",
        "|---|---|",
        *(f"| `{name}` | {what} |" for name, what in LAYERS),
        "",
        "## Packages",
        "",
        "| package | folder | modules | imports (packages, the modules that import them) |",
        "|---|---|---:|---|",
    ]
    for package in ranked:
        uses = sorted((t, n) for (s, t), n in pairs.items() if s == package)
        used = ", ".join(f"`{_short(t)}` {n}" for t, n in uses) or "–"
        lines.append(f"| `{package}` | `{found[package].as_posix()}/` | {modules[package]} | {used} |")
    lines += [
        "",
        "## The graph (sub-packages folded into their layer)",
        "",
        "```mermaid",
        "graph BT",
    ]
    layer_pairs: Counter[tuple[str, str]] = Counter()
    for (source, target), n in pairs.items():
        a, b = _layer(source), _layer(target)
        if a != b:
            layer_pairs[(a, b)] += n
    for (a, b), n in sorted(layer_pairs.items(), key=lambda e: (order.index(e[0][0]), order.index(e[0][1]))):
        lines.append(f"  {a} -->|{n}| {b}")
    lines += ["```", ""]
    return "\n".join(lines)


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT))
    from axisflow.model.files import write_atomic

    write_atomic(PAGE, architecture_page())
    print(f"wrote {PAGE.relative_to(ROOT)}")
