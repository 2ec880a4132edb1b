"""The documentation describes the code as it is: no work-log references (an issue or session number) in the
docs, and every relative link in README.md and docs/**/*.md points to a file that exists."""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = sorted((ROOT / "docs").rglob("*.md"))
LINKED = [ROOT / "README.md", *DOCS]
WORDED = [ROOT / "README.md", ROOT / "benchmarks" / "README.md", *DOCS]

HISTORY_WORD = re.compile(r"\b(?:issue|session)s? #?\d+", re.IGNORECASE)
# [text](target) and ![alt](target); the target ends at whitespace or ")"
LINK = re.compile(r"!?\[[^\]]*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
FENCE = re.compile(r"^(```|~~~).*?^\1", re.MULTILINE | re.DOTALL)


def _rel(path: Path) -> str:
    return path.relative_to(ROOT).as_posix()


def history_words(text: str) -> list[str]:
    return [m.group(0) for m in HISTORY_WORD.finditer(text)]


def relative_targets(text: str) -> list[str]:
    """The link targets of a Markdown text that point into the repository (no scheme, no pure anchor),
    without their #fragment; links inside fenced code blocks are not links."""
    text = FENCE.sub("", text)
    targets = []
    for match in LINK.finditer(text):
        target = match.group(1)
        if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.IGNORECASE) or target.startswith("#"):
            continue
        targets.append(target.split("#", 1)[0])
    return targets


def test_the_checks_catch_what_they_are_for():
    # the numbered words are joined here so that this file does not itself carry them
    issue, session, issues = " ".join(["issue", "32"]), " ".join(["Session", "7"]), " ".join(["issues", "3"])
    assert history_words(f"as {issue} asks; {session} measured; {issues}") == [issue, session, issues]
    assert history_words("the sessions of Dask; issue tracker; Python session open") == []
    text = "[a](explanation/model.md#x) ![f](figures/a.png) [w](https://x.org/a.md) [s](#top)\n"
    text += "```\n[c](no.md)\n```\n"
    assert relative_targets(text) == ["explanation/model.md", "figures/a.png"]


@pytest.mark.parametrize("path", WORDED, ids=_rel)
def test_no_issue_or_session_numbers(path):
    found = history_words(path.read_text(encoding="utf-8"))
    assert not found, (
        f"{_rel(path)} names the work log: {found} (describe the code as it is; history goes to CHANGELOG.md)"
    )


@pytest.mark.parametrize("path", LINKED, ids=_rel)
def test_relative_links_point_to_existing_files(path):
    broken = [
        t for t in relative_targets(path.read_text(encoding="utf-8")) if t and not (path.parent / t).exists()
    ]
    assert not broken, f"{_rel(path)} links to files that do not exist: {broken}"


def test_the_docs_have_the_four_kinds_of_page():
    for part in ("tutorial.md", "how-to", "reference", "explanation"):
        assert (ROOT / "docs" / part).exists(), part
