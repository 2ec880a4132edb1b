"""The batched contact evaluation gives the same contacts as evaluating floe by floe (a performance path)."""

import numpy as np
import pytest
import shapely

from floebreak.mechanics.contact import BowContactGeometry, ContactParams, evaluate_contact, evaluate_contacts
from floebreak.ship.hulls import agulhas_ii


def _floes() -> np.ndarray:
    rng = np.random.default_rng(3)
    floes = [
        shapely.Point(x, y).buffer(r, 16)
        for x, y, r in zip(
            rng.uniform(-30.0, 5.0, 12), rng.uniform(-14.0, 14.0, 12), rng.uniform(0.5, 6.0, 12), strict=True
        )
    ]
    floes.append(shapely.box(20.0, -1.0, 22.0, 1.0))  # far ahead of the bow: no contact
    # a U-shaped floe wrapping the stem: two contact zones
    floes.append(shapely.box(-6.0, -8.0, 4.0, 8.0).difference(shapely.box(-7.0, -2.0, 1.0, 2.0)))
    return np.array(floes, dtype=object)


def test_batch_equals_one_by_one():
    geometry = BowContactGeometry.from_bow(agulhas_ii(ice_thickness_m=1.0))
    params = ContactParams()
    floes = _floes()
    thickness = np.linspace(0.5, 1.5, len(floes))
    batch = evaluate_contacts(floes, thickness, geometry, params)
    assert len(batch) == len(floes)
    assert not batch[-2].in_contact
    assert len(batch[-1].zones) == 2
    assert sum(c.in_contact for c in batch) >= 5
    for floe, h, contact in zip(floes, thickness, batch, strict=True):
        single = evaluate_contact(floe, float(h), geometry, params)
        assert len(single.zones) == len(contact.zones)
        for a, b in zip(single.zones, contact.zones, strict=True):
            assert a.zone == b.zone and a.centre_panel == b.centre_panel
            np.testing.assert_array_equal(a.panels, b.panels)
            np.testing.assert_array_equal(a.a_h_m2, b.a_h_m2)
            np.testing.assert_array_equal(a.f_c_n, b.f_c_n)
            np.testing.assert_array_equal(a.centre_xy_m, b.centre_xy_m)
            assert shapely.equals_exact(a.overlap_upper, b.overlap_upper, tolerance=0.0)


def test_batch_zone_areas_match_independent_overlays():
    """A_u is the area of floe ∩ H_u per zone, and Σ A_h,i = A_u − A_l (footprints tile H_u \\ H_l)."""
    geometry = BowContactGeometry.from_bow(agulhas_ii(ice_thickness_m=1.0))
    floes = _floes()
    for floe, contact in zip(
        floes, evaluate_contacts(floes, np.ones(len(floes)), geometry, ContactParams()), strict=True
    ):
        expected = shapely.area(shapely.intersection(floe, geometry.hull_upper))
        assert abs(sum(z.a_u_m2 for z in contact.zones) - expected) <= 1e-9 * max(expected, 1.0)
        for zone in contact.zones:
            assert abs(zone.a_h_total_m2 - (zone.a_u_m2 - zone.a_l_m2)) <= 1e-9 * max(zone.a_u_m2, 1.0)


def test_a_blunt_bow_whose_footprints_are_bow_ties_is_evaluated_by_geos():
    # found by a random sweep of hull parameters: at an entrance half-angle of 88.5° the lower waterline
    # crosses the upper one's projection, and two panels' plan-view footprints are bow-ties, i.e. two
    # triangles (a MultiPolygon); preparing the compiled kernel's convex quads then raised AttributeError
    from floebreak.ship.hulls import parametric_bow

    bow = parametric_bow(
        "blunt",
        beam_m=23.9,
        waterline_entrance_half_angle_deg=88.5,
        stem_angle_deg=85.3,
        shape_exponent=1.95,
        midbody_length_m=1.8,
        ice_thickness_m=0.83,
    )
    assert (shapely.get_type_id(bow.panel_footprints) == 6).any()
    geometry = BowContactGeometry.from_bow(bow)
    assert geometry.kernel is None  # the GEOS path, which takes any footprint
    floe = shapely.Point(-1.0, 0.0).buffer(5.0)  # across the stem
    (contact,) = evaluate_contacts(np.array([floe]), np.array([0.83]), geometry, ContactParams())
    assert contact.in_contact
    # the zone's A_u is the floe's overlap with the hull, as GEOS measures it directly
    expected = shapely.intersection(floe, bow.hull_upper).area
    assert sum(z.a_u_m2 for z in contact.zones) == pytest.approx(expected, rel=1e-9)
