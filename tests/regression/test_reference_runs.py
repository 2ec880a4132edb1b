"""Regression: the default and thesis profiles on a small versioned field against stored cusp statistics.

Truth data: tests/regression/data/expected.json, written by scripts/regenerate_regression_data.py and
regenerated only when a change is meant to change results (the commit says why). The field is stored, not
generated, so the check does not depend on the BLAS kernels the field packing uses. Each statistic has its
own relative tolerance in the file.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import floebreak

DATA = Path(__file__).parent / "data"
EXPECTED = json.loads((DATA / "expected.json").read_text(encoding="utf-8"))


def _statistics(result) -> dict[str, float]:
    areas = np.asarray(result.cusps["area_m2"], dtype=float)
    return {
        **{key: result.summary[key] for key in ("n_cusps", "n_flipped", "n_breaks")},
        **{key: result.summary[key] for key in ("cusp_area_m2", "flipped_area_m2", "mean_cusp_area_m2")},
        "median_cusp_area_m2": float(np.median(areas)),
        "p90_cusp_area_m2": float(np.quantile(areas, 0.9)),
    }


@pytest.mark.parametrize("name", sorted(EXPECTED["cases"]))
def test_cusp_statistics_match_the_stored_truth(name):
    case = EXPECTED["cases"][name]
    scenario = {"profile": case["profile"], "seed": 1, "field": {"file": str(DATA / EXPECTED["field_file"])}}
    result = floebreak.run(scenario)
    got = _statistics(result)
    assert set(got) == set(case["expected"])
    off = {
        key: (got[key], expected)
        for key, expected in case["expected"].items()
        if got[key] != pytest.approx(expected, rel=case["relative_tolerance"][key])
    }
    assert not off, f"{name}: (got, expected) outside the tolerance: {off}"
    # the area balance holds whatever the statistics (docs/model.md: area conserved through every break)
    assert result.summary["area_balance_rel_error"] < 1e-9
