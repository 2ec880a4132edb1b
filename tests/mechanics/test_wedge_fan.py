"""The wedge fan at a contact (physics-notes §2.5): the ray block, Θ, the loading radius, the disk."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
import shapely

from floebreak.mechanics.wedge_fan import (
    _contiguous_block,
    disk_polygon,
    intact_fan,
    loading_radius_m,
    wedge_fan,
)


def block_by_definition(kept: np.ndarray) -> list[int]:
    """The rule of physics-notes §2.5 step 3, written out as a loop: the circular runs of kept rays (listed
    from the first unkept ray on), the run nearest to the normal (ray i lies (i + ½) steps from it), the
    longer one on a tie, the first listed on a full tie; its rays in circular order."""
    n = len(kept)
    if not any(kept):
        return []
    if all(kept):
        return list(range(n))
    start = next(i for i in range(n) if not kept[i])
    runs, current = [], []
    for index in [(start + j) % n for j in range(n)]:
        if kept[index]:
            current.append(index)
        elif current:
            runs.append(current)
            current = []
    if current:
        runs.append(current)
    return min(runs, key=lambda run: (min(min(i + 0.5, n - i - 0.5) for i in run), -len(run)))


def test_contiguous_block_follows_the_rule_for_every_small_pattern():
    for n in range(1, 13):
        for bits in itertools.product([False, True], repeat=n):
            kept = np.array(bits)
            assert _contiguous_block(kept).tolist() == block_by_definition(kept), bits


def test_contiguous_block_follows_the_rule_for_random_72_ray_patterns():
    rng = np.random.default_rng(5)
    for _ in range(2000):
        kept = rng.random(72) < rng.random()
        assert _contiguous_block(kept).tolist() == block_by_definition(kept)


def test_contiguous_block_examples():
    kept = np.zeros(12, dtype=bool)
    kept[[10, 11, 0, 1, 2]] = True  # the run through ray 0 wraps round
    kept[[5, 6, 7, 8]] = True  # a longer run further away is not taken
    assert _contiguous_block(kept).tolist() == [10, 11, 0, 1, 2]
    kept = np.zeros(12, dtype=bool)
    kept[[2, 3]] = True  # distance 2 from ray 0
    kept[[8, 9, 10]] = True  # distance 2 as well (ray 10), and longer: taken
    assert _contiguous_block(kept).tolist() == [8, 9, 10]


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
