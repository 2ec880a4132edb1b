"""Where files are touched: the physics packages compute on arrays and dataclasses and read no files (the
known exceptions read shipped tables or a hull file, docs/architecture.md), and the pure analyses import no
file reader (`floebreak.app.inputs` resolves paths into data first)."""

from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src" / "floebreak"


def _modules() -> dict[str, Path]:
    modules = {}
    for path in SRC.rglob("*.py"):
        parts = list(path.relative_to(SRC.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        modules[".".join(parts)] = path
    return modules


# the physics packages compute on arrays and dataclasses; the files they need are read by io (or the
# application layer) and handed over as text or data
PHYSICS = (
    "floebreak.ice",
    "floebreak.ship",
    "floebreak.mechanics",
    "floebreak.failure",
    "floebreak.dynamics",
    "floebreak.engine",
    "floebreak.config.profiles",
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


# the analyses take FemTables, TorqueSeries and ShaftLines; the files behind them (a user's path, a shipped
# table, a built-in line's name) are resolved by the application layer (`floebreak.app.inputs`)
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
