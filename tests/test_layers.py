"""The package plan of docs/architecture.md, checked on the import graph of src/floebreak built from the
source with `ast`: every import counts (module level, inside functions, and under ``if TYPE_CHECKING:``).
Packages import one way, down the plan; no file imports itself through others; there are no exceptions."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "floebreak"

# the plan, from the bottom up: a module may import its own package and the packages listed before it
PLAN = (
    "floebreak.data",  # shipped tables
    "floebreak.constants",
    "floebreak.errors",
    "floebreak.exit_codes",
    "floebreak.io",  # the leaf: atomic writes, GeoParquet, NetCDF, text, provenance; no model type
    "floebreak.ice",  # things and processes of the physics, each below the ones that use it
    "floebreak.mechanics",
    "floebreak.failure",
    "floebreak.dynamics",
    "floebreak.ship",
    "floebreak.propeller",
    "floebreak.shaft",
    "floebreak.engine",  # the stepping loop, its events, records and ice motions
    "floebreak.config",  # scenario and profiles, resolved into the settings of the packages above
    "floebreak.plotting",  # draws the domain objects
    "floebreak.output",  # what a run and an analysis write
    "floebreak.app",  # read, compute, write: run, propeller, shaft, replay
    "floebreak.studies",
    "floebreak.validation",
    "floebreak.api",
    "floebreak.testing",
    "floebreak.cli",
    "floebreak.__main__",
    "floebreak",  # the package's __init__: the public names, imported on first use
)


def _modules() -> dict[str, Path]:
    modules = {}
    for path in SRC.rglob("*.py"):
        parts = list(path.relative_to(SRC.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        modules[".".join(parts)] = path
    return modules


def _targets(module: str, is_package: bool, node: ast.Import | ast.ImportFrom, modules) -> set[str]:
    if isinstance(node, ast.Import):
        names = [alias.name for alias in node.names]
    else:
        if node.level:
            base = module.split(".")[: len(module.split(".")) - node.level + (1 if is_package else 0)]
            prefix = ".".join(base + ([node.module] if node.module else []))
        else:
            prefix = node.module or ""
        # `from package import module` imports the module; `from module import name` the module
        names = [f"{prefix}.{a.name}" if f"{prefix}.{a.name}" in modules else prefix for a in node.names]
    out = set()
    for name in names:
        if name.split(".")[0] != "floebreak":
            continue
        while name not in modules and "." in name:
            name = name.rsplit(".", 1)[0]
        if name != module:
            out.add(name)
    return out


def import_graph() -> dict[str, set[str]]:
    modules = _modules()
    graph = {}
    for module, path in modules.items():
        edges: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import | ast.ImportFrom):
                edges |= _targets(module, path.name == "__init__.py", node, modules)
        graph[module] = edges
    return graph


def package(module: str) -> str:
    """The entry of PLAN a module belongs to (the longest matching prefix)."""
    prefixes = [p for p in PLAN if module == p or module.startswith(p + ".")]
    return max(prefixes, key=len)


def rank(module: str) -> int:
    return PLAN.index(package(module))


def upward_imports(graph: dict[str, set[str]]) -> set[tuple[str, str]]:
    """Imports of a package listed after the importer's own in PLAN."""
    return {
        (module, target)
        for module, targets in graph.items()
        for target in targets
        if rank(target) > rank(module)
    }


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan), each a file cycle."""
    index, low, stack, on_stack, components = {}, {}, [], set(), []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for target in graph.get(node, ()):
            if target not in index:
                visit(target)
                low[node] = min(low[node], low[target])
            elif target in on_stack:
                low[node] = min(low[node], index[target])
        if low[node] == index[node]:
            component = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.append(member)
                if member == node:
                    break
            if len(component) > 1:
                components.append(sorted(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return components


def test_every_module_has_a_place_in_the_plan():
    top_level = {m for m in _modules() if m.count(".") == 1}
    assert top_level <= set(PLAN), f"add to PLAN and docs/architecture.md: {top_level - set(PLAN)}"


def test_packages_import_one_way_down_the_plan():
    upward = upward_imports(import_graph())
    assert not upward, "imports up the plan (docs/architecture.md):\n" + "\n".join(
        f"{a} -> {b}" for a, b in sorted(upward)
    )


def test_no_file_circles():
    assert cycles(import_graph()) == []


def test_at_most_eight_top_level_modules():
    files = sorted(p.name for p in SRC.glob("*.py"))
    assert len(files) <= 8, files


@pytest.mark.parametrize(
    ("graph", "expected"),
    [
        ({"a": {"b"}, "b": {"a"}, "c": {"a"}}, [["a", "b"]]),
        ({"a": {"b"}, "b": {"c"}, "c": {"a"}}, [["a", "b", "c"]]),
        ({"a": {"b"}, "b": set()}, []),
    ],
)
def test_the_cycle_finder_finds_cycles(graph, expected):
    assert cycles(graph) == expected


def test_the_checker_sees_function_level_type_checking_and_relative_imports(tmp_path, monkeypatch):
    # a hand-made package: the leaf `io` imports `app` inside a function, `app.high` imports `app.other`
    # relatively and `app.other` imports `app.high` for type checkers only
    package_dir = tmp_path / "floebreak"
    (package_dir / "io").mkdir(parents=True)
    (package_dir / "__init__.py").write_text("")
    (package_dir / "io" / "__init__.py").write_text("")
    (package_dir / "io" / "low.py").write_text("def f():\n    from floebreak.app import high\n")
    (package_dir / "app").mkdir()
    (package_dir / "app" / "__init__.py").write_text("")
    (package_dir / "app" / "high.py").write_text("from . import other\n")
    (package_dir / "app" / "other.py").write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from floebreak.app import high\n"
    )
    monkeypatch.setattr(f"{__name__}.SRC", package_dir)
    graph = import_graph()
    assert graph["floebreak.io.low"] == {"floebreak.app.high"}
    assert ("floebreak.io.low", "floebreak.app.high") in upward_imports(graph)
    assert cycles(graph) == [["floebreak.app.high", "floebreak.app.other"]]
