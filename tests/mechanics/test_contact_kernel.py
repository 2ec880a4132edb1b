"""The compiled contact kernel against the shapely (GEOS) implementation it replaces for convex floes.

Reference: `contact._zone_table_shapely`, the GEOS overlays (F ∩ H_u, Z ∩ Q_i, waterline ∩ F) — an
independent implementation of the same definitions (docs/model.md, contact zones and areas).
"""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import example, given, settings
from hypothesis import strategies as st

from floebreak.mechanics import contact, contact_kernel
from floebreak.mechanics.classify import oriented_extent_m
from floebreak.mechanics.contact import BowContactGeometry, ContactParams, evaluate_contacts
from floebreak.ship.hulls import agulhas_ii


@pytest.fixture(scope="module")
def geometry() -> BowContactGeometry:
    return BowContactGeometry.from_bow(agulhas_ii(ice_thickness_m=1.0))


def _by_floe(table):
    """{floe: (A_u, centre, centre panel, {panel: A_h})} of a zone table with one zone per floe."""
    out = {}
    if table is None:
        return out
    for k, floe in enumerate(table.owner.tolist()):
        rows = table.row_zone == k
        panels = dict(zip(table.row_panel[rows].tolist(), table.row_a_h_m2[rows].tolist(), strict=True))
        out[floe] = (table.a_u_m2[k], table.centre_xy_m[k], int(table.centre_panel[k]), panels)
    return out


def _assert_same(kernel_table, shapely_table, floes, geometry):
    fast, reference = _by_floe(kernel_table), _by_floe(shapely_table)
    # a floe whose overlap is a rounding-level sliver may be in one table only
    for floe in set(fast) ^ set(reference):
        only = fast.get(floe) or reference.get(floe)
        assert only[0] < 1e-9
    for floe in set(fast) & set(reference):
        a_u, centre, panel, rows = fast[floe]
        ref_a_u, ref_centre, ref_panel, ref_rows = reference[floe]
        assert a_u == pytest.approx(ref_a_u, rel=1e-9, abs=1e-12)
        if not np.allclose(centre, ref_centre, atol=1e-7):
            # a zone clear of the waterline: both must be a nearest waterline point
            parts = shapely.get_parts(shapely.intersection(geometry.waterline, floes[floe]))
            assert not ((shapely.get_type_id(parts) == 1) & (shapely.length(parts) > 0.0)).any()
            gap = shapely.distance(geometry.waterline, floes[floe])
            for point in (centre, ref_centre):
                assert shapely.distance(shapely.Point(point), floes[floe]) == pytest.approx(gap, abs=1e-9)
            continue
        if panel != ref_panel:  # only a centre on a node may go to either panel
            nodes = shapely.get_coordinates(geometry.waterline)
            assert np.hypot(*(nodes - centre).T).min() < 1e-7
            assert abs(panel - ref_panel) == 1
        for p in set(rows) | set(ref_rows):
            assert rows.get(p, 0.0) == pytest.approx(ref_rows.get(p, 0.0), rel=1e-9, abs=1e-10)
    # what the kernel measures for the classification on the way: floe area and Alg. 2 box
    for k, floe in enumerate(kernel_table.owner.tolist() if kernel_table is not None else []):
        normal = _normal_at(kernel_table.centre_xy_m[k], kernel_table.centre_panel[k], geometry)
        assert kernel_table.floe_area_m2[k] == pytest.approx(shapely.area(floes[floe]), rel=1e-12)
        expected = oriented_extent_m(floes[floe], normal)
        np.testing.assert_allclose(kernel_table.floe_extent_m[k], expected, rtol=1e-12, atol=1e-12)


def _normal_at(point, panel, geometry):
    """The panel's normal, or on an interior node i thesis Eq. 20's (y_(i−1) − y_(i+1), x_(i+1) − x_(i−1)),
    normalised and pointing outwards (the side of the panel's normal)."""
    nodes = np.asarray(geometry.waterline_xy_m)
    i = int(np.argmin(np.hypot(*(nodes - point).T)))
    normal = geometry.panel_normals[panel]
    if np.hypot(*(nodes[i] - point)) > 1e-9 or i in (0, len(nodes) - 1):
        return normal
    chord = np.array([nodes[i - 1, 1] - nodes[i + 1, 1], nodes[i + 1, 0] - nodes[i - 1, 0]])
    return np.sign(chord @ normal) * chord / np.hypot(*chord)


def _convex_floe(x, y, radius, n_vertices, aspect, angle):
    t = np.linspace(0.0, 2.0 * np.pi, n_vertices, endpoint=False)
    ring = np.stack([radius * np.cos(t), aspect * radius * np.sin(t)], axis=1)
    c, s = np.cos(angle), np.sin(angle)
    ring = ring @ np.array([[c, s], [-s, c]]) + [x, y]
    return shapely.Polygon(ring)


@settings(max_examples=120, deadline=None)
@given(
    x=st.floats(-60.0, 10.0),
    y=st.floats(-20.0, 20.0),
    radius=st.floats(0.3, 25.0),
    n_vertices=st.integers(3, 64),
    aspect=st.floats(0.1, 1.0),
    angle=st.floats(0.0, np.pi),
)
def test_kernel_matches_shapely_on_convex_floes(geometry, x, y, radius, n_vertices, aspect, angle):
    floes = np.array([_convex_floe(x, y, radius, n_vertices, aspect, angle)], dtype=object)
    fast, fallback = contact._zone_table_kernel(floes, geometry.kernel)
    assert fallback.size == 0  # convex floe, convex bow: the kernel decides alone
    _assert_same(fast, contact._zone_table_shapely(floes, np.arange(1), geometry), floes, geometry)


def test_kernel_matches_shapely_on_a_batch(geometry):
    rng = np.random.default_rng(7)
    floes = np.array(
        [
            _convex_floe(rng.uniform(-60, 10), rng.uniform(-20, 20), rng.uniform(0.5, 20), 64, 1.0, 0.0)
            for _ in range(200)
        ],
        dtype=object,
    )
    index = np.arange(len(floes))
    fast, fallback = contact._zone_table_kernel(floes, geometry.kernel)
    assert fallback.size == 0
    assert fast is not None and len(fast.zones) > 20  # the batch really has floes in contact
    _assert_same(fast, contact._zone_table_shapely(floes, index, geometry), floes, geometry)


def test_floe_inside_the_hull_takes_the_nearest_waterline_point(geometry):
    # a small floe wholly inside H_u, clear of the waterline (a piece the bow has already passed over)
    floes = np.array([shapely.Point(-30.0, 0.0).buffer(1.0)], dtype=object)
    assert shapely.contains(geometry.hull_upper, floes[0])
    assert not shapely.intersects(geometry.waterline, floes[0])
    fast, fallback = contact._zone_table_kernel(floes, geometry.kernel)
    assert fallback.size == 0
    _assert_same(fast, contact._zone_table_shapely(floes, np.arange(1), geometry), floes, geometry)


def test_floe_with_two_zones_goes_to_shapely(geometry):
    # a U-shaped floe around the stem whose arms reach into the hull on both sides: F ∩ H_u has two zones,
    # which the kernel cannot separate; evaluate_contacts still finds both, as GEOS does
    u_shape = shapely.Polygon([(-12, 3), (3, 3), (3, -8), (-12, -8), (-12, -4), (1, -4), (1, 2), (-12, 2)])
    expected = shapely.get_parts(shapely.intersection(u_shape, geometry.hull_upper))
    assert len(expected) == 2
    floes = np.array([u_shape], dtype=object)
    _, fallback = contact._zone_table_kernel(floes, geometry.kernel)
    assert fallback.tolist() == [0]
    (result,) = evaluate_contacts(floes, [1.0], geometry, ContactParams())
    assert sorted(z.a_u_m2 for z in result.zones) == pytest.approx(sorted(shapely.area(expected)), rel=1e-12)


def _star_floe(x, y, radii, angle):
    t = angle + np.linspace(0.0, 2.0 * np.pi, len(radii), endpoint=False)
    return shapely.Polygon(np.stack([x + radii * np.cos(t), y + radii * np.sin(t)], axis=1))


@settings(max_examples=120, deadline=None)
@given(
    x=st.floats(-40.0, 8.0),
    y=st.floats(-12.0, 12.0),
    radii=st.lists(st.floats(0.5, 12.0), min_size=5, max_size=40),
    angle=st.floats(0.0, np.pi),
)
def test_kernel_matches_shapely_on_non_convex_floes(geometry, x, y, radii, angle):
    floes = np.array([_star_floe(x, y, np.array(radii), angle)], dtype=object)
    fast, fallback = contact._zone_table_kernel(floes, geometry.kernel)
    if fallback.size == 0:  # the kernel decided alone (one zone): it must agree with GEOS
        _assert_same(fast, contact._zone_table_shapely(floes, np.arange(1), geometry), floes, geometry)
    else:  # handed over only when F ∩ H_u may have several zones or the boundaries touch
        assert not shapely.get_parts(shapely.intersection(floes[0], geometry.hull_upper)).size == 0


def test_non_convex_bow_has_no_kernel():
    bow = agulhas_ii(ice_thickness_m=1.0)
    hull = np.asarray(bow.hull_upper.exterior.coords)
    dented = hull.copy()
    k = len(hull) // 2  # push one node towards the centre line: H_u is no longer convex
    dented[k] = 0.5 * (hull[k - 1] + hull[k + 1]) * [1.0, 0.2]
    assert contact_kernel.is_convex_ring(contact_kernel.ccw_ring(hull))
    assert not contact_kernel.is_convex_ring(contact_kernel.ccw_ring(dented))
    footprints, upper = np.asarray(bow.panel_footprints, dtype=object), np.asarray(bow.upper_xy_m)
    distance = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(upper, axis=0).T))])
    for ring, convex in ((hull, True), (dented, False)):
        polygon = shapely.Polygon(ring)
        kernel = contact._ConvexBow.from_bow(polygon, footprints, upper, distance, bow.panel_normals)
        assert (kernel is not None) == convex


def test_clip_and_area_of_unit_squares():
    # independent hand values: two unit squares overlapping by half, and a square clipped by a triangle
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    shifted = square + np.array([0.5, 0.0])
    triangle = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    for clip, area in ((shifted, 0.5), (triangle, 0.5), (square + np.array([2.0, 0.0]), 0.0)):
        buf = [np.empty(16) for _ in range(4)]
        subject, clip_x, clip_y = square.T.copy(), clip[:, 0].copy(), clip[:, 1].copy()
        k = contact_kernel._clip_convex(*subject, 4, clip_x, clip_y, len(clip), *buf, 16)
        got = abs(contact_kernel._signed_area(buf[0], buf[1], k)) if k >= 3 else 0.0
        assert got == pytest.approx(area, abs=1e-15)


def _zones(table):
    """[(A_u, centre, centre panel, {panel: A_h})] of a zone table, in the table's zone order."""
    out = []
    for k in range(len(table.zones)):
        rows = table.row_zone == k
        panels = dict(zip(table.row_panel[rows].tolist(), table.row_a_h_m2[rows].tolist(), strict=True))
        out.append((table.a_u_m2[k], table.centre_xy_m[k], int(table.centre_panel[k]), panels))
    return out


@settings(max_examples=80, deadline=None)
@example(x=-8.0, width=2.40625, gap=1.0, reach=3.0, y=0.0)  # a tie: one zone, mirror-symmetric
@given(
    x=st.floats(-30.0, 0.0),
    width=st.floats(0.5, 4.0),
    gap=st.floats(0.5, 10.0),
    reach=st.floats(3.0, 30.0),
    y=st.floats(-3.0, 3.0),
)
def test_zones_found_by_geos_get_the_same_rows_and_centres_compiled(geometry, x, width, gap, reach, y):
    # a U-shaped floe whose two arms reach into the hull on both sides of the stem: two zones, which GEOS
    # separates; their panel rows and centres come from the compiled code and must equal GEOS's
    top, bottom = y + gap / 2.0, y - gap / 2.0
    u_shape = shapely.Polygon(
        [
            (x - reach, top + width),
            (x + 8.0, top + width),
            (x + 8.0, bottom - width),
            (x - reach, bottom - width),
            (x - reach, bottom),
            (x + 8.0 - width, bottom),
            (x + 8.0 - width, top),
            (x - reach, top),
        ]
    )
    floes = np.array([u_shape], dtype=object)
    reference = contact._zone_table_shapely(floes, np.arange(1), geometry)
    compiled = contact._zone_table_zones_by_geos(floes, np.arange(1), geometry)
    if reference is None:
        assert compiled is None
        return
    assert compiled.row_overlap_m.size == compiled.row_zone.size
    for (a_u, centre, panel, rows), (ref_a_u, ref_centre, ref_panel, ref_rows) in zip(
        _zones(compiled), _zones(reference), strict=True
    ):
        assert a_u == ref_a_u  # the same GEOS zones, in the same order
        # ties too (a mirror-symmetric floe: the middle of the tied parts' span): one rule on both paths
        np.testing.assert_allclose(centre, ref_centre, atol=1e-7)
        if panel != ref_panel:  # only a centre on a node may go to either panel
            nodes = shapely.get_coordinates(geometry.waterline)
            assert np.hypot(*(nodes - centre).T).min() < 1e-7
        for p in set(rows) | set(ref_rows):
            assert rows.get(p, 0.0) == pytest.approx(ref_rows.get(p, 0.0), rel=1e-9, abs=1e-10)


def test_zones_found_by_geos_on_a_two_zone_floe(geometry):
    u_shape = shapely.Polygon([(-12, 3), (3, 3), (3, -8), (-12, -8), (-12, -4), (1, -4), (1, 2), (-12, 2)])
    floes = np.array([u_shape], dtype=object)
    compiled = contact._zone_table_zones_by_geos(floes, np.arange(1), geometry)
    reference = contact._zone_table_shapely(floes, np.arange(1), geometry)
    assert len(compiled.zones) == len(reference.zones) == 2
    for got, expected in zip(_zones(compiled), _zones(reference), strict=True):
        np.testing.assert_allclose(got[1], expected[1], atol=1e-9)
        assert got[2] == expected[2]
        assert got[3].keys() == expected[3].keys()
    # the near-vertical guard's length of each panel inside the floe: GEOS's length of segment ∩ F
    rows = compiled.row_panel
    lengths = shapely.length(shapely.intersection(geometry.panel_segments[rows], u_shape))
    np.testing.assert_allclose(compiled.row_overlap_m, lengths, rtol=1e-9, atol=1e-12)
