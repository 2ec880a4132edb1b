"""The thesis' App. A.4 capacity lookup (physics-notes §1.7, erratum 12): the grid points it averages over,
read off the listing by hand."""

from __future__ import annotations

import math

import pytest

from floebreak.mechanics import nevel
from floebreak.mechanics.capacity_lookup import bracket, thesis_a4_capacity_n, thickness_corners_m

RADIUS_GRID_M = (0.1, 0.3, 0.6, 1.0, 1.5)
ANGLE_GRID_DEG = (*range(1, 60), 60, 90, 105, 135, 165, 180)


@pytest.mark.parametrize(
    ("thickness_m", "corners"),
    [
        (1.0, (1.2, 1.2)),  # the first grid value above 1.0 is 1.2, and so is the largest: P(1.0) = P(1.2)
        (0.8, (1.2, 0.9)),
        (0.5, (1.2, 0.6)),
        (1.2, (1.2, 1.2)),  # on the grid
        (0.6, (0.6, 0.6)),
        (1.5, (1.2, 1.2)),  # above the grid
    ],
)
def test_thickness_corners_follow_the_listing(thickness_m, corners):
    assert thickness_corners_m(thickness_m) == pytest.approx(corners)


@pytest.mark.parametrize(
    ("value", "grid", "expected"),
    [
        (0.45, RADIUS_GRID_M, (0.3, 0.6)),
        (1.0, RADIUS_GRID_M, (1.0, 1.0)),
        (120.5, ANGLE_GRID_DEG, (105, 135)),
        (30.5, ANGLE_GRID_DEG, (30, 31)),
        (0.5, ANGLE_GRID_DEG, (180, 1)),  # below the grid: the code's index −1 is the last value
    ],
)
def test_bracket_is_the_neighbouring_grid_values(value, grid, expected):
    assert bracket(value, grid) == pytest.approx(expected)


def test_capacity_is_the_plain_mean_of_the_eight_corners():
    calls = []

    def capacity_n(h, r, opening_rad):
        calls.append((h, r, round(math.degrees(opening_rad), 9)))
        return 1000.0 * h + 10.0 * r + math.degrees(opening_rad)

    # h 0.8 → (1.2, 0.9); r 2.0 clipped to 1.5 (on the grid); Θ 200° capped at 180° (on the grid)
    value = thesis_a4_capacity_n(0.8, 2.0, math.radians(200.0), capacity_n)
    assert sorted(set(calls)) == [(0.9, 1.5, 180.0), (1.2, 1.5, 180.0)]
    assert value == pytest.approx((1200.0 + 900.0) / 2 + 15.0 + 180.0)
    calls.clear()
    # h 1.0 → (1.2, 1.2); r 0.45 → (0.3, 0.6); Θ 120.5° → (105°, 135°): the mean does not depend on where
    # the point lies in its cell (no interpolation)
    value = thesis_a4_capacity_n(1.0, 0.45, math.radians(120.5), capacity_n)
    assert {c[0] for c in calls} == {1.2} and {c[1] for c in calls} == {0.3, 0.6}
    assert {c[2] for c in calls} == {105.0, 135.0}
    assert value == pytest.approx(1200.0 + 4.5 + 120.0)


def test_with_eq_1_4_the_capacity_at_1_m_is_the_one_at_1_2_m():
    """On the grid in r and Θ the lookup is Eq. 1.4 at its thickness corners: at h = 1.0 m that is h = 1.2 m,
    (1.2/1.0)² ≈ 1.44 times the direct capacity up to S(r/ℓ); at 0.8 m the mean of 0.9 and 1.2 m."""

    def eq_1_4(h, r, opening_rad):
        return float(nevel.bearing_capacity_n(h, r, opening_rad))

    half_plane = math.pi
    at_1_0 = thesis_a4_capacity_n(1.0, 0.6, half_plane, eq_1_4)
    assert at_1_0 == pytest.approx(eq_1_4(1.2, 0.6, half_plane), rel=1e-12)
    assert 1.3 < at_1_0 / eq_1_4(1.0, 0.6, half_plane) < 1.5
    at_0_8 = thesis_a4_capacity_n(0.8, 0.6, half_plane, eq_1_4)
    mean_of_corners = (eq_1_4(0.9, 0.6, half_plane) + eq_1_4(1.2, 0.6, half_plane)) / 2
    assert at_0_8 == pytest.approx(mean_of_corners, rel=1e-12)
