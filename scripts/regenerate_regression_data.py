"""Regenerate the regression truth data in tests/regression/data/ — only on purpose.

Usage:  python scripts/regenerate_regression_data.py [--field]

`expected.json` holds, per case (profile on the versioned field `field.parquet`), the cusp statistics of
the run and the tolerance each is checked with (tests/regression/test_reference_runs.py). Rerun this script
when a change to the model is meant to change results, say why in the commit, and commit the new file with
the change. `--field` also regenerates the field itself (observation 2019-12-18T20:20, 150 m × 50 m, seed
7, h = 1 m); the test also generates that field and requires it to equal the stored one (field generation
does not depend on the CPU: docs/model.md, fixed-order reductions).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

import floebreak
from floebreak.ice.generation import generate_field
from floebreak.ice.observations import get_observation
from floebreak.output.field_files import save_field

DATA = Path(__file__).resolve().parents[1] / "tests" / "regression" / "data"
FIELD_FILE = "field.parquet"
CASES = {"default": {"profile": "default"}, "thesis": {"profile": "thesis"}}
# relative tolerances on the stored field: the run is deterministic (the field is read, not generated), so
# counts are exact and the floating-point statistics agree to round-off
TOLERANCES = {
    "n_cusps": 0.0,
    "n_flipped": 0.0,
    "n_breaks": 0.0,
    "cusp_area_m2": 1e-9,
    "flipped_area_m2": 1e-9,
    "mean_cusp_area_m2": 1e-9,
    "median_cusp_area_m2": 1e-9,
    "p90_cusp_area_m2": 1e-9,
}


def scenario(case: dict) -> dict:
    """The scenario of a case: its profile on the stored field, the reference ship and step."""
    return {"profile": case["profile"], "seed": 1, "field": {"file": str(DATA / FIELD_FILE)}}


def statistics(result) -> dict[str, float]:
    """The checked statistics of a run (thesis Tables 5–8 columns and the cusp-area distribution)."""
    areas = np.asarray(result.cusps["area_m2"], dtype=float)
    summary = result.summary
    return {
        "n_cusps": summary["n_cusps"],
        "n_flipped": summary["n_flipped"],
        "n_breaks": summary["n_breaks"],
        "cusp_area_m2": summary["cusp_area_m2"],
        "flipped_area_m2": summary["flipped_area_m2"],
        "mean_cusp_area_m2": summary["mean_cusp_area_m2"],
        "median_cusp_area_m2": float(np.median(areas)),
        "p90_cusp_area_m2": float(np.quantile(areas, 0.9)),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--field", action="store_true", help="also regenerate the field file")
    args = parser.parse_args()
    if args.field:
        observation = get_observation("2019-12-18T20:20")
        field = generate_field(observation, 150.0, 50.0, np.random.default_rng(7), thickness_m=1.0, seed=7)
        save_field(field, DATA / FIELD_FILE)
    cases = {}
    for name, case in CASES.items():
        result = floebreak.run(scenario(case))
        cases[name] = {
            **case,
            "expected": statistics(result),
            "relative_tolerance": TOLERANCES,
        }
    document = {
        "floebreak_version": floebreak.__version__,
        "field_file": FIELD_FILE,
        "cases": cases,
    }
    (DATA / "expected.json").write_text(json.dumps(document, indent=2) + "\n", encoding="utf-8")
    print(f"written {DATA / 'expected.json'}")


if __name__ == "__main__":
    main()
