"""The must-hold rows of the thesis scoreboard (issue 16 §1; marker `validation`, `make validate`).

Runs `floebreak validate thesis` as documented (both profiles, 16 common fields of the inferred thesis
field length, root seed 2023) once per session and asserts every row whose statement must hold in that
profile (`floebreak.studies.statements`: the thesis' large trends in every profile; its levels, ratios and
rough sizes in the `thesis` profile; small effects stay small). Sixteen fields, not the thesis' four: the
verdict is on the model's mean trend, and over four fields the smallest must-hold trends (a few per cent) are
within the field-to-field noise (docs/validation.md). Set FLOEBREAK_VALIDATE_DIR to a directory to keep (and
resume) the run between sessions, e.g. to check other seeds with FLOEBREAK_VALIDATE_SEED, or other numbers
of fields with FLOEBREAK_VALIDATE_FIELDS.
"""

from __future__ import annotations

import csv
import os

import pytest
from typer.testing import CliRunner

from floebreak.cli import app
from floebreak.studies.statements import STATEMENTS

pytestmark = pytest.mark.validation

PROFILES = ("default", "thesis")


@pytest.fixture(scope="session")
def scoreboard(tmp_path_factory) -> dict[str, dict[str, str]]:
    out = os.environ.get("FLOEBREAK_VALIDATE_DIR") or str(tmp_path_factory.mktemp("validate") / "out")
    seed = os.environ.get("FLOEBREAK_VALIDATE_SEED", "2023")
    n_fields = os.environ.get("FLOEBREAK_VALIDATE_FIELDS", "16")
    args = ["validate", "thesis", "--out", out, "--profile", "both", "--n-fields", n_fields, "--seed", seed]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    with open(os.path.join(out, "scoreboard.csv"), encoding="utf-8") as handle:
        return {row["id"]: row for row in csv.DictReader(handle)}


MUST_HOLD = [
    pytest.param(st.id, profile, id=f"{profile}-{st.id}")
    for st in STATEMENTS
    for profile in PROFILES
    if profile in st.must_hold
]


@pytest.mark.parametrize(("statement", "profile"), MUST_HOLD)
def test_must_hold_row_passes(scoreboard, statement, profile):
    row = scoreboard[statement]
    assert row[f"{profile}_verdict"] == "pass", (
        f"{statement} ({row['source']}: {row['quote']}): {row['quantity']} = {row[f'{profile}_ours']} "
        f"± {row[f'{profile}_se']}, thesis {row['thesis_text'] or row['thesis_value']}, "
        f"tolerance {row['tolerance']}"
    )
