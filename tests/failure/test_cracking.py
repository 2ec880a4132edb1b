"""Global failure by cracking (thesis §4.2, Alg. 5 and 7, Eq. 20; physics-notes §3.3, §4).

Floes are rectangles pressed against the straight midbody panel (conftest): the crack line must run along
the panel normal (+y) through the zone centre O and cross the whole floe; a piece that has cracked before
cracks along a line rotated by α_nextcrack = 30° (thesis §4.2.3, Fig. 11). Each criterion is made to fail and
not to fail where an independent calculation from physics-notes §4 says so.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from scipy.optimize import brentq

from floebreak.failure import Cracking, CrackingSettings, Fate
from floebreak.failure.bending import BendingSettings, bending_check
from floebreak.failure.cracking import crack_direction, indentation_depth_m

WIDTH_M = 9.0  # along the panel: w > l → cracking class (thesis Eq. 4)
LENGTH_M = 6.0  # along the panel normal


def criterion_check(cracking: Cracking, inp, context):
    """The crack criterion's driving and resistance at this contact (`fracture.CrackCheck`)."""
    direction = crack_direction(inp, math.radians(cracking.settings.next_crack_angle_deg))
    return cracking.criterion_check(inp, context, direction)


def kappa(tip_angle_deg: float = 64.54) -> float:
    """F_cr / F_h = 1 / (2 tan(α/2)) (thesis Alg. 7, physics-notes §3.3 with μ = 0)."""
    return 1.0 / (2.0 * math.tan(math.radians(tip_angle_deg) / 2.0))


def bz_strength_pa(size_m: float) -> float:
    """BZ size-effect law σ = 0.68 (1 + L/0.26)^(−1/2) MPa (thesis Eq. 15, physics-notes §4.1)."""
    return 0.68e6 / math.sqrt(1.0 + size_m / 0.26)


def tada_factor(eps: float, polynomial: str) -> float:
    """√(tan t/t) G(ε), t = πε/2; "tension" G_T or "bending" G_B (Tada; physics-notes §4.3)."""
    t = math.pi * eps / 2.0
    if polynomial == "tension":
        g = (0.752 + 2.02 * eps + 0.37 * (1.0 - math.sin(t)) ** 3) / math.cos(t)
    else:
        g = (0.923 + 0.199 * (1.0 - math.sin(t)) ** 4) / math.cos(t)
    return math.sqrt(math.tan(t) / t) * g


def thickness_for_ell_over_5(kit, a_m: float) -> float:
    """h with ℓ(h)/5 = a (ℓ ∝ h^(3/4))."""
    return (5.0 * a_m / kit.ell_m(1.0)) ** (4.0 / 3.0)


def test_first_crack_runs_along_the_normal_and_crosses_the_whole_floe(make_input, context, kit):
    p = 0.1
    floe = kit.midbody_box(WIDTH_M, LENGTH_M, p)
    inp = make_input(floe)
    assert inp.classification.failure_class == "cracking"
    # point_load with P_t = σ_t h b: F_h = 3.3 MN > 0.342 MPa · 1 m · 6 m = 2.05 MN
    outcome = Cracking(CrackingSettings(criterion="point_load", point_load_capacity="tensile_Pt")).evaluate(
        inp, context
    )
    assert outcome.failed
    assert len(outcome.pieces) == 2
    assert all(piece.fate == Fate.FLOE and piece.crack_count == 1 for piece in outcome.pieces)
    x_o = inp.zone.centre_xy_m[0]
    # the crack line is x = x_O: the pieces are the two halves of the rectangle
    far_edge = shapely.LineString(
        [(x_o - WIDTH_M, kit.panel0_y_m - p + LENGTH_M), (x_o + WIDTH_M, kit.panel0_y_m - p + LENGTH_M)]
    )
    for piece in outcome.pieces:
        assert piece.polygon.area == pytest.approx(WIDTH_M * LENGTH_M / 2.0, rel=1e-9)
        assert shapely.intersection(piece.polygon.boundary, far_edge).length == pytest.approx(WIDTH_M / 2.0)
    shared = shapely.intersection(outcome.pieces[0].polygon.boundary, outcome.pieces[1].polygon.boundary)
    coords = shapely.get_coordinates(shared)
    np.testing.assert_allclose(coords[:, 0], x_o, atol=1e-9)  # along n̂ = +y through O
    assert np.ptp(coords[:, 1]) == pytest.approx(LENGTH_M, rel=1e-9)  # through the whole floe


@pytest.mark.parametrize("sign_of_offset", [1.0, -1.0])
def test_later_crack_is_rotated_by_30_degrees(make_input, context, kit, sign_of_offset):
    p = 0.1
    # centre the floe a little off O so that one of the two ±30° lines passes closer to the centroid
    floe = kit.midbody_box(WIDTH_M, LENGTH_M, p, x_centre_m=kit.panel0_x_centre_m + 0.5 * sign_of_offset)
    inp = make_input(floe, crack_count=1)
    settings = CrackingSettings(criterion="point_load", point_load_capacity="tensile_Pt")
    outcome = Cracking(settings).evaluate(inp, context)
    assert outcome.failed and len(outcome.pieces) == 2
    assert all(piece.crack_count == 2 for piece in outcome.pieces)
    shared = shapely.line_merge(
        shapely.intersection(outcome.pieces[0].polygon.boundary, outcome.pieces[1].polygon.boundary)
    )
    start, end = shapely.get_coordinates(shared)[[0, -1]]
    direction = (end - start) / np.hypot(*(end - start))
    angle = math.degrees(math.acos(abs(direction[1])))  # angle to the normal n̂ = +y
    assert angle == pytest.approx(30.0, abs=1e-6)
    # the line passes through O
    o = inp.zone.centre_xy_m
    assert abs(direction[0] * (o[1] - start[1]) - direction[1] * (o[0] - start[0])) < 1e-9
    # independent areas of the two trapezoids cut by x = x_O + s (y − y_O), s = ±tan 30°
    x_left = floe.bounds[0]
    y0, y1 = floe.bounds[1], floe.bounds[3]
    areas = []
    for s in (math.tan(math.radians(30.0)), -math.tan(math.radians(30.0))):
        left = (y1 - y0) * (o[0] - x_left) + s * ((y1 - o[1]) ** 2 - (y0 - o[1]) ** 2) / 2.0
        areas.append(sorted([left, floe.area - left]))
    got = sorted(piece.polygon.area for piece in outcome.pieces)
    assert any(got == pytest.approx(a, rel=1e-9) for a in areas)
    assert sum(got) == pytest.approx(floe.area, rel=1e-9)


@pytest.mark.parametrize(("thickness_m", "must_fail"), [(1.0, True), (2.0, False)])
def test_point_load_tensile_capacity(make_input, context, kit, thickness_m, must_fail):
    """F_h > P_t = σ_t h b, σ_t = 4.278 ν_t^(−0.6455) MPa = 0.342 MPa at 50 ppt (physics-notes §4.2)."""
    p = 0.1
    f_h = kit.panel0_forces_per_area()[1] * WIDTH_M * p  # 3.34 MN
    p_t = 4.278e6 * 50.0**-0.6455 * thickness_m * LENGTH_M  # b = extent along the crack = L
    assert 4.278e6 * 50.0**-0.6455 == pytest.approx(0.342e6, rel=2e-3)
    assert (f_h > 1.3 * p_t) if must_fail else (f_h < p_t / 1.1)
    inp = make_input(kit.midbody_box(WIDTH_M, LENGTH_M, p), thickness_m)
    settings = CrackingSettings(criterion="point_load", point_load_capacity="tensile_Pt")
    outcome = Cracking(settings).evaluate(inp, context)
    assert outcome.failed is must_fail
    check = criterion_check(Cracking(settings), inp, context)
    assert check.resistance == pytest.approx(p_t, rel=1e-9)
    assert check.driving == pytest.approx(f_h, rel=1e-9)
    assert outcome.margin == pytest.approx(math.log(f_h / p_t), rel=1e-9)  # ln(F_h / P_t), > 0 if it fails
    # P_t is the default capacity (erratum 20, docs/model.md §11)
    default = criterion_check(Cracking(CrackingSettings(criterion="point_load")), inp, context)
    assert default.resistance == pytest.approx(p_t, rel=1e-9)


@pytest.mark.parametrize(("penetration_m", "must_fail"), [(0.005, False), (0.05, True)])
def test_point_load_bending_capacity(make_input, context, kit, penetration_m, must_fail):
    """F_h > P with P the Nevel capacity at the contact (thesis Alg. 7 `fracture_criterion_simple`)."""
    a_h = WIDTH_M * penetration_m
    f_h = kit.panel0_forces_per_area()[1] * a_h
    theta = math.radians(180.0)
    # Θ is 180° or 185° (see test_bending); bracket both Θ and ρ = √(2 A_h/Θ)/ℓ
    rho_low = math.sqrt(2.0 * a_h / math.radians(185.0)) / kit.ell_m(1.0)
    rho_high = math.sqrt(2.0 * a_h / theta) / kit.ell_m(1.0)
    low = kit.capacity_bracket_n(1.0, theta, rho_low)[0]
    high = kit.capacity_bracket_n(1.0, math.radians(185.0), rho_high)[1]
    assert (f_h > 1.3 * high) if must_fail else (f_h < low / 1.3)
    inp = make_input(kit.midbody_box(WIDTH_M, LENGTH_M, penetration_m))
    cracking = Cracking(CrackingSettings(criterion="point_load", point_load_capacity="bending_P"))
    assert cracking.evaluate(inp, context).failed is must_fail
    assert low <= criterion_check(cracking, inp, context).resistance <= high


@pytest.mark.parametrize(("penetration_m", "must_fail"), [(0.003, False), (0.02, True)])
def test_line_load_with_crack_length_ell_over_5(make_input, context, kit, penetration_m, must_fail):
    """K_I = 0.878 (κ F_h / h) √(π/a) ≥ K_Ic, κ = 1/(2 tan(64.54°/2)), a = ℓ/5 (Alg. 5, 7; notes §4.3)."""
    h = 1.0
    f_h = kit.panel0_forces_per_area()[1] * WIDTH_M * penetration_m
    a = kit.ell_m(h) / 5.0
    k_i = 0.878 * kappa() * f_h / h * math.sqrt(math.pi / a)
    assert kappa() == pytest.approx(0.792, abs=1e-3)  # physics-notes §3.3
    assert (k_i > 1.3 * kit.k_ic_pa_sqrt_m) if must_fail else (k_i < kit.k_ic_pa_sqrt_m / 1.3)
    inp = make_input(kit.midbody_box(WIDTH_M, LENGTH_M, penetration_m), h)
    settings = CrackingSettings(criterion="line_load", crack_length="ell_over_5")
    outcome = Cracking(settings).evaluate(inp, context)
    assert outcome.failed is must_fail
    check = criterion_check(Cracking(settings), inp, context)
    assert check.driving == pytest.approx(k_i, rel=1e-9)
    assert check.resistance == kit.k_ic_pa_sqrt_m


def test_indentation_depth_is_the_penetration(make_input, context, kit):
    """Default crack length a: the crack line behind O inside the floe, = the penetration p here."""
    p = 0.07
    floe = kit.midbody_box(WIDTH_M, LENGTH_M, p)
    inp = make_input(floe)
    assert indentation_depth_m(floe, inp.zone.centre_xy_m, np.array([0.0, 1.0])) == pytest.approx(p, rel=1e-9)
    f_h = kit.panel0_forces_per_area()[1] * WIDTH_M * p
    expected = 0.878 * kappa() * f_h * math.sqrt(math.pi / p)
    cracking = Cracking(CrackingSettings(criterion="line_load", line_load_crack_length="indentation"))
    assert criterion_check(cracking, inp, context).driving == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("penetration_m", [1e-4, 0.07])
def test_line_load_has_no_singularity_at_first_touch(make_input, context, kit, penetration_m):
    """Default: the line load is evaluated at a = max(indentation, 0.13 b), where a crack loaded at its mouth
    in a strip of width b has its smallest K_I (physics-notes §3.3), so K_I → 0 with the load at first touch
    instead of reaching K_Ic at a few kN with a = 1 mm (F_h ≈ 3.7 kN)."""
    floe = kit.midbody_box(WIDTH_M, LENGTH_M, penetration_m)
    inp = make_input(floe)
    f_h = kit.panel0_forces_per_area()[1] * WIDTH_M * penetration_m
    a = 0.13 * LENGTH_M  # b = the floe's extent along the crack (the panel normal) = LENGTH_M
    expected = 0.878 * kappa() * f_h * math.sqrt(math.pi / a)  # h = 1 m
    check = criterion_check(Cracking(CrackingSettings(criterion="line_load")), inp, context)
    assert check.driving == pytest.approx(expected, rel=1e-9)
    assert check.fails is (expected >= kit.k_ic_pa_sqrt_m)
    literal = Cracking(CrackingSettings(criterion="line_load", line_load_crack_length="indentation"))
    assert criterion_check(literal, inp, context).driving > check.driving


def test_indentation_depth_counts_only_the_part_connected_to_o():
    # a U-shaped floe (arms x ∈ [0, 2] and [4, 6], bar y ∈ [0, 2]); the line behind O runs along −direction
    # behind O = (1, 9) for direction −y: up the left arm to its end at y = 10
    u_shape = shapely.Polygon([(0, 0), (6, 0), (6, 10), (4, 10), (4, 2), (2, 2), (2, 10), (0, 10)])
    assert indentation_depth_m(u_shape, np.array([1.0, 9.0]), np.array([0.0, -1.0])) == pytest.approx(1.0)
    # from O = (1, 1) along +x (behind O: −x): 1 m to the left edge, the right arm beyond is not connected
    assert indentation_depth_m(u_shape, np.array([1.0, 1.0]), np.array([1.0, 0.0])) == pytest.approx(1.0)
    # O = (3, 5) in the notch, outside the floe: the ray behind it (−y) meets the bar 3 m away, not at O
    assert indentation_depth_m(u_shape, np.array([3.0, 5.0]), np.array([0.0, 1.0])) == 0.0
    # behind O = (5, 3) towards −x: 1 m in the right arm, then the notch, then the left arm (not counted)
    assert indentation_depth_m(u_shape, np.array([5.0, 3.0]), np.array([1.0, 0.0])) == pytest.approx(1.0)


@pytest.mark.parametrize(
    ("criterion", "labels", "a_m", "must_fail"),
    [
        # physics-notes §4.4: BZ, b = L = 10 m → cracks once a ≥ 0.44 m (correct Tada tension) …
        ("tensile_stress", "correct", 0.40, False),
        ("tensile_stress", "correct", 0.48, True),
        # … or a ≥ 0.50 m with the thesis' swapped labels (tension → the bending polynomial)
        ("tensile_stress", "thesis_alg7", 0.46, False),
        ("tensile_stress", "thesis_alg7", 0.54, True),
        # in-plane bending (G_B): the same threshold as the thesis' "tensile" variant
        ("flexural_stress", "correct", 0.46, False),
        ("flexural_stress", "correct", 0.54, True),
    ],
)
def test_stress_criteria_are_load_independent_thresholds_on_a(
    make_input, context, kit, criterion, labels, a_m, must_fail
):
    b = 10.0
    h = thickness_for_ell_over_5(kit, a_m)
    assert kit.ell_m(h) / 5.0 == pytest.approx(a_m, rel=1e-12)
    polynomial = "tension" if (criterion == "tensile_stress") == (labels == "correct") else "bending"
    k_i = bz_strength_pa(b) * math.sqrt(math.pi * a_m) * tada_factor(a_m / b, polynomial)
    assert (k_i > 1.02 * kit.k_ic_pa_sqrt_m) if must_fail else (k_i < kit.k_ic_pa_sqrt_m / 1.02)
    settings = CrackingSettings(
        criterion=criterion,
        tada_labels=labels,
        crack_length="ell_over_5",
        size_effect_law="BZ",
        stress_mode="thesis",
    )
    for p in (0.01, 0.1):  # the verdict does not depend on the contact load (erratum 19)
        inp = make_input(kit.midbody_box(WIDTH_M, b, p), h)
        outcome = Cracking(settings).evaluate(inp, context)
        assert outcome.failed is must_fail
        check = criterion_check(Cracking(settings), inp, context)
        assert check.driving == pytest.approx(k_i, rel=1e-9)


@pytest.mark.parametrize(("penetration_m", "must_fail"), [(0.015, False), (0.06, True)])
def test_stress_criterion_strength_mode_follows_the_load(make_input, context, kit, penetration_m, must_fail):
    """Load-consistent alternative (physics-notes §4.4): F_h / (h b) ≥ σ_n^t(L = b)."""
    b, h = 10.0, 1.0
    applied = kit.panel0_forces_per_area()[1] * WIDTH_M * penetration_m / (h * b)
    strength = bz_strength_pa(b)
    assert strength == pytest.approx(0.108e6, rel=5e-3)  # notes §4.1 table
    assert (applied > 1.3 * strength) if must_fail else (applied < strength / 1.3)
    inp = make_input(kit.midbody_box(WIDTH_M, b, penetration_m), h)
    settings = CrackingSettings(criterion="tensile_stress", stress_mode="strength")
    outcome = Cracking(settings).evaluate(inp, context)
    assert outcome.failed is must_fail
    check = criterion_check(Cracking(settings), inp, context)
    assert check.driving == pytest.approx(applied, rel=1e-9)
    assert check.resistance == pytest.approx(strength, rel=1e-9)


def test_stress_criterion_default_is_k_i_from_the_load(make_input, context, kit):
    """Default `stress_mode = "sif"` (physics-notes §4.4): K_I = F_h/(h b) √(πa) F(a/b) against K_Ic, so it
    scales with the contact load (the thesis' form does not, erratum 19)."""
    b, a = 10.0, 0.3
    h = thickness_for_ell_over_5(kit, a)
    drivings = []
    for penetration_m in (0.02, 0.04):
        floe = kit.midbody_box(WIDTH_M, b, penetration_m)
        applied = kit.panel0_forces_per_area()[1] * WIDTH_M * penetration_m / (h * b)
        expected = applied * math.sqrt(math.pi * a) * tada_factor(a / b, "tension")
        settings = CrackingSettings(criterion="tensile_stress", crack_length="ell_over_5")
        check = criterion_check(Cracking(settings), make_input(floe, h), context)
        assert check.driving == pytest.approx(expected, rel=1e-9)
        assert check.resistance == kit.k_ic_pa_sqrt_m
        drivings.append(check.driving)
    assert drivings[1] == pytest.approx(2.0 * drivings[0], rel=1e-9)


def crack_onset_penetration_m(make_input, context, kit, settings, thickness_m: float) -> float:
    """The smallest penetration (to 1 mm) at which `settings`' criterion cracks a 9 m × 10 m floe."""
    cracking = Cracking(settings)
    for penetration_m in np.arange(0.001, 3.0, 0.001):
        inp = make_input(kit.midbody_box(WIDTH_M, 10.0, penetration_m), thickness_m)
        if criterion_check(cracking, inp, context).fails:
            return float(penetration_m)
    return math.inf


def test_thicker_ice_needs_a_deeper_indentation_to_crack_only_with_the_load(make_input, context, kit):
    """Why Ā stopped growing above h = 1 m in v0.1 (docs/model.md §12): with the thesis' load-independent
    stress criterion the crack starts at the same indentation whatever the thickness, so thicker ice, whose
    bending capacity grows as h², cracks before it bends and breaks into more, smaller pieces; with K_I from
    the load (default) thicker ice needs a deeper indentation, F_h ∝ a at a fixed K_I h."""
    onsets = {}
    for mode in ("thesis", "sif"):
        settings = CrackingSettings(criterion="tensile_stress", stress_mode=mode)
        onsets[mode] = [crack_onset_penetration_m(make_input, context, kit, settings, h) for h in (1.0, 1.2)]
    assert all(math.isfinite(p) for p in onsets["thesis"] + onsets["sif"])
    thin, thick = onsets["thesis"]
    assert thick == pytest.approx(thin, abs=1.5e-3), onsets
    thin, thick = onsets["sif"]
    assert thick > 1.05 * thin, onsets


def nevel_stress_factor(kit, rho: float) -> float:
    """S(ρ) interpolated linearly in the physics-notes §1.3 table."""
    rows = sorted(kit.table)
    return float(np.interp(rho, rows, [kit.table[r][0] for r in rows]))


def expected_onsets_m(kit, thickness_m: float) -> tuple[float, float]:
    """(bending, cracking) onset penetrations of the 9 m × 10 m floe on panel 0, from the notes alone.
    Bending: F_v = c_v W p against P_f = σ_f Θ h²/(6 S(ρ)), Θ = π, ρ = r/ℓ, r = √(2 W p/Θ) (notes §1.4, §1.7).
    Cracking (K_I from the load): K_I = c_h W p/(h b) √(πp) F_T(p/b) against K_Ic, a = p (notes §4.4)."""
    c_v, c_h = kit.panel0_forces_per_area()
    length_m = 10.0

    def bending_excess_n(p: float) -> float:
        rho = math.sqrt(2.0 * WIDTH_M * p / math.pi) / kit.ell_m(thickness_m)
        capacity = kit.nevel_capacity_n(thickness_m, math.pi, nevel_stress_factor(kit, rho))
        return c_v * WIDTH_M * p - capacity

    def cracking_excess_pa_sqrt_m(p: float) -> float:
        applied = c_h * WIDTH_M * p / (thickness_m * length_m)
        return applied * math.sqrt(math.pi * p) * tada_factor(p / length_m, "tension") - kit.k_ic_pa_sqrt_m

    return brentq(bending_excess_n, 1e-4, 0.36), brentq(cracking_excess_pa_sqrt_m, 1e-4, 0.36)


def bending_onset_penetration_m(make_input, context, kit, thickness_m: float) -> float:
    """The smallest penetration (to 1 mm) at which the same floe fails Eq. 11 (F_v > P_f)."""
    for penetration_m in np.arange(0.001, 0.364, 0.001):
        inp = make_input(kit.midbody_box(WIDTH_M, 10.0, penetration_m), thickness_m)
        if bending_check(inp, context, BendingSettings()).fails:
            return float(penetration_m)
    return math.inf


def test_thicker_ice_must_be_pushed_deeper_to_bend_than_to_crack(make_input, context, kit):
    """Why the affected area falls at h = 1.2 m in our model (docs/model.md §12; thesis §5.3.3: +2.6 %): the
    crushing force at an indentation does not depend on h (Eqs. 6–10: the crushed area is the overlap in
    plan), the bending capacity grows as h² and K_I from the load falls as 1/h. From h = 1.0 to 1.2 m the
    indentation at which a floe bends grows by ≈ 1.46, the one at which it cracks by ≈ 1.13: thicker ice is
    carried further along the bow before it bends, more of it reaches the shoulder unbent."""
    bending, cracking = {}, {}
    settings = CrackingSettings(criterion="tensile_stress")  # default stress_mode "sif"
    for h in (1.0, 1.2):
        bending[h] = bending_onset_penetration_m(make_input, context, kit, h)
        cracking[h] = crack_onset_penetration_m(make_input, context, kit, settings, h)
        expected_bending, expected_cracking = expected_onsets_m(kit, h)
        # 1 mm search resolution; the table's linear interpolation of S is good to a few per cent here
        assert bending[h] == pytest.approx(expected_bending, rel=0.03, abs=1e-3), (h, bending[h])
        assert cracking[h] == pytest.approx(expected_cracking, abs=1e-3), (h, cracking[h])
    assert bending[1.2] / bending[1.0] > 1.35
    assert cracking[1.2] / cracking[1.0] < 1.2


def test_flexural_and_tensile_stress_start_the_same_crack_with_the_load(make_input, context, kit):
    """Why V̄ hardly differs between the two stress criteria in `default` (docs/model.md §12; thesis Table 6:
    −1.2 %): they differ only by the Tada factor, and both factors tend to 1.122 for a short edge crack
    (notes §4.3). With K_I from the load a crack starts at a = the indentation, a few centimetres (a/b < 0.01,
    where the factors differ by 1 %), so the two criteria start it within a millimetre of indentation — far
    less than the bow's 0.25 m step."""
    onsets = {
        name: crack_onset_penetration_m(make_input, context, kit, CrackingSettings(criterion=name), 1.0)
        for name in ("tensile_stress", "flexural_stress")
    }
    a = onsets["tensile_stress"]
    assert a / 10.0 < 0.01
    assert tada_factor(a / 10.0, "bending") == pytest.approx(tada_factor(a / 10.0, "tension"), rel=0.02)
    assert abs(onsets["flexural_stress"] - a) <= 1e-3


@pytest.mark.parametrize("spelling", ["table", "flat"])
def test_a_self_locking_wedge_is_refused_when_the_scenario_is_read(spelling):
    # fuzz campaign: wedge_friction = 2 within its [0, 2] with the default tip angle 64.54° passed
    # validation and was refused only at the first line-load check, mid-run, as "failure.wedge_friction";
    # μ tan(α/2) = 2 tan(32.27°) = 1.26 ≥ 1 is self-locking (physics-notes §3.3)
    from floebreak.config.scenario import Scenario
    from floebreak.errors import InputError

    assert 2.0 * math.tan(math.radians(64.54 / 2.0)) >= 1.0
    cracking = {"wedge_friction": 2.0}
    failure = (
        {"cracking": {**cracking, "criterion": "line_load"}}
        if spelling == "table"
        else {"crack_criterion": "line_load", "cracking": cracking}
    )
    with pytest.raises(InputError) as info:
        Scenario.from_dict({"failure": failure})
    assert info.value.field == "failure.cracking.wedge_friction"
    assert "self-locking" in str(info.value)
    # another criterion does not use the wedge: the same friction is accepted
    Scenario.from_dict({"failure": {"cracking": {**cracking, "criterion": "tensile_stress"}}})
    with pytest.raises(InputError, match="wedge_friction"):
        CrackingSettings(criterion="line_load", wedge_friction=2.0)


def test_a_tie_between_the_two_later_cracks_turns_counter_clockwise(make_input):
    """A symmetric piece loaded on the stem (its centroid on the normal, the centreline): the ±30° lines pass
    equally close to the centroid, a genuine tie that no single crack can keep symmetric. The documented
    rule (docs/model.md, Breaking sequence) takes +α_nextcrack, counter-clockwise: (cos 30°, sin 30°), for
    the piece and for its mirror image alike (whose ring runs the other way), not by rounding."""
    t = np.linspace(-0.5 * np.pi, 0.5 * np.pi, 33)
    half_disc = shapely.Polygon(np.c_[-0.3 + 6.0 * np.cos(t), 6.0 * np.sin(t)])  # 0.3 m into the stem
    for piece in (half_disc, shapely.transform(half_disc, lambda xy: xy * np.array([1.0, -1.0]))):
        inp = make_input(piece, crack_count=1)
        np.testing.assert_allclose(inp.zone.centre_xy_m, [0.0, 0.0], atol=1e-12)
        np.testing.assert_allclose(inp.zone.centre_normal, [1.0, 0.0], atol=1e-12)
        direction = crack_direction(inp, math.radians(30.0))
        np.testing.assert_allclose(direction, [math.cos(math.radians(30.0)), 0.5], atol=1e-12)
