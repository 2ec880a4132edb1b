"""The developers' guide: "functions short enough to read at once (≤ 80 lines)". Every function and method
of the package, its signature and docstring included, is checked here, so a long one fails `make test`
instead of waiting for a review."""

from __future__ import annotations

import ast
from pathlib import Path

import floebreak

MAX_LINES = 80
PACKAGE = Path(floebreak.__file__).resolve().parent


def long_functions(source: str, max_lines: int = MAX_LINES) -> list[tuple[str, int]]:
    """(name, lines) of every function in `source` longer than `max_lines`, decorators excluded."""
    tree = ast.parse(source)
    return [
        (node.name, node.end_lineno - node.lineno + 1)
        for node in ast.walk(tree)
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)
        and node.end_lineno - node.lineno + 1 > max_lines
    ]


def test_the_checker_finds_a_long_function():
    body = "\n".join(f"    x{i} = {i}" for i in range(80))
    assert long_functions(f"def f():\n{body}\n") == [("f", 81)]
    assert long_functions("def g():\n    return 1\n") == []


def test_no_function_in_the_package_is_over_80_lines():
    found = [
        f"{path.relative_to(PACKAGE)}: {name} ({lines} lines)"
        for path in sorted(PACKAGE.rglob("*.py"))
        for name, lines in long_functions(path.read_text(encoding="utf-8"))
    ]
    assert not found, "functions over 80 lines: " + "; ".join(found)
