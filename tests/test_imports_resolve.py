"""Every `from floebreak.X import name` in the package, the tools, scripts and benchmarks names something that
exists — the imports inside functions too, which only run when their function does (a moved or renamed name
would otherwise surface as an ImportError in a slow path, e.g. the scoreboard's propeller rows)."""

from __future__ import annotations

import ast
import importlib
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FOLDERS = ("src/floebreak", "tools", "scripts", "benchmarks")


def _from_imports():
    for folder in FOLDERS:
        for path in sorted((ROOT / folder).rglob("*.py")):
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                if (
                    isinstance(node, ast.ImportFrom)
                    and node.level == 0
                    and (node.module or "").startswith("floebreak")
                ):
                    yield path.relative_to(ROOT).as_posix(), node


def test_every_imported_floebreak_name_exists():
    missing = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)  # old paths stay importable for one release
        for where, node in _from_imports():
            module = importlib.import_module(node.module)
            for alias in node.names:
                if not hasattr(module, alias.name):
                    try:
                        importlib.import_module(f"{node.module}.{alias.name}")
                    except ImportError:
                        missing.append(f"{where}:{node.lineno} {node.module}.{alias.name}")
    assert missing == []
