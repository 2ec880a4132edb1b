"""Fixtures shared by the whole test suite."""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path

import pytest

from floebreak.cli import main

# the fuzz generators live outside the installed package (tools/fuzz, `make fuzz`)
TOOLS = str(Path(__file__).resolve().parents[1] / "tools")
if TOOLS not in sys.path:
    sys.path.insert(0, TOOLS)


@pytest.fixture
def cli(monkeypatch, capsys) -> Callable[..., tuple[int, str, str]]:
    """Run the command line in-process: ``code, out, err = cli("run", "s.toml", "--out", ...)``.

    The exit code is the one `floebreak` would return (0 when the command returns normally); the output
    is what it printed on stdout and stderr.
    """

    def run(*args: object) -> tuple[int, str, str]:
        monkeypatch.setattr(sys, "argv", ["floebreak", *map(str, args)])
        try:
            main()
            code = 0
        except SystemExit as exit_:
            code = exit_.code or 0
        captured = capsys.readouterr()
        return code, captured.out, captured.err

    return run
