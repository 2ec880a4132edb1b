"""Property tests of the floe cutters (thesis §4.1–4.3): the half-plane split of cracking, the disk split of
bending and the local-cracking cutter, on random star-shaped polygons, circles and boxes.

Properties (the engine's area balance, tolerance 1e-9 as in `simulation`): the pieces' areas sum to the
parent's within 1e-9 relative, pieces do not overlap (pairwise intersection area ≤ 1e-9 · parent), every piece
is a valid polygon.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from floebreak.failure.base import split_parts
from floebreak.failure.bending import BendingCheck, split_by_radius
from floebreak.failure.cracking import split_by_line
from floebreak.failure.local_cracking import local_crack_line
from floebreak.mechanics.wedge_fan import WedgeFan
from floebreak.testing import angles_rad, floe_polygons, points_near

SETTINGS = settings(
    max_examples=50, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow]
)
PHI_RAD = math.radians(5.0)


def assert_partition(parent, pieces) -> None:
    assert all(shapely.get_type_id(p) == 3 and p.is_valid and p.area > 0 for p in pieces)
    total = sum(p.area for p in pieces)
    assert total == pytest.approx(parent.area, rel=1e-9)
    for a, b in itertools.combinations(pieces, 2):
        assert shapely.area(shapely.intersection(a, b)) <= 1e-9 * parent.area


@SETTINGS
@given(data=st.data(), polygon=floe_polygons(), direction_angle=angles_rad)
def test_split_by_line_partitions_the_floe(data, polygon, direction_angle):
    assert polygon.is_valid
    point = data.draw(points_near(polygon))
    direction = np.array([math.cos(direction_angle), math.sin(direction_angle)])
    left, right = split_by_line(polygon, point, direction)
    assert_partition(polygon, [*left, *right])
    # each side lies on its side of the line
    for side, sign in ((left, 1.0), (right, -1.0)):
        for piece in side:
            rel = shapely.get_coordinates(piece) - point
            cross = direction[0] * rel[:, 1] - direction[1] * rel[:, 0]
            assert np.all(sign * cross >= -1e-7 * (1.0 + np.hypot(*rel.T)))


@SETTINGS
@given(
    data=st.data(),
    polygon=floe_polygons(),
    centre_angle=angles_rad,
    n_wedges=st.integers(1, 72),
    radius=st.floats(0.2, 40.0),
)
def test_split_by_radius_partitions_the_floe(data, polygon, centre_angle, n_wedges, radius):
    origin = data.draw(points_near(polygon))
    fan = WedgeFan(origin, centre_angle, n_wedges * PHI_RAD, PHI_RAD, 0.5)
    check = BendingCheck(fan, 11.62, 1.0, 2.0, radius)
    near, far = split_by_radius(polygon, check)
    assert_partition(polygon, [*near, *far])
    for piece in near:  # within the circumscribed radius of the 72-gon
        assert np.all(np.hypot(*(shapely.get_coordinates(piece) - origin).T) <= radius * (1 + 1e-9))


@SETTINGS
@given(
    data=st.data(),
    polygon=floe_polygons(),
    normal_angle=angles_rad,
    radius=st.floats(1.0, 15.0),
    ell=st.floats(3.0, 15.0),
)
def test_local_cracking_cutter_partitions_the_floe(data, polygon, normal_angle, radius, ell):
    origin = data.draw(points_near(polygon, spread=1.0))
    normal = np.array([math.cos(normal_angle), math.sin(normal_angle)])
    frontmost = origin + data.draw(st.floats(-2.0, 2.0)) * np.array([-normal[1], normal[0]])
    line = local_crack_line(origin, normal, frontmost, radius, ell, PHI_RAD)
    inside = shapely.get_parts(shapely.intersection(polygon, line.cutter))
    outside = shapely.get_parts(shapely.difference(polygon, line.cutter))
    pieces = [p for p in [*inside, *outside] if shapely.get_type_id(p) == 3 and p.area > 0]
    assert_partition(polygon, pieces)


# --------------------------------------------------------------------------------------------------------
# A sub-threshold sliver (≤ MIN_PIECE_AREA_M2 = 1e-6 m²) is merged into a neighbour, not dropped
# --------------------------------------------------------------------------------------------------------


def comb_floe_with_bump(bump_height_m: float) -> shapely.Polygon:
    """A concave floe (base 10 × 3 m, two 2 m towers to y = 10) with a 1 m wide flat bump up to 5 + δ."""
    return shapely.Polygon(
        [
            (0, 0), (10, 0), (10, 10), (8, 10), (8, 3), (6, 3), (6, 5 + bump_height_m),
            (5, 5 + bump_height_m), (5, 3), (2, 3), (2, 10), (0, 10),
        ]
    )  # fmt: skip


def test_crack_line_grazing_a_bump_keeps_all_the_area():
    floe = comb_floe_with_bump(5e-7)  # the bump crosses the crack line y = 5 by 0.5 µm over 1 m: 5e-7 m²
    left, right = split_by_line(floe, np.array([0.0, 5.0]), np.array([1.0, 0.0]))
    assert left and right
    assert sum(p.area for p in [*left, *right]) == pytest.approx(floe.area, rel=1e-9)
    # the bump is merged into the base it sits on, not kept as a 5e-7 m² "piece"
    assert len(left) == 2 and len(right) == 1
    assert all(p.area > 1e-6 for p in [*left, *right])


def test_bending_disk_just_below_a_spike_tip_keeps_all_the_area():
    # a 20 × 3 m floe with a triangular spike (base 2 m) up to y = 6; the bending disk about (5, 0) reaches
    # y = 6 − 1.2 mm, so the spike's tip (≈ 5e-7 m²) lies beyond the bending line, with the two outer corners
    floe = shapely.Polygon([(-5, 0), (15, 0), (15, 3), (6, 3), (5, 6), (4, 3), (-5, 3)])
    fan = WedgeFan(np.array([5.0, 0.0]), math.pi / 2.0, PHI_RAD, PHI_RAD, 0.5)  # a disk vertex at 90°
    check = BendingCheck(fan, 11.62, 1.0, 2.0, 6.0 - 1.2e-3)
    near, far = split_by_radius(floe, check)
    assert near and far
    assert sum(p.area for p in [*near, *far]) == pytest.approx(floe.area, rel=1e-9)


@pytest.mark.parametrize(("cut_y_m", "thickness_m", "separate"), [(0.3, 1.0, False), (0.6, 1.0, True)])
def test_a_strip_thinner_than_the_ice_is_no_piece(cut_y_m, thickness_m, separate):
    """A cut parallel to an edge of a 10 m × 10 m floe leaves a 10 m strip of width w: its hydraulic diameter
    4A/P = 4·10w/(20 + 2w) is below h for w = 0.3 m (0.59 m < 1 m: rubble, no piece of its own, so the cut
    separates nothing) and above it for w = 0.6 m (1.13 m: a piece of ice of its own)."""
    floe = shapely.box(0.0, 0.0, 10.0, 10.0)
    strip = shapely.box(0.0, 0.0, 10.0, cut_y_m)
    near, far = split_parts(
        shapely.intersection(floe, strip), shapely.difference(floe, strip), thickness_m=thickness_m
    )
    assert (len(near) == 1) is separate
    assert len(far) == 1
    if separate:  # a real split: two pieces, the area kept
        assert sum(p.area for p in [*near, *far]) == pytest.approx(100.0, rel=1e-12)
    # else the cut separates nothing (an empty side): the modes keep the floe whole
    assert all(shapely.is_valid(p) for p in [*near, *far])


def test_dust_of_a_split_of_rubble_is_merged():
    """Fuzz campaign: in 10 m ice every part of a split of a 1 m × 1 m floe is a sliver (4A/P ≤
    1 m), and such parts were kept as they were — also dust of 1e-17 m² whose vertices lay one rounding step
    apart and which became invalid polygons once moved to the world frame. Dust (≤ 1e-6 m²) is merged even
    there."""
    square, right = shapely.box(0.0, 0.0, 1.0, 1.0), shapely.box(1.0, 0.0, 2.0, 1.0)
    dust = shapely.Polygon([(0.0, 0.0), (0.0, 0.5), (-1e-7, 0.25)])  # on the square's left edge: 2.5e-8 m²
    # a cut that leaves only dust on one side separates nothing (an empty side: the modes keep the floe)
    near, far = split_parts(square, dust, thickness_m=10.0)
    assert len(near) == 1 and far == []
    # a split of rubble into two parts and dust: the two stay, the dust joins the part it touches
    near, far = split_parts(square, shapely.union(right, dust), thickness_m=10.0)
    assert len(near) == 1 and len(far) == 1 and near[0].is_valid
    assert near[0].area == pytest.approx(1.0 + 0.5 * 0.5 * 1e-7, rel=1e-12) and far[0].area == 1.0
