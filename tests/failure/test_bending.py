"""Failure by bending (thesis §4.1, Eq. 11, Alg. 4; physics-notes §1, §2.5).

Expectations are computed here from physics-notes: P_f = σ_f Θ h² / (6 S(ρ)) with S from the §1.3 table,
the bending line at ξ_σ(ρ) ℓ from the wedge origin O (§1.1 Eq. 1.5, §2.5 step 6), and the panel-0 contact
forces by hand (conftest). The floe is a rectangle pressed against the straight midbody panel, so
A_h = W p exactly and O lies on the straight waterline at the middle of the rectangle.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
import shapely

from floebreak.config.profiles import build_model
from floebreak.failure import Bending, BendingSettings, Fate, Status
from floebreak.failure.bending import bending_check
from floebreak.ship.hulls import agulhas_ii
from floebreak.studies.single_floe import SingleFloeCase, run_case

WIDTH_M = 9.0  # along the panel (x)
LENGTH_M = 20.0  # along the outward normal (+y)
PHI_RAD = math.radians(5.0)  # wedge discretisation angle


def fan_opening_rad(make_input, context, kit, thickness_m=1.0):
    """Θ of the intact-ice fan at panel 0: a half-plane, exactly 180° (36 rays of 5°, none along the
    straight waterline)."""
    inp = make_input(kit.midbody_box(WIDTH_M, LENGTH_M, 0.05), thickness_m)
    opening = bending_check(inp, context, BendingSettings()).fan.opening_rad
    assert math.degrees(opening) == pytest.approx(180.0)
    return opening


def test_panel0_contact_is_the_hand_calculation(make_input, kit):
    p = 0.1
    inp = make_input(kit.midbody_box(WIDTH_M, LENGTH_M, p))
    fv_per_area, fh_per_area = kit.panel0_forces_per_area()
    assert len(inp.contact.zones) == 1
    assert inp.zone.a_h_total_m2 == pytest.approx(WIDTH_M * p, rel=1e-9)
    assert inp.zone.vertical_force_n == pytest.approx(fv_per_area * WIDTH_M * p, rel=1e-9)
    assert inp.zone.horizontal_force_n == pytest.approx(fh_per_area * WIDTH_M * p, rel=1e-9)
    np.testing.assert_allclose(inp.zone.centre_xy_m, [kit.panel0_x_centre_m, kit.panel0_y_m], atol=1e-9)
    np.testing.assert_allclose(inp.zone.centre_normal, [0.0, 1.0], atol=1e-12)


@pytest.mark.parametrize("rho", [0.03, 0.075, 0.10])
def test_capacity_and_verdict_at_a_tabulated_rho(make_input, context, kit, rho):
    h = 1.0
    ell = kit.ell_m(h)
    assert ell == pytest.approx(11.62, abs=0.01)  # physics-notes §0
    theta = fan_opening_rad(make_input, context, kit, h)
    # penetration that makes r = √(2 A_h/Θ) = ρ ℓ with A_h = W p
    p = (rho * ell) ** 2 * theta / (2.0 * WIDTH_M)
    assert p < 0.36  # stays above the lower waterline, A_h = W p
    inp = make_input(kit.midbody_box(WIDTH_M, LENGTH_M, p), h)
    check = bending_check(inp, context, BendingSettings())
    assert check.fan.opening_rad == pytest.approx(theta)
    assert check.fan.loading_radius_m == pytest.approx(rho * ell, rel=1e-9)
    s, xi_sigma, _ = kit.table[rho]
    expected_capacity = kit.nevel_capacity_n(h, theta, s)
    assert check.capacity_n == pytest.approx(expected_capacity, rel=2e-3)
    assert check.breaking_radius_m == pytest.approx(xi_sigma * ell, rel=3e-3)
    f_v = kit.panel0_forces_per_area()[0] * WIDTH_M * p
    must_fail = f_v > expected_capacity
    assert max(f_v, expected_capacity) / min(f_v, expected_capacity) > 1.5  # clear either way
    outcome = Bending().evaluate(inp, context)
    assert outcome.failed == must_fail
    assert outcome.status is (Status.FAILED if must_fail else Status.INTACT)  # F_v ≤ P_f: the floe holds


@pytest.mark.parametrize("rho", [0.075, 0.10])
def test_max_moment_breaking_distance(make_input, context, kit, rho):
    """Thesis-literal breaking length (erratum 11): the moment maximum ξ_M ℓ ≈ 1.6 ℓ from O."""
    ell = kit.ell_m(1.0)
    theta = fan_opening_rad(make_input, context, kit)
    p = (rho * ell) ** 2 * theta / (2.0 * WIDTH_M)
    inp = make_input(kit.midbody_box(WIDTH_M, 40.0, p))
    check = bending_check(inp, context, BendingSettings(breaking_length_mode="max_moment"))
    assert check.breaking_radius_m == pytest.approx(kit.table[rho][2] * ell, rel=3e-3)


@pytest.mark.parametrize(
    ("penetration_m", "thickness_m", "must_bend"),
    [
        (0.02, 1.0, False),  # F_v = 0.12 MN < P_f ≈ 0.3 MN
        (0.30, 1.0, True),  # F_v = 2.0 MN > P_f ≈ 0.36 MN
        (0.149, 0.5, True),  # thin ice: P_f ≈ 0.1 MN
        (0.149, 2.5, False),  # thick ice: P_f ≈ 2 MN > F_v = 1.0 MN
    ],
)
def test_floe_bends_exactly_when_the_vertical_force_exceeds_the_capacity(
    make_input, context, kit, penetration_m, thickness_m, must_bend
):
    theta = fan_opening_rad(make_input, context, kit, thickness_m)
    a_h = WIDTH_M * penetration_m
    f_v = kit.panel0_forces_per_area()[0] * a_h
    rho = math.sqrt(2.0 * a_h / theta) / kit.ell_m(thickness_m)
    low, high = kit.capacity_bracket_n(thickness_m, theta, rho)
    assert (f_v > 1.3 * high) if must_bend else (f_v < low / 1.3)  # the case is clear-cut
    inp = make_input(kit.midbody_box(WIDTH_M, LENGTH_M, penetration_m), thickness_m)
    outcome = Bending().evaluate(inp, context)
    assert outcome.failed is must_bend
    check = bending_check(inp, context, BendingSettings())
    assert low <= check.capacity_n <= high
    assert check.vertical_force_n == pytest.approx(f_v, rel=1e-9)
    # the outcome's margin ln(F_v / P_f), from the hand calculation's capacity bracket, of the verdict's sign
    assert math.log(f_v / high) - 1e-9 <= outcome.margin <= math.log(f_v / low) + 1e-9
    assert (outcome.margin > 0.0) is must_bend
    if must_bend:
        assert len(outcome.pieces) >= 2
        assert all(piece.fate == Fate.FLOE for piece in outcome.pieces)
    else:
        assert outcome.pieces == ()


def test_thesis_a4_lookup_takes_the_capacity_of_1_2_m_ice_at_1_m(make_input, context, kit):
    """`capacity_lookup = "thesis_a4"` (thesis App. A.4, erratum 12): at h = 1.0 m the capacity is the mean of
    Eq. 1.4 at h = 1.2 m over the two radius grid values around r (Θ = 180° is on the grid); the breaking
    radius is still that of the ice as it is."""
    theta = fan_opening_rad(make_input, context, kit)
    penetration_m = 0.03
    a_h = WIDTH_M * penetration_m
    r = math.sqrt(2.0 * a_h / theta)  # 0.415 m: between the grid values 0.3 and 0.6 m
    assert 0.3 < r < 0.6
    brackets = [kit.capacity_bracket_n(1.2, theta, grid_r / kit.ell_m(1.2)) for grid_r in (0.3, 0.6)]
    low = sum(b[0] for b in brackets) / 2
    high = sum(b[1] for b in brackets) / 2
    inp = make_input(kit.midbody_box(WIDTH_M, LENGTH_M, penetration_m), 1.0)
    direct = bending_check(inp, context, BendingSettings())
    looked_up = bending_check(inp, context, BendingSettings(capacity_lookup="thesis_a4"))
    assert low <= looked_up.capacity_n <= high
    assert looked_up.capacity_n > 1.3 * direct.capacity_n  # ≈ (1.2/1.0)² up to S(r/ℓ)
    assert looked_up.breaking_radius_m == direct.breaking_radius_m


def test_bending_line_at_xi_sigma_ell_and_area_conserved(make_input, context, kit):
    rho = 0.075
    ell = kit.ell_m(1.0)
    theta = fan_opening_rad(make_input, context, kit)
    p = (rho * ell) ** 2 * theta / (2.0 * WIDTH_M)
    floe = kit.midbody_box(WIDTH_M, LENGTH_M, p)
    inp = make_input(floe)
    outcome = Bending().evaluate(inp, context)
    assert outcome.failed
    radius = kit.table[rho][1] * ell  # ξ_σ ℓ = 6.23 m
    origin = shapely.Point(inp.zone.centre_xy_m)
    polygons = [piece.polygon for piece in outcome.pieces]
    near = [q for q in polygons if shapely.hausdorff_distance(origin, q) <= radius * 1.003]
    far = [q for q in polygons if q not in near]
    assert len(near) == 1 and len(far) == 1  # the rectangle is cut once by the arc
    # the bending line = the boundary shared by the two pieces: a polygonised arc of radius ξ_σ ℓ about O
    # (5° polygon: vertices on the circle, chords at most cos(2.5°) closer)
    shared = shapely.intersection(near[0].boundary, far[0].boundary)
    assert shared.length > 0.5 * radius  # a line, not a point
    distance = np.hypot(*(shapely.get_coordinates(shared) - inp.zone.centre_xy_m).T)
    assert np.all(distance <= radius * 1.003)
    assert np.all(distance >= radius * math.cos(PHI_RAD / 2.0) / 1.003)
    # the arc crosses the whole width of the floe
    assert shared.length >= WIDTH_M
    total = sum(q.area for q in polygons)
    assert total == pytest.approx(floe.area, rel=1e-9)
    assert shapely.area(shapely.intersection(near[0], far[0])) <= 1e-9 * floe.area
    assert all(q.is_valid for q in polygons)


# --------------------------------------------------------------------------------------------------------
# Whole runs: a single 20 m floe straight ahead of the bow (thesis §5.2, Fig. 14 position e), step 0.25 m
# --------------------------------------------------------------------------------------------------------

UNBREAKABLE_AREA_M2 = 13.5 * 1.0**0.75  # A_rotate = 1 m · 13.5 h^(3/4) at h = 1 m (thesis Eq. 5, erratum 8)


@functools.cache
def single_floe_run(profile: str):
    bow = agulhas_ii(ice_thickness_m=1.0)
    return run_case(SingleFloeCase("e", 20.0, 1.0), bow, build_model(profile), step_m=0.25)


@pytest.mark.parametrize("profile", ["default", "thesis"])
def test_whole_run_conserves_area(profile):
    result = single_floe_run(profile)
    assert result.n_breaks >= 1
    total = result.area_m2("cusp") + result.area_m2("flipped") + result.area_m2("remaining")
    initial = 0.5 * 64 * 10.0**2 * math.sin(2.0 * math.pi / 64)  # the regular 64-gon of radius 10 m
    assert abs(total - initial) <= 1e-9 * initial
    assert result.area_balance_rel_error <= 1e-9


@pytest.mark.parametrize("profile", ["default", "thesis"])
def test_cusps_from_direct_rotation_are_unbreakable_by_size(profile):
    result = single_floe_run(profile)
    rotated = [
        i for i in np.flatnonzero(result.mask("cusp")) if result.failure_chain(i)[-1:] == ("rotation",)
    ]
    assert all(result.polygon[i].area <= UNBREAKABLE_AREA_M2 for i in rotated)


@pytest.mark.parametrize("profile", ["default", "thesis"])
def test_every_cusp_is_unbreakable_by_the_classification_rule(profile):
    result = single_floe_run(profile)
    cusps = result.polygon[result.mask("cusp")]
    assert len(cusps) >= 1
    too_big = [
        (p.area, result.failure_chain(i))
        for i, p in zip(np.flatnonzero(result.mask("cusp")), cusps, strict=True)
        if p.area > UNBREAKABLE_AREA_M2
    ]
    assert not too_big, too_big
