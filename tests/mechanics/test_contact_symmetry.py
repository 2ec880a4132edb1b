"""Contact of a mirror-symmetric floe on the centreline of the symmetric reference bow (mirror
symmetry): the zone centre, its normal and the dominant zone must not take one side. Expected values come
from the symmetry alone (a centre on the stem, a normal along the centreline) and from thesis Eq. 20 (the
node normal from the neighbouring nodes), computed here from the bow's nodes."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from floebreak.mechanics import contact, contact_kernel
from floebreak.mechanics.contact import BowContactGeometry, ContactParams, evaluate_contact
from floebreak.ship.hulls import agulhas_ii

BOW = agulhas_ii(ice_thickness_m=1.0)
GEOMETRY = BowContactGeometry.from_bow(BOW)
PARAMS = ContactParams()


def _mirror(polygon):
    return shapely.transform(polygon, lambda xy: xy * np.array([1.0, -1.0]))


def _orders(polygon):
    """The same outline with its ring reversed and started at another vertex: GEOS returns zones in an
    order that follows the ring, which must not decide anything."""
    ring = np.asarray(polygon.exterior.coords)[:-1]
    return [
        shapely.Polygon(r) for r in (ring, ring[::-1], np.roll(ring, 5, axis=0), np.roll(ring[::-1], 3, 0))
    ]


def test_the_bow_is_symmetric_about_the_centreline():
    assert shapely.equals(_mirror(BOW.hull_upper), BOW.hull_upper)
    nodes = np.asarray(BOW.upper_xy_m)
    stem = int(np.argmax(nodes[:, 0]))
    assert np.array_equal(nodes[stem], [0.0, 0.0])


def test_a_floe_centred_ahead_of_the_stem_is_loaded_on_the_stem_along_the_centreline():
    # a 64-gon of radius 10 m centred at x = 9.5 m on y = 0: the bow has pushed 0.5 m into it
    t = 2 * np.pi * np.arange(64) / 64
    floe = shapely.Polygon(np.c_[9.5 + 10 * np.cos(t), 10 * np.sin(t)])
    for outline in _orders(floe):
        zone = evaluate_contact(outline, 1.0, GEOMETRY, PARAMS).dominant
        np.testing.assert_allclose(zone.centre_xy_m, [0.0, 0.0], atol=1e-12)
        # thesis Eq. 20 at the stem node: (y_(i−1) − y_(i+1), x_(i+1) − x_(i−1)) of two mirror nodes is +x
        np.testing.assert_allclose(zone.centre_normal, [1.0, 0.0], atol=1e-12)
        for params in (PARAMS, ContactParams(area_model="single_psi")):  # per panel; one ψ (thesis Eq. 6)
            force_x, force_y = evaluate_contact(outline, 1.0, GEOMETRY, params).dominant.force_on_ice_xy_n
            assert force_x > 0.0 and abs(force_y) <= 1e-9 * force_x  # pushed ahead, not aside


def test_an_off_node_centre_keeps_its_panels_normal():
    floe = shapely.box(-3.0, 1.0, 3.0, 6.0)  # touches the port side only
    zone = evaluate_contact(floe, 1.0, GEOMETRY, PARAMS).dominant
    nodes = np.asarray(BOW.upper_xy_m)
    assert np.hypot(*(nodes - zone.centre_xy_m).T).min() > 1e-6
    np.testing.assert_array_equal(zone.centre_normal, GEOMETRY.panel_normals[zone.centre_panel])


@pytest.mark.parametrize("k", [1, 10, 20, 31, 45, 61])
def test_the_normal_on_a_node_is_thesis_eq_20(k):
    nodes = np.asarray(BOW.upper_xy_m)
    eq20 = np.array([nodes[k - 1, 1] - nodes[k + 1, 1], nodes[k + 1, 0] - nodes[k - 1, 0]])
    eq20 /= np.hypot(*eq20)
    eq20 *= np.sign(eq20 @ GEOMETRY.panel_normals[k])  # "multiplied by −1 … to point outwards"
    for panel in (k - 1, k):  # the node ends one panel and starts the next: the same normal either way
        got = contact_kernel.centre_normal(*nodes[k], panel, GEOMETRY.waterline_xy_m, GEOMETRY.panel_normals)
        np.testing.assert_allclose(got, eq20, atol=1e-12)
    middle = 0.5 * (nodes[k] + nodes[k + 1])  # off the nodes: the panel's own normal
    got = contact_kernel.centre_normal(*middle, k, GEOMETRY.waterline_xy_m, GEOMETRY.panel_normals)
    np.testing.assert_array_equal(got, GEOMETRY.panel_normals[k])


@pytest.mark.parametrize("depth_m", [0.0, 0.25])
def test_a_floe_whose_far_corner_the_stem_reaches_is_loaded_on_the_stem(depth_m):
    # the bow has run into a floe from behind up to its far corner, a right angle on the centreline: at the
    # stem (depth 0: the two parts of waterline ∩ F meet there) or 0.25 m past it (the stem in open water
    # between two equal parts). The bow is narrower than the corner, so the waterline runs inside the floe
    # on both sides; by symmetry the load centre is the stem, and the normal the centreline
    corner = shapely.Polygon([(-depth_m, 0.0), (-9.0, 9.0), (-14.0, 9.0), (-14.0, -9.0), (-9.0, -9.0)])
    for outline in _orders(corner):
        zone = evaluate_contact(outline, 1.0, GEOMETRY, PARAMS).dominant  # the compiled kernel's path
        np.testing.assert_allclose(zone.centre_xy_m, [0.0, 0.0], atol=1e-12)
        np.testing.assert_allclose(zone.centre_normal, [1.0, 0.0], atol=1e-12)
        by_geos = contact._zone_table_shapely(np.array([outline], dtype=object), np.arange(1), GEOMETRY)
        np.testing.assert_allclose(by_geos.centre_xy_m[0], [0.0, 0.0], atol=1e-12)


def test_equal_shoulder_zones_go_to_the_port_zone_whatever_the_ring_order():
    # a U-shaped floe around the bow whose two arms reach into the hull at both shoulders, mirror-symmetric:
    # two zones whose crushing forces are equal up to rounding; the documented rule picks the port one
    u_shape = shapely.Polygon(
        [(-30, 12), (5, 12), (5, -12), (-30, -12), (-30, -9.5), (2, -9.5), (2, 9.5), (-30, 9.5)]
    )
    for outline in _orders(u_shape):
        both = evaluate_contact(outline, 1.0, GEOMETRY, PARAMS)
        assert len(both.zones) == 2
        port, starboard = sorted(both.zones, key=lambda z: -z.centre_xy_m[1])
        assert port.crushing_force_n == pytest.approx(starboard.crushing_force_n, rel=1e-12)
        assert both.dominant is port
