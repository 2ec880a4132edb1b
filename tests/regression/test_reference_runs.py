"""Regression: the default and thesis profiles on a small versioned field against stored cusp statistics.

Truth data: tests/regression/data/expected.json, written by scripts/regenerate_regression_data.py and
regenerated only when a change is meant to change results (the commit says why). Each statistic has its own
relative tolerance in the file.

The field is stored (field.parquet) and the breaking is deterministic: the counts must match exactly and
the area statistics to 1e-9 relative (round-off of another build of GEOS, numba or libm, measured ≈ 1e-15).
Field generation does not depend on the CPU (fixed-order reductions), so the field generated here from the
stored field's parameters must be the stored field, polygon for polygon.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import shapely

import floebreak
from floebreak.ice.generation import generate_field
from floebreak.ice.observations import get_observation
from floebreak.output.field_files import load_field

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


def _outside(got: dict[str, float], expected: dict[str, float], tolerance: dict[str, float]) -> dict:
    """The statistics outside their relative tolerance, as (got, expected); 0 means exactly equal."""
    return {
        key: (got[key], value)
        for key, value in expected.items()
        if not math.isclose(got[key], value, rel_tol=tolerance[key], abs_tol=0.0)
    }


def _scenario(profile: str) -> dict:
    return {"profile": profile, "seed": 1, "field": {"file": str(DATA / EXPECTED["field_file"])}}


@pytest.mark.parametrize("name", sorted(EXPECTED["cases"]))
def test_cusp_statistics_match_the_stored_truth(name):
    case = EXPECTED["cases"][name]
    result = floebreak.run(_scenario(case["profile"]))
    got = _statistics(result)
    assert set(got) == set(case["expected"])
    assert all(case["relative_tolerance"][key] == 0.0 for key in ("n_cusps", "n_flipped", "n_breaks"))
    assert max(case["relative_tolerance"].values()) <= 1e-9
    off = _outside(got, case["expected"], case["relative_tolerance"])
    assert not off, f"{name}: (got, expected) outside the tolerance: {off}"
    # the area balance holds whatever the statistics (docs/model.md: area conserved through every break)
    assert result.summary["area_balance_rel_error"] < 1e-9


def test_the_field_generated_here_is_the_stored_field():
    """The stored field's parameters (scripts/regenerate_regression_data.py: observation 2019-12-18T20:20,
    150 m × 50 m, seed 7, h = 1 m) give the stored polygons and thicknesses exactly, on any CPU."""
    stored = load_field(DATA / EXPECTED["field_file"])
    observation = get_observation("2019-12-18T20:20")
    field = generate_field(observation, 150.0, 50.0, np.random.default_rng(7), thickness_m=1.0, seed=7)
    assert len(field.polygons) == len(stored.polygons)
    assert [shapely.to_wkb(p) for p in field.polygons] == [shapely.to_wkb(p) for p in stored.polygons]
    assert np.array_equal(field.thickness_m, stored.thickness_m)
