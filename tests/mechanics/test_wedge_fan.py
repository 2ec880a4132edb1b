"""The wedge fan at a contact (physics-notes §2.5): the ray block, Θ, the loading radius, the disk."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from floebreak.mechanics.wedge_fan import (
    disk_polygon,
    intact_fan,
    loading_radius_m,
    wedge_fan,
)


def test_half_plane_floe_gives_a_half_fan_centred_on_the_normal():
    # O just above the straight edge y = 0 of a large floe below it (outward bow normal −y), no hull: the
    # probes (0.55 m from O) of the 36 rays at ±2.5°, …, ±87.5° from −y lie in the ice, the others do not
    floe = shapely.box(-50.0, -50.0, 50.0, 0.0)
    no_hull = shapely.Polygon()
    opening, centre = intact_fan(
        floe, no_hull, np.array([0.0, 0.01]), np.array([0.0, -1.0]), 0.5, math.radians(5.0)
    )
    assert opening == pytest.approx(math.radians(180.0))  # a half plane: exactly 180°
    assert centre == pytest.approx(-math.pi / 2.0, abs=1e-12)


def test_loading_radius_is_the_sector_with_the_crushed_area():
    # A_h = Θ r² / 2 (physics-notes §2.5 step 4)
    assert loading_radius_m(0.5, math.pi / 2.0) == pytest.approx(math.sqrt(2.0 * 0.5 / (math.pi / 2.0)))
    assert loading_radius_m(0.0, 1.0) == 0.0
    assert loading_radius_m(-1.0, 1.0) == 0.0
    assert loading_radius_m(1.0, 0.0) == 0.0
    # clipped to Erceg's table range [0.1, 1.5] m for the thesis replication
    assert loading_radius_m(1e-6, math.pi, "sector_area_clipped") == 0.1
    assert loading_radius_m(100.0, math.pi, "sector_area_clipped") == 1.5
    assert loading_radius_m(0.5, math.pi, "sector_area_clipped") == pytest.approx(math.sqrt(1.0 / math.pi))


def test_wedge_fan_radius_uses_the_found_opening():
    floe = shapely.box(-50.0, -50.0, 50.0, 0.0)
    fan = wedge_fan(
        floe, shapely.Polygon(), np.array([0.0, 0.01]), np.array([0.0, -1.0]), 0.3, math.radians(5)
    )
    assert fan.opening_rad == pytest.approx(math.radians(180.0))
    assert fan.loading_radius_m == pytest.approx(math.sqrt(2.0 * 0.3 / math.radians(180.0)))
    assert fan.n_wedges == 36


def test_disk_polygon_has_its_corners_on_the_circle():
    disk = disk_polygon(np.array([1.0, -2.0]), 3.0, 0.25, 72)
    corners = shapely.get_coordinates(disk)[:-1]
    assert len(corners) == 72 and disk.is_valid
    np.testing.assert_allclose(np.hypot(corners[:, 0] - 1.0, corners[:, 1] + 2.0), 3.0, rtol=1e-14)
    np.testing.assert_allclose(corners[0], [1.0 + 3.0 * math.cos(0.25), -2.0 + 3.0 * math.sin(0.25)])
    # a regular 72-gon: area (n/2) R² sin(2π/n)
    assert disk.area == pytest.approx(36.0 * 9.0 * math.sin(2.0 * math.pi / 72.0), rel=1e-12)


@pytest.mark.parametrize("n_rays", [25, 41, 50, 36])
def test_a_fan_of_intact_ice_all_around_is_the_whole_circle(n_rays):
    # O inside a large floe, no hull: every ray meets intact ice and Θ = 2π; n · (2π/n) rounds above 2π for
    # n = 25, 41, 50, which Nevel's capacity refused mid-run as "opening_rad exceeds 2π" (fuzz campaign,
    # wedge_angle_deg 7.13° → 50 rays, a 1 m wide bow inside a 10 m thick floe)
    from floebreak.mechanics.nevel import bearing_capacity_n

    assert (n_rays * (2.0 * math.pi / n_rays) > 2.0 * math.pi) == (n_rays != 36)
    floe = shapely.box(-50.0, -50.0, 50.0, 50.0)
    opening, _ = intact_fan(
        floe, shapely.Polygon(), np.array([0.0, 0.0]), np.array([1.0, 0.0]), 0.5, 2.0 * math.pi / n_rays
    )
    assert opening == 2.0 * math.pi
    assert bearing_capacity_n(1.0, 0.5, opening) > 0.0
