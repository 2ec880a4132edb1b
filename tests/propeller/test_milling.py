"""Blade milling model (docs/propeller.md, "Blade milling model"): analytic limits computed here."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from floebreak.errors import InputError
from floebreak.propeller.loads import milling
from floebreak.propeller.loads.milling import (
    BladeGeometry,
    IceBlock,
    IceStrength,
    cut_depth_m,
    impact_loads,
)
from floebreak.propeller.spec import PropellerSpec

AGULHAS = BladeGeometry.from_spec(PropellerSpec())  # D 4.3 m, Z 4, hub 0.3, EAR 0.55, t 0.105 m, 95.86 %


def block(thickness, length=3.0, width=2.0) -> IceBlock:
    return IceBlock(np.atleast_1d(thickness), np.atleast_1d(length), np.atleast_1d(width))


def one_strip_by_hand(geom: BladeGeometry, extent, rpm, speed, ice: IceStrength, centre=None):
    """Torque and aft axial force of one strip [R − e, R] (or of extent e about `centre`) at its mid
    radius, written out from the docs."""
    r = geom.radius_m - extent / 2 if centre is None else centre
    chord = geom.chord_m(r).item() if geom.chord_distribution == "b_series" else geom.chord_07_m
    t = geom.thickness_07_m
    omega_r = 2 * math.pi * rpm / 60 * r
    beta = math.atan(speed / omega_r)
    phi = math.atan(geom.pitch_m / (2 * math.pi * r))
    alpha = phi - beta
    layer = speed / (geom.blades * rpm / 60) * math.cos(beta)
    w_nose = min(t * abs(math.cos(alpha)), layer)
    w_flank = min(chord * abs(math.sin(alpha)), layer - w_nose)
    # the flank touches the ice along the chord over its swept length, at most the rule's 0.2 c
    length = min(w_flank / abs(math.sin(alpha)), ice.flank_contact_chord_fraction * chord)
    a_nose, a_flank = w_nose * extent, length * extent
    area = a_nose + a_flank
    p = ice.crushing_pressure_pa * (area / ice.reference_area_m2) ** ice.area_exponent
    s = 1.0 if alpha > 0 else -1.0
    against = p * a_nose * math.cos(beta) + p * a_flank * (s * math.sin(phi) + ice.friction * math.cos(phi))
    aft = p * a_nose * math.sin(beta) + p * a_flank * (-s * math.cos(phi) + ice.friction * math.sin(phi))
    return against * r, aft, area


@pytest.mark.parametrize("fraction", [0.2, 1.0])
@pytest.mark.parametrize("pitch_percent", [0.0, 50.0, 95.8551])
@pytest.mark.parametrize("strips", [1, 64])
def test_one_radial_strip_torque_is_force_times_radius(pitch_percent, strips, fraction):
    geom = replace(AGULHAS, pitch_percent=pitch_percent)
    ice = IceStrength(flank_contact_chord_fraction=fraction)
    extent = 0.01  # thinner than one of 64 strips (1.505 m / 64 = 0.0235 m): only the tip strip is in ice
    q, f_aft, area = one_strip_by_hand(geom, extent, 140.0, 3.0, ice)
    loads = impact_loads(block(extent), geom, 140.0, 3.0, ice, strips=strips)
    assert loads.torque_n_m[0] == pytest.approx(q, rel=1e-9)
    assert loads.axial_force_aft_n[0] == pytest.approx(f_aft, rel=1e-9)
    assert loads.force_n[0] == pytest.approx(abs(f_aft), rel=1e-9)
    assert loads.contact_area_m2[0] == pytest.approx(area, rel=1e-9)
    assert loads.radial_extent_m[0] == pytest.approx(extent)


@pytest.mark.parametrize("strips", [1, 64])
def test_an_engaged_interval_mid_blade_loads_one_strip_at_its_midpoint(strips):
    # [1.2, 1.205] m lies inside one of 64 strips (edges every 1.505/64 m from 0.645 m: 1.1860–1.2096)
    ice = IceStrength()
    q, f_aft, area = one_strip_by_hand(AGULHAS, 0.005, 140.0, 3.0, ice, centre=1.2025)
    thick = IceBlock(np.ones(1), np.full(1, 3.0), np.full(1, 2.0), 1.2, 1.205)
    loads = impact_loads(thick, AGULHAS, 140.0, 3.0, ice, strips=strips)
    assert loads.torque_n_m[0] == pytest.approx(q, rel=1e-9)
    assert loads.axial_force_aft_n[0] == pytest.approx(f_aft, rel=1e-9)
    assert loads.contact_area_m2[0] == pytest.approx(area, rel=1e-9)
    assert loads.radial_extent_m[0] == pytest.approx(0.005, abs=1e-15)
    assert loads.impact_angle_deg[0] == pytest.approx(math.degrees(2.0 / 1.2025))


def test_an_engaged_interval_at_the_tip_is_the_tip_placement_of_that_thickness():
    e = 0.4
    tip = impact_loads(block(e), AGULHAS, 140.0, 3.0)
    interval = impact_loads(
        IceBlock(np.full(1, e), np.full(1, 3.0), np.full(1, 2.0), AGULHAS.radius_m - e, AGULHAS.radius_m),
        AGULHAS,
        140.0,
        3.0,
    )
    for name in ("torque_n_m", "force_n", "contact_area_m2", "impact_angle_deg", "n_impacts"):
        assert getattr(interval, name)[0] == pytest.approx(getattr(tip, name)[0], rel=1e-12), name


def test_a_thick_block_engaged_lower_on_the_blade_takes_less_torque_than_at_the_tip():
    # the same 0.5 m of blade, mid-span instead of at the tip: smaller radius, narrower layer
    h = np.ones(1)
    at_tip = impact_loads(IceBlock(h, 3.0, 2.0, 1.65, 2.15), AGULHAS, 140.0, 3.0)
    lower = impact_loads(IceBlock(h, 3.0, 2.0, 0.9, 1.4), AGULHAS, 140.0, 3.0)
    assert 0.0 < lower.torque_n_m[0] < at_tip.torque_n_m[0]
    assert lower.radial_extent_m[0] == pytest.approx(0.5) == at_tip.radial_extent_m[0]


def test_a_zero_length_interval_gives_no_contact_and_no_impacts():
    loads = impact_loads(IceBlock(np.ones(1), 3.0, 2.0, 1.0, 1.0), AGULHAS, 140.0, 3.0)
    assert loads.torque_n_m[0] == 0.0 and loads.force_n[0] == 0.0 and loads.contact_area_m2[0] == 0.0
    assert loads.n_impacts[0] == 0


def test_tip_placement_with_nan_intervals_is_the_old_strip_formula_to_the_bit():
    # the tip placement as it was before engaged intervals: [R − e, R], e = min(h, R − r_hub)
    rng = np.random.default_rng(5)
    h = rng.uniform(0.01, 3.0, 40)
    radius, hub, n = AGULHAS.radius_m, AGULHAS.hub_radius_m, 64
    extent = np.minimum(h, radius - hub)
    edges = np.linspace(hub, radius, n + 1)
    inner = np.maximum(edges[:-1], (radius - extent)[..., None])
    overlap = np.clip(edges[1:] - inner, 0.0, None)
    mid = np.where(overlap > 0.0, 0.5 * (inner + edges[1:]), edges[1:])
    got = milling.block_strips(AGULHAS, h, np.ones(40), n, np.full(40, np.nan), np.full(40, np.nan))
    np.testing.assert_array_equal(got.radial_extent_m, extent)
    np.testing.assert_array_equal(got.overlap_m, overlap)
    np.testing.assert_array_equal(got.mid_radius_m, mid)
    default = impact_loads(IceBlock(h, 3.0, 2.0), AGULHAS, 140.0, 3.0)
    nan = impact_loads(IceBlock(h, 3.0, 2.0, np.nan, np.nan), AGULHAS, 140.0, 3.0)
    centre = radius - 0.5 * extent  # the old contact centre
    np.testing.assert_array_equal(default.impact_angle_deg, np.degrees(np.minimum(2.0 / centre, math.pi)))
    for name in ("torque_n_m", "force_n", "n_impacts", "n_impacts_thrown", "contact_area_m2"):
        np.testing.assert_array_equal(getattr(nan, name), getattr(default, name))


@pytest.mark.parametrize(
    ("inner", "outer", "key"),
    [(-0.1, 1.0, "inner_radius_m"), (1.2, 1.0, "outer_radius_m"), (1.0, np.nan, "outer_radius_m")],
)
def test_bad_engaged_intervals_are_refused(inner, outer, key):
    with pytest.raises(InputError, match=rf"block\.{key}"):
        IceBlock(np.ones(1), np.ones(1), np.ones(1), inner, outer)


def test_face_contact_at_pitch_pushes_forward_and_back_contact_at_zero_pitch_pushes_aft():
    loads95 = impact_loads(block(1.0), AGULHAS, 140.0, 3.0)
    loads0 = impact_loads(block(1.0), replace(AGULHAS, pitch_percent=0.0), 140.0, 3.0)
    assert loads95.axial_force_aft_n[0] < 0.0 < loads0.axial_force_aft_n[0]
    assert loads95.torque_n_m[0] > 0.0 and loads0.torque_n_m[0] > 0.0


def test_doubling_the_cut_depth_scales_loads_by_two_to_one_plus_the_area_exponent():
    # constant chord 3 m: the face (α ≈ 20°, c sin α ≈ 1 m) is wider than both layers, nose ≈ 0, no friction:
    # every load is p(A)·A·const, A ∝ cut depth → ratio 2^(1 + ex). Halving Z doubles the cut, angles equal.
    # the full geometric flank contact (fraction 1): the contact length follows the layer
    geom = replace(AGULHAS, chord_07_m=3.0, chord_distribution="constant", thickness_07_m=1e-9)
    ice = IceStrength(friction=0.0, area_exponent=-0.3, flank_contact_chord_fraction=1.0)
    four = impact_loads(block(1.2), geom, 140.0, 1.0, ice)
    two = impact_loads(block(1.2), replace(geom, blades=2), 140.0, 1.0, ice)
    assert two.cut_depth_m[0] == pytest.approx(2 * four.cut_depth_m[0])
    assert two.torque_n_m[0] / four.torque_n_m[0] == pytest.approx(2**0.7, rel=1e-6)
    assert two.force_n[0] / four.force_n[0] == pytest.approx(2**0.7, rel=1e-6)
    assert four.removed_fraction[0] == pytest.approx(1.0) and two.removed_fraction[0] == pytest.approx(1.0)


def test_cut_depth_is_advance_per_blade_passage():
    assert cut_depth_m(3.0, 140.0, 4) == pytest.approx(3.0 / (4 * 140 / 60))
    assert cut_depth_m(3.0, 280.0, 4) == pytest.approx(0.5 * 3.0 / (4 * 140 / 60))
    assert cut_depth_m(0.0, 140.0, 4) == 0.0
    assert np.isinf(cut_depth_m(3.0, 0.0, 4))


def test_zero_advance_cuts_nothing():
    loads = impact_loads(block(1.0), AGULHAS, 140.0, 0.0)
    assert loads.cut_depth_m[0] == 0.0 and loads.n_impacts[0] == 0
    assert loads.torque_n_m[0] == 0.0 and loads.force_n[0] == 0.0 and loads.contact_area_m2[0] == 0.0


def test_block_thinner_than_the_blade_meets_fewer_strips():
    span = AGULHAS.radius_m - AGULHAS.hub_radius_m
    thin, full, thick = (impact_loads(block(h), AGULHAS, 140.0, 3.0) for h in (0.3, span, span + 2.0))
    assert thin.radial_extent_m[0] == pytest.approx(0.3)
    assert full.radial_extent_m[0] == pytest.approx(span) == thick.radial_extent_m[0]
    assert thin.contact_area_m2[0] < full.contact_area_m2[0]
    assert thin.torque_n_m[0] < full.torque_n_m[0] == pytest.approx(thick.torque_n_m[0])


def test_monotone_in_thickness_and_length():
    h = np.linspace(0.05, 2.0, 30)
    loads = impact_loads(block(h, 3.0, 2.0), AGULHAS, 140.0, 3.0)
    inside = h[1:] <= AGULHAS.radius_m - AGULHAS.hub_radius_m  # beyond the span the block meets no more blade
    assert np.all(np.diff(loads.torque_n_m)[inside] > 0.0) and np.all(
        np.diff(loads.contact_area_m2)[inside] > 0.0
    )
    beyond = h[:-1] >= AGULHAS.radius_m - AGULHAS.hub_radius_m
    assert np.all(np.diff(loads.torque_n_m)[beyond] == 0.0) and inside.any() and beyond.any()
    lengths = np.linspace(0.1, 8.0, 30)
    by_length = impact_loads(block(1.0, lengths, 2.0), AGULHAS, 140.0, 3.0, block_motion=None)
    assert np.all(np.diff(by_length.n_impacts) >= 0) and by_length.n_impacts[-1] > by_length.n_impacts[0]
    cut = 3.0 / (4 * 140 / 60)
    longer = lengths >= cut  # the length sets the number of impacts, not their size ...
    assert np.ptp(by_length.torque_n_m[longer]) == 0.0
    # ... except a block shorter than the cut depth: one impact cutting a layer as long as the block
    assert np.all(by_length.torque_n_m[~longer] < by_length.torque_n_m[longer][0]) and (~longer).any()
    assert list(by_length.n_impacts) == [math.ceil(x / cut - 1e-12) for x in lengths]
    assert by_length.milling_time_s == pytest.approx(lengths / 3.0)


def test_vectorised_equals_scalar_with_changing_rpm():
    rng = np.random.default_rng(7)
    h, length, width = rng.uniform(0.1, 2.0, 12), rng.uniform(0.5, 6.0, 12), rng.uniform(0.5, 4.0, 12)
    rpm = rng.uniform(60.0, 160.0, 12)
    together = impact_loads(IceBlock(h, length, width), AGULHAS, rpm, 3.0)
    for i in range(12):
        alone = impact_loads(block(h[i], length[i], width[i]), AGULHAS, rpm[i], 3.0)
        for name in (
            "torque_n_m",
            "force_n",
            "cut_depth_m",
            "n_impacts",
            "impact_angle_deg",
            "removed_fraction",
        ):
            assert getattr(together, name)[i] == pytest.approx(getattr(alone, name)[0], rel=1e-12)


def test_from_spec_and_b_series_chord():
    assert AGULHAS.pitch_m == pytest.approx(0.958551 * 5.15)
    assert AGULHAS.chord_at_07_m == pytest.approx(2.144 * 4.3 * 0.55 / 4)
    assert AGULHAS.chord_m(0.9 * 2.15) == pytest.approx(1.582 / 2.144 * AGULHAS.chord_at_07_m)
    assert AGULHAS.chord_m(2.15) == pytest.approx(0.0)


def test_from_box_puts_the_longer_side_along_the_axis():
    b = IceBlock.from_box([1.0, 4.0], [3.0, 2.0], [0.5, 0.7])
    assert list(b.length_m) == [3.0, 4.0] and list(b.width_m) == [1.0, 2.0]


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"diameter_m": 0.0}, "blade.diameter_m"),
        ({"diameter_m": -1.0}, "blade.diameter_m"),
        ({"blades": 1}, "blade.blades"),
        ({"hub_ratio": 1.0}, "blade.hub_ratio"),
        ({"max_pitch_ratio": 0.0}, "blade.max_pitch_ratio"),
        ({"expanded_area_ratio": 0.0}, "blade.expanded_area_ratio"),
        ({"thickness_07_m": 0.0}, "blade.thickness_07_m"),
        ({"pitch_percent": 101.0}, "blade.pitch_percent"),
        ({"chord_distribution": "elliptic"}, "blade.chord_distribution"),
    ],
)
def test_bad_geometry_names_the_key(change, key):
    with pytest.raises(InputError) as err:
        replace(AGULHAS, **change)
    assert err.value.field == key and key in str(err.value)


def test_bad_operation_block_and_ice_name_the_key():
    for kwargs, key in (({"rpm": -1.0}, "rpm"), ({"advance_speed_m_s": np.nan}, "advance_speed_m_s")):
        args = {"rpm": 140.0, "advance_speed_m_s": 3.0} | kwargs
        with pytest.raises(InputError, match=key):
            impact_loads(block(1.0), AGULHAS, args["rpm"], args["advance_speed_m_s"])
    with pytest.raises(InputError, match=r"block\.thickness_m"):
        block(-0.1)
    with pytest.raises(InputError, match=r"ice\.area_exponent"):
        IceStrength(area_exponent=0.2)
    with pytest.raises(InputError, match="strips"):
        impact_loads(block(1.0), AGULHAS, 140.0, 3.0, strips=0)


def test_the_impact_torque_at_1_m_lies_between_the_rules_thickness_scaling_and_q_max():
    """The PC5 rows' link (docs/propeller.md §10): a 1 m block at 95.86 % pitch, 140 rpm and 3 m/s, with the
    flank contact capped at 0.2 c, gives a per-impact torque below the rule's PC5 Q_max (H_ice = 2 m) but
    above that Q_max scaled to H_ice = 1 m by the rule's H_ice^1.1 (its branch for D > 1.8 H_ice:
    4.3 m > 1.8 m), whatever the block's length and width (the thickness, its radial extent, sets it);
    without the cap (fraction 1) it exceeded the PC5 Q_max itself."""
    from floebreak.propeller.iceclass import ur_i3_loads

    q_max = ur_i3_loads(PropellerSpec(), "PC5").max_torque_nm
    q_rule_1m = q_max * (1.0 / 2.0) ** 1.1
    blocks = block(1.0, np.array([2.0, 4.0, 8.0]), np.array([1.5, 3.0, 6.0]))
    loads = impact_loads(blocks, AGULHAS, 140.0, 3.0)
    full = impact_loads(blocks, AGULHAS, 140.0, 3.0, IceStrength(flank_contact_chord_fraction=1.0))
    assert np.ptp(loads.torque_n_m) == 0.0
    assert q_rule_1m < loads.torque_n_m[0] < q_max < full.torque_n_m[0]


def test_a_free_block_is_thrown_out_of_the_disc_after_a_few_impacts():
    """By hand for a 0.4 m × 2.5 m × 1.7 m block on the Agulhas II at 140 rpm, 3 m/s: Q per impact from the
    model, contact radius r_c = 2.15 − 0.2 m, contact time t_c = (1.7 / r_c) / ω; the impulse
    (2/π)(Q/r_c) t_c over the block's mass with its added mass (C_A = 1.21 at a/b = 4.25, DNV-RP-C205 Table
    A-1, interpolated in log a/b) gives Δv; the block travels Δv Δt k(k+1)/2 after k impacts and leaves
    the disc at √(R² − (R − h)²)."""
    free = impact_loads(block(0.4, 2.5, 1.7), AGULHAS, 140.0, 3.0)
    held = impact_loads(block(0.4, 2.5, 1.7), AGULHAS, 140.0, 3.0, block_motion=None)
    assert held.torque_n_m[0] == free.torque_n_m[0]
    assert held.n_impacts[0] == math.ceil(2.5 / (3.0 / (4 * 140 / 60))) == free.n_impacts_milled[0]
    omega, r_c = 2 * math.pi * 140 / 60, 2.15 - 0.2
    c_a = np.interp(math.log(1.7 / 0.4), np.log([2.0, 5.0]), [1.36, 1.21])
    mass = 917 * 0.4 * 2.5 * 1.7 + c_a * 1025 * math.pi * 0.2**2 * 2.5
    dv = 2 / math.pi * free.torque_n_m[0] / r_c * (1.7 / r_c) / omega / mass
    exit_m = math.sqrt(2.15**2 - 1.75**2)
    k = 1
    while dv * (2 * math.pi / (4 * omega)) * k * (k + 1) / 2 < exit_m:
        k += 1
    assert free.n_impacts_thrown[0] == k == free.n_impacts[0] < held.n_impacts[0]


def test_the_flank_contact_of_one_strip_is_capped_at_a_fifth_of_the_chord():
    """One strip at the tip of a constant-chord blade (c = 1.268 m), 95.86 % pitch, 140 rpm, 3 m/s, written
    out here: the swept flank length s_f / sin α (α ≈ 18°, layer ≈ 0.32 m) is ≈ 0.7 c; the rule's open-
    propeller load cases 1 and 3 load 0.2 c from the leading edge, so the strip's flank force is
    p(A) · 0.2 c · Δr with A = (w_n + 0.2 c) Δr."""
    geom = replace(AGULHAS, chord_07_m=1.268, chord_distribution="constant")
    extent, rpm, speed = 0.01, 140.0, 3.0
    r = geom.radius_m - extent / 2
    omega_r = 2 * math.pi * rpm / 60 * r
    beta = math.atan(speed / omega_r)
    alpha = math.atan(geom.pitch_m / (2 * math.pi * r)) - beta
    layer = 2 * math.pi * r * speed / (4 * math.hypot(speed, omega_r))
    w_nose = min(0.105 * math.cos(alpha), layer)
    swept = (layer - w_nose) / math.sin(alpha)  # the layer is thinner than c sin α here
    assert 1.268 * math.sin(alpha) > layer - w_nose and swept > 0.6 * 1.268
    area = (w_nose + 0.2 * 1.268) * extent
    p = 1.28e6 * area**-0.1
    phi = alpha + beta
    q = r * p * extent * (w_nose * math.cos(beta) + 0.2 * 1.268 * (math.sin(phi) + 0.15 * math.cos(phi)))
    capped = impact_loads(block(extent), geom, rpm, speed, strips=1)
    whole = IceStrength(flank_contact_chord_fraction=1.0)
    full = impact_loads(block(extent), geom, rpm, speed, whole, strips=1)
    assert capped.contact_area_m2[0] == pytest.approx(area, rel=1e-9)
    assert capped.torque_n_m[0] == pytest.approx(q, rel=1e-9)
    assert full.contact_area_m2[0] == pytest.approx((w_nose + swept) * extent, rel=1e-9)
    # the cap changes the contact, not the layer removed
    assert capped.removed_fraction[0] == pytest.approx(full.removed_fraction[0])


def test_a_binding_cap_makes_the_impact_load_independent_of_the_cut_depth():
    """With the nose negligible and the capped flank shorter than the swept length at both cut depths, the
    contact area, and so every load, is that of 0.2 c whatever the cut: halving Z doubles the cut, the
    loads stay (the uncapped model's ratio is 2^(1 + ex), test above)."""
    geom = replace(AGULHAS, chord_07_m=3.0, chord_distribution="constant", thickness_07_m=1e-9)
    ice = IceStrength(friction=0.0, area_exponent=-0.3)
    four = impact_loads(block(1.2), geom, 140.0, 3.0, ice)
    two = impact_loads(block(1.2), replace(geom, blades=2), 140.0, 3.0, ice)
    assert two.cut_depth_m[0] == pytest.approx(2 * four.cut_depth_m[0])
    assert four.contact_area_m2[0] == pytest.approx(0.2 * 3.0 * 1.2, rel=1e-6)  # + a 1e-9 m nose
    assert two.torque_n_m[0] == pytest.approx(four.torque_n_m[0], rel=1e-12)


def test_the_flank_fraction_is_checked():
    for bad in (-0.1, 1.5, float("nan")):
        with pytest.raises(InputError, match=r"ice\.flank_contact_chord_fraction"):
            IceStrength(flank_contact_chord_fraction=bad)
