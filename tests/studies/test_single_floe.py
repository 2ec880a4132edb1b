"""Single floes at the five positions of thesis Fig. 14 (§5.2): the fan-shaped pattern of Figs. 15–16.

The thesis (and the model tests it cites) describe: cusps broken off along the bow, flipped pieces beside the
shoulders, and the ice area conserved. We test those statements on counts and locations, h = 1 m.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
import shapely

from floebreak.config.profiles import build_model
from floebreak.ship.hulls import agulhas_ii
from floebreak.studies.single_floe import DIAMETERS_M, POSITIONS, SingleFloeCase, run_case

BOW = agulhas_ii(ice_thickness_m=1.0)
HALF_BREADTH_M = float(BOW.half_breadth_m)


@functools.cache
def result(position: str, diameter_m: float):
    return run_case(SingleFloeCase(position, diameter_m, 1.0), BOW, build_model("default"))


def centroid_y(result, fate: str) -> np.ndarray:
    return shapely.get_coordinates(shapely.centroid(result.polygon[result.mask(fate)]))[:, 1]


@pytest.mark.parametrize("diameter_m", DIAMETERS_M)
@pytest.mark.parametrize("position", POSITIONS)
def test_area_conserved_and_cusps_along_the_bow(position, diameter_m):
    res = result(position, diameter_m)
    assert res.area_balance_rel_error <= 1e-9
    y = centroid_y(res, "cusp")
    assert y.size > 0, "every floe in the bow's path gives cusps"
    # cusps break off where the bow meets the ice: within the hull's half-breadth plus a quarter diameter
    assert np.all(np.abs(y) <= HALF_BREADTH_M + diameter_m / 4.0)


@pytest.mark.parametrize("diameter_m", DIAMETERS_M)
@pytest.mark.parametrize("position", POSITIONS)
def test_flipped_pieces_lie_beside_the_shoulders(position, diameter_m):
    y = centroid_y(result(position, diameter_m), "flipped")
    assert np.all(np.abs(y) >= 0.8 * HALF_BREADTH_M)


@pytest.mark.parametrize("diameter_m", [10.0, 20.0])
def test_midship_floes_end_as_cusps_only(diameter_m):
    res = result("e", diameter_m)
    assert res.mask("flipped").sum() == 0
    assert res.area_m2("cusp") == pytest.approx(res.initial_ice_area_m2, rel=1e-9)


@pytest.mark.parametrize("position", ["a", "c"])
def test_shoulder_floes_are_partly_flipped(position):
    assert result(position, 10.0).mask("flipped").sum() >= 1
    assert result(position, 30.0).mask("flipped").sum() >= 1
