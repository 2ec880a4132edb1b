"""Contact mechanics against hand calculations (thesis Eqs. 6–10, physics-notes §2.2–2.3)."""

from types import SimpleNamespace

import numpy as np
import pytest
import shapely

from floebreak.errors import InputError
from floebreak.mechanics.contact import BowContactGeometry, ContactParams, evaluate_contact, panel_forces


def box_bow(psi_deg: float, dz_m: float = 1.0, half_width_m: float = 5.0, length_m: float = 20.0):
    """A blunt 'bow' with one flat front panel of angle ψ (from vertical) facing +x and vertical sides.

    Upper front face at x = 0; the lower waterline lies d = Δz tan ψ aft of it.
    """
    d = dz_m * np.tan(np.radians(psi_deg))
    b, length = half_width_m, length_m
    upper = np.array([[-length, b], [0.0, b], [0.0, -b], [-length, -b]])
    lower = np.array([[-length, b], [-d, b], [-d, -b], [-length, -b]])
    footprints = np.array(
        [shapely.Polygon([upper[i], upper[i + 1], lower[i + 1], lower[i]]).buffer(0) for i in range(3)],
        dtype=object,
    )
    return SimpleNamespace(
        upper_xy_m=upper,
        lower_xy_m=lower,
        hull_upper=shapely.Polygon(upper),
        hull_lower=shapely.Polygon(lower),
        panel_footprints=footprints,
        panel_normals=np.array([[0.0, 1.0], [1.0, 0.0], [0.0, -1.0]]),
        panel_psi_rad=np.radians([0.0, psi_deg, 0.0]),
    ), d


SIGMA_C = 1.28e6
MU = 0.15


@pytest.mark.parametrize("psi_deg", [20.0, 46.3, 63.0])
@pytest.mark.parametrize("penetration_m", [0.2, 0.5, 2.0])
def test_rectangular_floe_on_flat_panel_by_hand(psi_deg, penetration_m):
    bow, d = box_bow(psi_deg)
    geometry = BowContactGeometry.from_bow(bow)
    half_w = 2.0
    floe = shapely.box(-penetration_m, -half_w, 20.0, half_w)
    contact = evaluate_contact(floe, 1.0, geometry, ContactParams())
    assert len(contact.zones) == 1
    zone = contact.zones[0]
    # independent hand calculation
    a_u = 2 * half_w * penetration_m
    a_h = 2 * half_w * min(penetration_m, d)
    a_l = a_u - a_h
    psi = np.radians(psi_deg)
    a_c = a_h / np.sin(psi)
    f_c = SIGMA_C * a_c
    f_v = f_c * (np.sin(psi) - MU * np.cos(psi))
    f_h = f_c * (np.cos(psi) + MU * np.sin(psi))
    assert zone.a_u_m2 == pytest.approx(a_u, rel=1e-9)
    assert zone.a_l_m2 == pytest.approx(a_l, rel=1e-9, abs=1e-12)
    assert zone.a_h_total_m2 == pytest.approx(a_h, rel=1e-9)
    assert zone.a_c_m2.sum() == pytest.approx(a_c, rel=1e-9)
    assert zone.crushing_force_n == pytest.approx(f_c, rel=1e-9)
    assert zone.vertical_force_n == pytest.approx(f_v, rel=1e-9)
    assert zone.horizontal_force_n == pytest.approx(f_h, rel=1e-9)
    # the horizontal force pushes the ice forward (+x), along the panel's outward normal
    np.testing.assert_allclose(zone.force_on_ice_xy_n, [f_h, 0.0], atol=1e-6 * f_h)
    np.testing.assert_allclose(contact.force_on_bow_xyz_n, [-f_h, 0.0, f_v], rtol=1e-9, atol=1e-6)
    assert zone.centre_panel == 1
    np.testing.assert_allclose(zone.centre_xy_m, [0.0, 0.0], atol=1e-12)


def test_thesis_alg3_and_eq9_10_signs():
    psi = np.radians([46.3, 63.0])  # the Agulhas II stem ψ_v (physics-notes §6.3) and the thesis 63°
    area = np.array([1.0, 1.0])
    f_c, _f_v, f_h = panel_forces(area, psi, ContactParams(force_signs="consistent"))
    # physics-notes §2.3 example: F_h/F_c = 0.80 (46°) and 0.59 (63°) with the correct sign
    np.testing.assert_allclose(f_h / f_c, [0.80, 0.59], atol=0.005)
    _, _, f_h_alg3 = panel_forces(area, psi, ContactParams(force_signs="thesis_alg3"))
    np.testing.assert_allclose(f_h_alg3 / f_c, [0.58, 0.32], atol=0.005)  # Alg. 3 friction sign
    _, f_v_eq, f_h_eq = panel_forces(area, psi, ContactParams(force_signs="thesis_eq9_10"))
    np.testing.assert_allclose(f_v_eq / f_c, np.cos(psi) - 0.15 * np.sin(psi))
    np.testing.assert_allclose(f_h_eq / f_c, np.sin(psi) + 0.15 * np.cos(psi))


def test_vertical_force_clamped_when_tan_psi_below_mu():
    # physics-notes §2.3: F_v ≤ 0 when tan ψ ≤ μ (ψ ≤ 8.5° for μ = 0.15) → clamped to 0
    _, f_v, _ = panel_forces(np.array([1.0]), np.radians([5.0]), ContactParams())
    assert f_v[0] == 0.0


def test_near_vertical_panel_uses_vertical_face_area():
    bow, d = box_bow(5.0)  # below ψ_min = 10°
    geometry = BowContactGeometry.from_bow(bow)
    floe = shapely.box(-1.0, -2.0, 20.0, 2.0)
    zone = evaluate_contact(floe, 0.8, geometry, ContactParams()).zones[0]
    # vertical face: A_c = h × overlap length along the waterline = 0.8 m × 4 m
    assert zone.a_c_m2.sum() == pytest.approx(0.8 * 4.0)
    capped = evaluate_contact(floe, 0.8, geometry, ContactParams(near_vertical="cap")).zones[0]
    assert capped.a_c_m2.sum() == pytest.approx(4.0 * d / np.sin(np.radians(10.0)))
    literal = evaluate_contact(floe, 0.8, geometry, ContactParams(near_vertical="none")).zones[0]
    assert literal.a_c_m2.sum() == pytest.approx(4.0 * d / np.sin(np.radians(5.0)))


def test_single_psi_thesis_area_model_equals_per_panel_on_one_panel():
    bow, _ = box_bow(30.0)
    geometry = BowContactGeometry.from_bow(bow)
    floe = shapely.box(-0.3, -2.0, 20.0, 2.0)
    per_panel = evaluate_contact(floe, 1.0, geometry, ContactParams()).zones[0]
    single = evaluate_contact(floe, 1.0, geometry, ContactParams(area_model="single_psi")).zones[0]
    assert single.crushing_force_n == pytest.approx(per_panel.crushing_force_n)


def test_no_contact_returns_empty():
    bow, _ = box_bow(30.0)
    contact = evaluate_contact(
        shapely.box(0.5, -1, 3, 1), 1.0, BowContactGeometry.from_bow(bow), ContactParams()
    )
    assert not contact.in_contact


def test_two_zones_for_a_floe_wrapping_the_bow():
    bow, d = box_bow(30.0)
    # a U-shaped floe touching the front face at two separate places
    floe = shapely.union(shapely.box(-0.2, 1.0, 5.0, 3.0), shapely.box(-0.2, -3.0, 5.0, -1.0))
    floe = shapely.union(floe, shapely.box(4.0, -3.0, 5.0, 3.0))
    contact = evaluate_contact(floe, 1.0, BowContactGeometry.from_bow(bow), ContactParams())
    assert len(contact.zones) == 2
    for zone in contact.zones:
        assert zone.a_h_total_m2 == pytest.approx(2.0 * min(0.2, d))


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"friction_coefficient": -0.1}, "friction_coefficient"),
        ({"crushing_strength_pa": 0.0}, "crushing_strength_pa"),
        ({"psi_min_deg": 0.0}, "psi_min_deg"),
        ({"psi_min_deg": 45.0}, "psi_min_deg"),
    ],
)
def test_bad_contact_params(kwargs, field):
    with pytest.raises(InputError, match=field):
        ContactParams(**kwargs)
