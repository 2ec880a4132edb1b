"""Shared test fixtures."""

from __future__ import annotations

import subprocess
import sys

import pytest


@pytest.fixture
def imported_by():
    """`imported_by(code, modules, *args)`: run `code` in a fresh interpreter (``sys.argv[1:]`` = args) and
    return which of `modules` it imported — for the tests that keep heavy imports off a path."""

    def run(code: str, modules: tuple[str, ...], *args) -> set[str]:
        probe = f"{code}\nimport sys\nprint(','.join(m for m in {tuple(modules)!r} if m in sys.modules))\n"
        out = subprocess.run(
            [sys.executable, "-c", probe, *map(str, args)], capture_output=True, text=True, check=True
        ).stdout
        return {name for name in out.strip().split(",") if name}

    return run
