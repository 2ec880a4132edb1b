"""Compiled polygon queries (mechanics/polygon_kernel.py) against GEOS on random polygons."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
import shapely

from floebreak.mechanics import polygon_kernel
from floebreak.mechanics.wedge_fan import intact_fan


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


def _contiguous_block(kept: np.ndarray) -> np.ndarray:
    """The compiled rule's (first, length) as the list of ray indices in circular order."""
    first, length = polygon_kernel._block_nearest_normal(kept)
    return (first + np.arange(length)) % len(kept)


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


def star_polygon(rng: np.random.Generator, centre, radius: float, n: int = 17) -> shapely.Polygon:
    """A random star-shaped (generally non-convex) polygon."""
    angles = np.sort(rng.uniform(0.0, 2.0 * math.pi, n))
    radii = radius * rng.uniform(0.3, 1.0, n)
    return shapely.Polygon(np.c_[centre[0] + radii * np.cos(angles), centre[1] + radii * np.sin(angles)])


def random_floe(rng: np.random.Generator) -> shapely.Geometry:
    floe = star_polygon(rng, (0.0, 0.0), rng.uniform(2.0, 15.0))
    if rng.random() < 0.3:  # a hole
        floe = floe.difference(shapely.Point(0.0, 0.0).buffer(rng.uniform(0.2, 1.0)))
    if rng.random() < 0.2:  # two parts
        floe = floe.union(star_polygon(rng, (40.0, 0.0), 5.0))
    return floe


def fan_by_geos(floe, hull, origin, normal, reach, n_rays):
    """physics-notes §2.5 step 3 written with shapely's point-in-polygon and the rule as a loop."""
    step = 2.0 * math.pi / n_rays
    normal_angle = math.atan2(normal[1], normal[0])
    angles = normal_angle + (np.arange(n_rays) + 0.5) * step
    x, y = origin[0] + reach * np.cos(angles), origin[1] + reach * np.sin(angles)
    kept = shapely.contains_xy(floe, x, y) & ~shapely.contains_xy(hull, x, y)
    block = block_by_definition(kept)
    if not block or len(block) == n_rays:
        return len(block) * step, normal_angle
    return len(block) * step, math.atan2(np.sin(angles[block]).sum(), np.cos(angles[block]).sum())


def test_ring_arrays_list_every_ring():
    shell = shapely.box(0.0, 0.0, 10.0, 10.0)
    holed = shell.difference(shapely.box(4.0, 4.0, 6.0, 6.0))
    two = shapely.MultiPolygon([holed, shapely.box(20.0, 0.0, 21.0, 1.0)])
    xs, ys, offsets = polygon_kernel.ring_arrays(two)
    assert offsets.tolist() == [0, 5, 10, 15]
    assert xs.size == ys.size == 15
    # the even–odd rule over the rings: inside the shell, not in the hole, inside the second part
    inside = [polygon_kernel._inside_rings(x, y, xs, ys, offsets) for x, y in [(1, 1), (5, 5), (20.5, 0.5)]]
    assert inside == [True, False, True]


def test_intact_fan_agrees_with_geos_on_random_floes():
    rng = np.random.default_rng(11)
    hull = shapely.Polygon([(0.0, 0.0), (-20.0, 8.0), (-60.0, 10.0), (-60.0, -10.0), (-20.0, -8.0)])
    for _ in range(400):
        floe = random_floe(rng)
        floe = shapely.affinity.translate(floe, rng.uniform(-10.0, 10.0), rng.uniform(-10.0, 10.0))
        origin = rng.uniform(-12.0, 12.0, 2)
        normal_angle = rng.uniform(-math.pi, math.pi)
        normal = np.array([math.cos(normal_angle), math.sin(normal_angle)])
        radius = rng.uniform(0.0, 6.0)
        wedge = math.radians(rng.choice([5.0, 10.0, 7.5]))
        n_rays = round(2.0 * math.pi / wedge)
        expected = fan_by_geos(floe, hull, origin, normal, radius + 0.05, n_rays)
        got = intact_fan(floe, hull, origin, normal, radius, wedge)
        assert got[0] == pytest.approx(expected[0], abs=1e-12)
        assert got[1] == pytest.approx(expected[1], abs=1e-12)
        # the hull given as its rings once per bow gives the same
        assert intact_fan(floe, polygon_kernel.ring_arrays(hull), origin, normal, radius, wedge) == got


def inside_length_by_geos(polygon, origin, end) -> float:
    """Length of the part of segment origin → end inside the polygon that starts at origin (GEOS overlay)."""
    inside = shapely.intersection(shapely.LineString([origin, end]), polygon)
    parts = shapely.get_parts(shapely.line_merge(inside)) if not inside.is_empty else []
    for part in parts:
        if part.length > 0.0 and part.distance(shapely.Point(origin)) < 1e-6:
            return part.length
    return 0.0


def test_inside_length_agrees_with_geos_on_random_floes():
    rng = np.random.default_rng(12)
    n_inside = 0
    for _ in range(600):
        floe = random_floe(rng)
        origin = rng.uniform(-8.0, 8.0, 2)
        angle = rng.uniform(-math.pi, math.pi)
        end = origin + 40.0 * np.array([math.cos(angle), math.sin(angle)])
        expected = inside_length_by_geos(floe, origin, end)
        got = polygon_kernel.inside_length_from(
            *polygon_kernel.ring_arrays(floe), *origin, *(end - origin), 1e-6
        )
        assert got == pytest.approx(expected, rel=1e-9, abs=1e-9)
        n_inside += expected > 0.0
    assert n_inside > 100  # the cases exercise rays that start inside a floe


def test_inside_length_hand_cases():
    square = polygon_kernel.ring_arrays(shapely.box(0.0, 0.0, 4.0, 4.0))
    # from the centre to the right: 2 m inside; from outside: nothing starts at O
    assert polygon_kernel.inside_length_from(*square, 2.0, 2.0, 10.0, 0.0, 1e-6) == pytest.approx(2.0)
    assert polygon_kernel.inside_length_from(*square, -1.0, 2.0, 10.0, 0.0, 1e-6) == 0.0
    # O on the boundary (within the tolerance) going in: the whole chord
    assert polygon_kernel.inside_length_from(*square, 0.0, 2.0, 10.0, 0.0, 1e-6) == pytest.approx(4.0)
    # a ray through a hole stops at the hole's edge
    holed = polygon_kernel.ring_arrays(shapely.box(0.0, 0.0, 4.0, 4.0).difference(shapely.box(3, 1, 3.5, 3)))
    assert polygon_kernel.inside_length_from(*holed, 1.0, 2.0, 10.0, 0.0, 1e-6) == pytest.approx(2.0)


def swept_by(hull: shapely.Polygon, shift_m: float) -> shapely.Geometry:
    """The region the hull covers while it moves by `shift_m` in +x: the hull at both ends and the
    quadrilateral each of its edges sweeps (exact for any polygon)."""
    ring = np.asarray(hull.exterior.coords)
    quads = [
        shapely.Polygon([a, b, (b[0] + shift_m, b[1]), (a[0] + shift_m, a[1])])
        for a, b in itertools.pairwise(ring)
        if a[1] != b[1]
    ]
    return shapely.union_all([hull, shapely.affinity.translate(hull, shift_m), *quads])


def test_advance_to_contact_hand_cases():
    hull = polygon_kernel.ring_arrays(shapely.box(0.0, 0.0, 1.0, 1.0))

    def advance(polygon, clearance=1e-9):
        return polygon_kernel.advance_to_contact(*polygon_kernel.ring_arrays(polygon), *hull, clearance)

    assert advance(shapely.box(3.0, 0.2, 4.0, 0.8)) == pytest.approx(2.0)  # ahead: the faces meet after 2 m
    assert advance(shapely.box(3.0, 0.5, 4.0, 3.0)) == pytest.approx(2.0)  # reaching into the path
    assert advance(shapely.box(3.0, 2.0, 4.0, 3.0)) == math.inf  # beside the path
    assert advance(shapely.box(-5.0, 0.0, -4.0, 1.0)) == math.inf  # behind the hull
    assert advance(shapely.box(0.5, 0.5, 2.0, 2.0)) == 0.0  # overlapping
    assert advance(shapely.box(1.0, 0.0, 2.0, 1.0)) == 0.0  # touching
    assert advance(shapely.box(0.2, 0.2, 0.4, 0.4)) == 0.0  # inside the hull
    assert advance(shapely.box(-5.0, -5.0, 5.0, 5.0)) == 0.0  # around the hull
    assert advance(shapely.box(1.0 + 1e-10, 0.0, 2.0, 1.0)) == 0.0  # within the clearance
    assert advance(shapely.box(1.0 + 1e-6, 0.0, 2.0, 1.0)) == pytest.approx(1e-6)
    # a triangle whose tip points at the hull: the tip (a vertex) meets the hull's face
    assert advance(shapely.Polygon([(2.5, 0.5), (4.0, -1.0), (4.0, 2.0)])) == pytest.approx(1.5)
    # the hull's corner (1, 1) meets a slanted face, which is at x = 3.5 at the corner's height
    assert advance(shapely.Polygon([(2.5, 2.0), (5.5, -1.0), (5.5, 2.0)])) == pytest.approx(2.5)
    # the hull inside a floe's hole moves to the hole's edge
    holed = shapely.box(-10.0, -10.0, 10.0, 10.0).difference(shapely.box(-2.0, -2.0, 3.0, 3.0))
    assert advance(holed) == pytest.approx(2.0)


@pytest.mark.parametrize("notch", [False, True], ids=["convex hull", "non-convex hull"])
def test_advance_to_contact_agrees_with_the_swept_hull_on_random_floes(notch):
    """0 ⇔ within the clearance now; else the hull's sweep up to just before t misses the floe and the hull
    touches it at t; inf ⇔ a long sweep misses it."""
    rng = np.random.default_rng(17)
    outline = [(0.0, 0.0), (-20.0, 8.0), (-60.0, 10.0), (-60.0, -10.0), (-20.0, -8.0)]
    if notch:
        outline[2:2] = [(-30.0, 9.0), (-35.0, 3.0), (-40.0, 9.5)]
    hull = shapely.Polygon(outline)
    hull_rings = polygon_kernel.ring_arrays(hull)
    outcomes = {"now": 0, "later": 0, "never": 0}
    for _ in range(300):
        floe = random_floe(rng)
        floe = shapely.affinity.translate(floe, rng.uniform(-70.0, 60.0), rng.uniform(-25.0, 25.0))
        travel = polygon_kernel.advance_to_contact(*polygon_kernel.ring_arrays(floe), *hull_rings, 1e-9)
        if travel == 0.0:
            outcomes["now"] += 1
            assert shapely.distance(hull, floe) <= 1e-9
            continue
        assert shapely.distance(hull, floe) > 1e-9
        if travel == math.inf:
            outcomes["never"] += 1
            assert not swept_by(hull, 1e4).intersects(floe)
            continue
        outcomes["later"] += 1
        assert not swept_by(hull, travel - 1e-7).intersects(floe)
        assert shapely.distance(shapely.affinity.translate(hull, travel), floe) < 1e-9
    assert min(outcomes.values()) >= 30, outcomes  # every case is exercised
