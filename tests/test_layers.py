"""The layers of docs/architecture.md, checked on the import graph of src/floebreak built from the source
with `ast` (module-level and function-level imports; imports under ``if TYPE_CHECKING:`` are for type
checkers only and are left out): no module imports a layer above its own, and no two files import each
other, directly or through others."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "floebreak"

# layer rank (higher may import lower or equal), by module name prefix; the longest prefix decides
ENTRY, APP, COMPUTING, LEAF, BASE = 4, 3, 2, 1, 0
LAYERS = {
    # the command line, the public API and the tools built on it
    "floebreak": ENTRY,  # the package's __init__ (PEP 562 names) and anything not listed below
    "floebreak.__main__": ENTRY,
    "floebreak.cli": ENTRY,
    "floebreak.api": ENTRY,
    "floebreak.studies.cli": ENTRY,
    "floebreak.studies.validate_cli": ENTRY,
    "floebreak.fuzz": ENTRY,
    "floebreak.testing": ENTRY,
    # the application layer: reading + computing + writing; the study and voyage orchestration
    "floebreak.app": APP,
    "floebreak.replay": APP,
    "floebreak.studies.runner": APP,
    "floebreak.studies.inert": APP,
    "floebreak.studies.executors": APP,
    "floebreak.studies.aggregate": APP,
    "floebreak.studies.voyage": APP,
    "floebreak.studies.voyage_results": APP,
    "floebreak.studies.voyage_shaft": APP,
    "floebreak.studies.validation_report": APP,
    "floebreak.studies.sensitivity": APP,
    # the computing packages
    "floebreak.ice": COMPUTING,
    "floebreak.ship": COMPUTING,
    "floebreak.mechanics": COMPUTING,
    "floebreak.failure": COMPUTING,
    "floebreak.simulation": COMPUTING,
    "floebreak.simulation_events": COMPUTING,
    "floebreak.simulation_motion": COMPUTING,
    "floebreak.dynamics": COMPUTING,
    "floebreak.results": COMPUTING,
    "floebreak.profiles": COMPUTING,
    "floebreak.scenario": COMPUTING,
    "floebreak.propeller": COMPUTING,
    "floebreak.shaft": COMPUTING,
    "floebreak.studies": COMPUTING,  # design, field size, statements, scoring, single-floe matrix
    # the leaves: readers and writers, figures
    "floebreak.io": LEAF,
    "floebreak.plotting": LEAF,
    "floebreak.report": LEAF,
    # the base every layer may import
    "floebreak.constants": BASE,
    "floebreak.errors": BASE,
    "floebreak.exit_codes": BASE,
    "floebreak.data": BASE,
}

# io and plotting are siblings that do not know each other (figures are drawn by plotting and handed to io)
SIBLINGS_APART = (("floebreak.io", "floebreak.plotting"), ("floebreak.plotting", "floebreak.io"))

# upward imports that exist today, each a known debt (docs/architecture.md, "Known exceptions"); a new
# one fails the test, and a fixed one must be removed from here
KNOWN_UPWARD = {
    ("floebreak.io.field_files", "floebreak.ice.field"),  # the FloeField dataclass it reads and writes
    ("floebreak.io.voyage_log", "floebreak.ice.observations"),  # validates log rows as observations
    ("floebreak.io.voyage_log", "floebreak.propeller.spec"),
    ("floebreak.io.voyage_log", "floebreak.scenario"),
    ("floebreak.plotting.field", "floebreak.ice.field"),  # the FloeField dataclass it draws
    ("floebreak.plotting.propeller", "floebreak.propeller.iceclass"),  # draws curves it computes
    ("floebreak.plotting.propeller", "floebreak.propeller.interpolation"),
    ("floebreak.plotting.propeller", "floebreak.propeller.rates"),
    ("floebreak.plotting.propeller", "floebreak.propeller.ruleform"),
    ("floebreak.plotting.propeller", "floebreak.propeller.spectra"),
}


def _modules() -> dict[str, Path]:
    modules = {}
    for path in SRC.rglob("*.py"):
        parts = list(path.relative_to(SRC.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        modules[".".join(parts)] = path
    return modules


def _type_checking_blocks(tree: ast.AST) -> set[int]:
    """ids of the import nodes under ``if TYPE_CHECKING:``."""
    skipped = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            skipped.update(id(n) for child in node.body for n in ast.walk(child))
    return skipped


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
        tree = ast.parse(path.read_text(encoding="utf-8"))
        skipped = _type_checking_blocks(tree)
        edges: set[str] = set()
        for node in ast.walk(tree):
            if isinstance(node, ast.Import | ast.ImportFrom) and id(node) not in skipped:
                edges |= _targets(module, path.name == "__init__.py", node, modules)
        graph[module] = edges
    return graph


def layer(module: str) -> int:
    prefixes = [p for p in LAYERS if module == p or module.startswith(p + ".")]
    return LAYERS[max(prefixes, key=len)]


def upward_imports(graph: dict[str, set[str]]) -> set[tuple[str, str]]:
    found = set()
    for module, targets in graph.items():
        for target in targets:
            if layer(target) > layer(module):
                found.add((module, target))
            for low, high in SIBLINGS_APART:
                if module.startswith(low) and target.startswith(high):
                    found.add((module, target))
    return found


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


def test_no_module_imports_a_layer_above_its_own():
    new = upward_imports(import_graph()) - KNOWN_UPWARD
    assert not new, "upward imports (docs/architecture.md, layers):\n" + "\n".join(
        f"{a} -> {b}" for a, b in sorted(new)
    )


def test_the_known_exceptions_still_exist():
    # a debt paid off is removed from KNOWN_UPWARD, so that it cannot come back unnoticed
    assert KNOWN_UPWARD <= upward_imports(import_graph())


def test_no_file_cycles():
    assert cycles(import_graph()) == []


def test_io_and_the_computing_packages_follow_the_rules_of_the_issue():
    graph = import_graph()
    for module, targets in graph.items():
        if module.startswith("floebreak.io"):
            analyses = ("floebreak.propeller.pipeline", "floebreak.shaft")
            computing = {t for t in targets if t.startswith(analyses)}
            assert not computing, f"{module} runs an analysis: {computing}"
        if module.startswith(("floebreak.propeller", "floebreak.shaft")):
            assert not {t for t in targets if layer(t) > COMPUTING}, module


# the physics packages compute on arrays and dataclasses; the files they need are read by io (or the
# application layer) and handed over as text or data (issue 34)
PHYSICS = (
    "floebreak.ice",
    "floebreak.ship",
    "floebreak.mechanics",
    "floebreak.failure",
    "floebreak.dynamics",
    "floebreak.simulation",
    "floebreak.results",
    "floebreak.profiles",
    "floebreak.propeller",
    "floebreak.shaft",
)
# calls that touch a file (a name called, or a method of any object), and modules that read or write files
# (xarray builds datasets in memory too: its file access is `open_dataset` and `to_netcdf`)
FILE_CALLS = {"open", "read_text", "read_bytes", "write_text", "write_bytes", "read_csv", "to_csv", "savefig"}
FILE_CALLS |= {"loadtxt", "genfromtxt", "savetxt", "open_dataset", "to_netcdf", "read_parquet", "ParquetFile"}
FILE_CALLS |= {"read_table", "write_table"}
FILE_MODULES = ("importlib.resources", "pyarrow.parquet", "pyarrow.csv", "pyarrow.dataset", "h5netcdf")
# file reads that exist today in physics modules (known debts, docs/architecture.md)
KNOWN_FILE_ACCESS = {
    "floebreak.ice.observations",  # the shipped observation table (thesis Table 1)
    "floebreak.mechanics.nevel",  # the shipped Nevel table
    "floebreak.ship.bow",  # Bow.from_csv reads, Bow.to_csv writes a hull file
}


def file_access(path: Path) -> list[str]:
    """The file-touching calls and imports of one source file, as "line: what"."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            func = node.func
            name = getattr(func, "id", None) or getattr(func, "attr", "")  # f(...) or obj.f(...)
            if name in FILE_CALLS:
                found.append(f"{node.lineno}: {name}()")
        elif isinstance(node, ast.Import | ast.ImportFrom):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else [node.module or ""]
            if isinstance(node, ast.ImportFrom):
                names += [f"{node.module}.{a.name}" for a in node.names]
            found += [f"{node.lineno}: import {n}" for n in names if n.startswith(FILE_MODULES)]
    return found


def test_the_physics_packages_read_no_files():
    reads = {}
    for module, path in _modules().items():
        if module.startswith(PHYSICS) and module not in KNOWN_FILE_ACCESS:
            if found := file_access(path):
                reads[module] = found
    assert not reads, f"file access in physics modules (move it to io/ or app/): {reads}"
    known = {m: file_access(p) for m, p in _modules().items() if m in KNOWN_FILE_ACCESS}
    assert all(known.values()), f"a known file access was removed: drop it from KNOWN_FILE_ACCESS {known}"


def test_the_file_access_check_sees_calls_and_imports(tmp_path):
    source = tmp_path / "m.py"
    source.write_text(
        "import importlib.resources\nfrom pyarrow import parquet\n"
        "def f(p):\n    return p.read_text(), open(p), np.loadtxt(p), tomllib.loads(p)\n"
    )
    assert file_access(source) == [
        "1: import importlib.resources",
        "2: import pyarrow.parquet",
        "4: read_text()",
        "4: open()",
        "4: loadtxt()",
    ]


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


def test_the_checker_sees_function_level_and_relative_imports(tmp_path, monkeypatch):
    # a hand-made package: `low` (a leaf) imports `high` inside a function, `b` imports `a` relatively
    package = tmp_path / "floebreak"
    (package / "io").mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "io" / "__init__.py").write_text("")
    (package / "io" / "low.py").write_text("def f():\n    from floebreak.app import high\n")
    (package / "app").mkdir()
    (package / "app" / "__init__.py").write_text("")
    (package / "app" / "high.py").write_text("from . import other\n")
    (package / "app" / "other.py").write_text("from floebreak.app import high\n")
    monkeypatch.setattr(f"{__name__}.SRC", package)
    graph = import_graph()
    assert graph["floebreak.io.low"] == {"floebreak.app.high"}
    assert ("floebreak.io.low", "floebreak.app.high") in upward_imports(graph)
    assert cycles(graph) == [["floebreak.app.high", "floebreak.app.other"]]


# the analyses take FemTables, TorqueSeries and ShaftLines; the files behind them (a user's path, a shipped
# table, a built-in line's name) are resolved by the application layer (`floebreak.app.inputs`, issue 34)
ANALYSES = ("floebreak.propeller.pipeline", "floebreak.shaft.analysis")
READERS = {"read_fem_table", "shipped_fem_tables", "resolve_fem_tables", "read_torque_csv"}
READERS |= {"synthetic_torque_path", "load_shaft_line", "read_text_file", "read_package_data"}
READERS |= {"package_data_path", "read_run_cusps", "load_cusps"}


def reader_imports(path: Path) -> list[str]:
    """The text-file readers one source file imports (`floebreak.io.text_files` or a name in READERS)."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            names = [a.name for a in node.names]
            if (node.module or "").startswith("floebreak.io.text_files"):
                found.append(f"{node.lineno}: {node.module}")
            found += [f"{node.lineno}: {n}" for n in names if n in READERS]
        elif isinstance(node, ast.Import):
            found += [f"{node.lineno}: {a.name}" for a in node.names if a.name.startswith("floebreak.io")]
    return found


def test_the_analyses_import_no_file_readers():
    modules = _modules()
    found = {m: reader_imports(modules[m]) for m in ANALYSES}
    assert not any(found.values()), f"resolve files in floebreak.app, not in the analyses: {found}"


def test_the_reader_check_sees_reader_imports(tmp_path):
    source = tmp_path / "m.py"
    source.write_text(
        "from floebreak.io.text_files import read_text_file\n"
        "def f():\n    from floebreak.propeller.fem import FemTable, shipped_fem_tables\n"
    )
    assert reader_imports(source) == [
        "1: floebreak.io.text_files",
        "1: read_text_file",
        "3: shipped_fem_tables",
    ]
