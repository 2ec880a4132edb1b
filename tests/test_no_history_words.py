"""Code and tests say why, not when: no "issue N" or "session N" in src/ or tests/ (history belongs in git and
the changelog)."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
HISTORY = re.compile(r"\b(?:[Ii]ssues? \d|[Ss]essions? \d)")


def history_words(path: Path) -> list[str]:
    """The lines of `path` with a history word, as "line: text"."""
    lines = path.read_text(encoding="utf-8").splitlines()
    return [f"{n}: {line.strip()}" for n, line in enumerate(lines, 1) if HISTORY.search(line)]


def _files() -> list[Path]:
    return [p for folder in ("src", "tests") for p in sorted((ROOT / folder).rglob("*.py"))]


def test_no_history_words_in_src_and_tests():
    found = {}
    for path in _files():
        if hits := history_words(path):
            found[path.relative_to(ROOT).as_posix()] = hits
    assert not found, f"say why, not which issue or session: {found}"


def test_the_check_sees_both_words(tmp_path):
    source = tmp_path / "m.py"
    issue, session = "is" + "sue 20", "Ses" + "sion 3"  # spelt apart, so that this file passes its own check
    source.write_text(f"# see {issue}\nx = 1  # {session} measured it\n# reissued 2 times is fine\n")
    assert history_words(source) == [f"1: # see {issue}", f"2: x = 1  # {session} measured it"]
