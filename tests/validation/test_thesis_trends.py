"""Scientific validation against statements of the thesis (marker `validation`; `make validate`, ≈ 2 min).

Not in the default run: each test runs the reference scenario (thesis §5.3: obs 2019-12-18T20:20,
400 m × 50 m assumed, h = 1 m, Agulhas II) on the thesis' four random fields, or the single-floe matrix.
"""

from __future__ import annotations

import csv

import numpy as np
import pytest

import floebreak
from floebreak.studies.single_floe import write_single_floe_matrix

pytestmark = pytest.mark.validation

SEEDS = (1, 2, 3, 4)  # the thesis averages over four random floe fields (Fig. 1)


def affected_area_m2(overrides: list[str]) -> float:
    """A_cusp^tot + A_flip^tot averaged over the four fields [m²]."""
    totals = []
    for seed in SEEDS:
        summary = floebreak.run(overrides=[f"seed={seed}", *overrides]).summary
        totals.append(summary["cusp_area_m2"] + summary["flipped_area_m2"])
    return float(np.mean(totals))


@pytest.fixture(scope="module")
def reference_area_m2() -> float:
    return affected_area_m2([])


@pytest.mark.parametrize("toughness_pa_sqrt_m", [120e3, 230e3])
def test_affected_area_hardly_depends_on_the_fracture_toughness(reference_area_m2, toughness_pa_sqrt_m):
    # thesis §5.3.1: "A_cusp^tot + A_flip^tot is nearly constant and within the range of 0.4 % deviation
    # around the reference parameter combination" (Table 5: K_Ic = 120, 145.7, 230 kPa√m)
    area = affected_area_m2([f"ice.fracture_toughness_pa_sqrt_m={toughness_pa_sqrt_m}"])
    assert area == pytest.approx(reference_area_m2, rel=0.005)


KNOWN_GAP = (
    "known discrepancy with the thesis: cracked pieces outside the bow's path stay in the field; with this "
    "criterion fewer floes are flipped whole at the shoulder (seed 1: A_flip^tot 3560 m² point load, "
    "1159 m² line load vs 3941 m² tensile stress), so the affected area drops by ≈ 5–30 %"
)


@pytest.mark.parametrize(
    "criterion",
    [
        pytest.param("point_load", marks=pytest.mark.xfail(strict=True, reason=KNOWN_GAP)),
        pytest.param("line_load", marks=pytest.mark.xfail(strict=True, reason=KNOWN_GAP)),
        "flexural_stress",
    ],
)
def test_affected_area_hardly_depends_on_the_cracking_criterion(reference_area_m2, criterion):
    # thesis §5.3.2: "the total area of affected floes A_cusp^tot + A_flip^tot for all parameter
    # configurations is nearly constant with a deviation of less than 0.5 % from the reference configuration"
    area = affected_area_m2([f"failure.crack_criterion={criterion}"])
    assert area == pytest.approx(reference_area_m2, rel=0.005)


def test_single_floe_matrix_is_port_starboard_symmetric(tmp_path):
    # thesis §5.2, Fig. 14: positions a/c (shoulders) and b/d (between tip and shoulder) are mirror images;
    # the same floe must break into the same cusps and flipped pieces on either side
    out = write_single_floe_matrix(tmp_path / "single")
    with (out / "cases.csv").open() as handle:
        rows = {(r["position"], r["diameter_m"], r["thickness_m"]): r for r in csv.DictReader(handle)}
    for (position, diameter, thickness), row in rows.items():
        mirror = {"a": "c", "b": "d"}.get(position)
        if mirror is None:
            continue
        other = rows[(mirror, diameter, thickness)]
        floe_area = sum(float(row[k]) for k in ("cusp_area_m2", "flipped_area_m2", "remaining_area_m2"))
        for key in ("n_cusps", "n_flipped", "n_remaining"):
            assert row[key] == other[key], (position, diameter, thickness, key)
        for key in ("cusp_area_m2", "flipped_area_m2", "remaining_area_m2"):
            assert float(row[key]) == pytest.approx(float(other[key]), abs=1e-9 * floe_area), key
