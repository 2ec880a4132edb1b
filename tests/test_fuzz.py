"""A small fixed sample of the fuzz campaign (`floebreak.fuzz`; the full campaign: `make fuzz N=5000`)."""

from __future__ import annotations

import json

from floebreak import fuzz
from floebreak.scenario import Scenario


def test_drawn_scenarios_are_valid_and_reproducible():
    first, again = fuzz.draw_scenarios(20, 7), fuzz.draw_scenarios(20, 7)
    assert first == again and len(first) == 20
    for data in first:
        Scenario.from_dict(data)  # every drawn scenario passes validation (the campaign tests the engine)


def test_fixed_sample_has_no_crash_or_violation(tmp_path):
    summary = fuzz.run_campaign(4, 3, 1, tmp_path, max_rss_mb=1024.0)
    assert summary["runs"] == 4
    assert summary["crash"] == 0 and summary["violations"] == 0 and summary["over_memory"] == 0, list(
        tmp_path.glob("case-*.toml")
    )
    assert json.loads((tmp_path / "summary.json").read_text())["runs"] == 4
