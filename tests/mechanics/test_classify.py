"""Failure-mode classification, thesis Alg. 2 and Eqs. 2–5 (errata 7, 8)."""

import numpy as np
import pytest
import shapely

from floebreak.ice.field import circle_polygons
from floebreak.mechanics.classify import (
    ClassificationParams,
    classify,
    oriented_extent_m,
    unbreakable_area_m2,
)

H = 1.0
ELL = (2e9 * H**3 / (12 * (1 - 0.3**2)) / (1025 * 9.81)) ** 0.25  # Eq. 1, computed here: 11.62 m


def test_oriented_extent_of_rotated_rectangle():
    rect = shapely.box(-3.0, -1.0, 3.0, 1.0)  # 6 m along x, 2 m along y
    angle = np.radians(30.0)
    rotated = shapely.affinity.rotate(rect, 30.0, origin=(0, 0))
    length, width = oriented_extent_m(rotated, np.array([np.cos(angle), np.sin(angle)]))
    assert (length, width) == pytest.approx((6.0, 2.0))


def test_unbreakable_thresholds():
    p = ClassificationParams()
    # thesis Eq. 5 with ℓ = 13.5 h^(3/4): A_rotate = 1 m · 13.5 m = 13.5 m² at h = 1 m (erratum 8)
    assert unbreakable_area_m2(1.0, p) == pytest.approx(13.5)
    assert unbreakable_area_m2(0.8, p) == pytest.approx(13.5 * 0.8**0.75)
    assert unbreakable_area_m2(1.0, ClassificationParams(unbreakable_rule="ell_squared")) == pytest.approx(
        182.25
    )
    assert unbreakable_area_m2(1.0, ClassificationParams(unbreakable_ell="eq1")) == pytest.approx(ELL)


def test_small_floe_is_unbreakable():
    floe = shapely.box(0, 0, 3.6, 3.6)  # 12.96 m² ≤ 13.5 m²
    assert classify(floe, H, np.array([1.0, 0.0]), ClassificationParams()).failure_class == "unbreakable"


def test_large_floe_bends_eq2():
    floe = shapely.box(0, 0, 2.5 * ELL, 3 * ELL)  # both sides > 2ℓ
    result = classify(floe, H, np.array([1.0, 0.0]), ClassificationParams())
    assert result.failure_class == "bending"
    assert result.characteristic_length_m == pytest.approx(ELL, rel=1e-9)


def test_narrow_long_floe_bends_eq3_and_wide_short_floe_cracks_eq4():
    normal = np.array([1.0, 0.0])  # length along x, width along y
    long_narrow = shapely.box(0, 0, 30.0, 8.0)  # l = 30 > w = 8, w ≤ 2ℓ → bending (Eq. 3)
    wide_short = shapely.box(0, 0, 8.0, 30.0)  # w = 30 > l = 8, l ≤ 2ℓ → cracking (Eq. 4)
    assert classify(long_narrow, H, normal, ClassificationParams()).failure_class == "bending"
    assert classify(wide_short, H, normal, ClassificationParams()).failure_class == "cracking"
    # the same floe seen from a panel rotated by 90° swaps length and width
    assert classify(wide_short, H, np.array([0.0, 1.0]), ClassificationParams()).failure_class == "bending"


@pytest.mark.parametrize("angle_deg", np.linspace(0.0, 90.0, 13))
def test_round_floes_bend_whatever_the_panel_direction(angle_deg):
    circle = circle_polygons(np.array([[0.0, 0.0]]), np.array([7.5]), 64)[0]
    normal = np.array([np.cos(np.radians(angle_deg)), np.sin(np.radians(angle_deg))])
    assert classify(circle, H, normal, ClassificationParams()).failure_class == "bending"


def test_bbox_rule():
    p = ClassificationParams(unbreakable_rule="bbox_lt_ell")
    assert classify(shapely.box(0, 0, 13.0, 13.0), H, np.array([1.0, 0.0]), p).failure_class == "unbreakable"
    assert classify(shapely.box(0, 0, 14.0, 3.0), H, np.array([1.0, 0.0]), p).failure_class != "unbreakable"


def test_measured_box_and_area_are_used_as_given():
    # a 30 m × 4 m strip: its own box makes it a cracking floe (wide along the panel, short along the normal);
    # handed the box of a small square instead, classify must use the given numbers, not re-measure
    strip = shapely.box(0.0, -15.0, 4.0, 15.0)
    normal = np.array([1.0, 0.0])
    params = ClassificationParams()
    measured = classify(strip, 1.0, normal, params)
    given = classify(strip, 1.0, normal, params, extent_m=(4.0, 30.0), area_m2=120.0)
    assert given == measured
    tiny = classify(strip, 1.0, normal, params, extent_m=(0.5, 0.5), area_m2=0.25)
    assert tiny.failure_class == "unbreakable" != measured.failure_class
    assert (tiny.length_m, tiny.width_m, tiny.area_m2) == (0.5, 0.5, 0.25)
