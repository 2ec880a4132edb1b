"""Cusp transport under the hull (`floebreak.propeller.transport`, docs/model.md "Cusp transport under the
hull"): geometric limits computed by hand, mirror symmetry, arrival times, monotonicity and bad input."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from floebreak.errors import InputError
from floebreak.failure.dispatch import bow_region
from floebreak.propeller.transport import (
    NO_PROPELLER,
    PATH_BILGE,
    PATH_PROPELLER,
    PATH_SHOULDER,
    HullUnderwater,
    Propeller,
    PropellerArrangement,
    TransportParameters,
    TransportSettings,
    terminal_rise_speed_m_s,
    transport_cusp_table,
    transport_cusps,
)

HULL = HullUnderwater()
CENTRE = PropellerArrangement((Propeller(0.0, diameter_m=4.0, shaft_depth_m=5.0),), tip_clearance_m=0.5)


def _one(y_m, *, x_aft_m=-3.0, bow_x_m=10.0, area_m2=4.0, thickness_m=1.0, **kw):
    return transport_cusps([bow_x_m], [bow_x_m + x_aft_m], [y_m], [area_m2], [thickness_m], **kw)


def test_centreline_cusp_hugging_the_hull_reaches_a_centre_propeller_at_top_dead_centre():
    # a long run: the cusp rises onto the hull above the disc, z_hull = 5 − 2 − 0.5 = 2.5 m; its lower face
    # at 3.5 m is 1.5 m above the axis: r/R = 1.5 / 2, at top dead centre
    hull = HullUnderwater(run_length_m=200.0)
    got = _one(0.0, hull=hull, arrangement=CENTRE)
    assert got.propeller_index.tolist() == [0]
    assert got.path.tolist() == [PATH_PROPELLER]
    assert got.entry_radius_fraction[0] == pytest.approx(0.75)
    assert got.entry_angle_deg[0] == pytest.approx(0.0)


def test_cross_section_is_given_relative_to_the_reached_shaft_centre():
    # hugging the hull above the disc: z from 2.5 to 3.5 m, i.e. 2.5 … 1.5 m above the axis at 5 m; the
    # area 4 m² gives half-width 1 m about y = 0.3 m
    hull = HullUnderwater(run_length_m=200.0)
    got = _one(0.3, hull=hull, arrangement=CENTRE)
    y_lo, y_hi, z_lo, z_hi = (float(a[0]) for a in got.cross_section_m)
    assert (y_lo, y_hi, z_lo, z_hi) == pytest.approx((-0.7, 1.3, -2.5, -1.5))


def test_cross_section_is_nan_without_a_propeller_and_on_the_winning_shaft_with_two():
    hull = HullUnderwater(run_length_m=200.0)
    two = PropellerArrangement(
        (
            Propeller(5.5, diameter_m=4.0, shaft_depth_m=5.0),
            Propeller(-5.5, diameter_m=4.0, shaft_depth_m=5.0),
        ),
        tip_clearance_m=0.5,
    )
    got = transport_cusps(
        [10.0] * 3, [7.0] * 3, [-5.0, 0.0, 5.0], [4.0] * 3, [1.0] * 3, hull=hull, arrangement=two
    )
    assert got.propeller_index.tolist() == [1, NO_PROPELLER, 0]
    y_lo, y_hi = got.cross_section_m[0], got.cross_section_m[1]
    assert (y_lo[0], y_hi[0]) == pytest.approx((-5.0 - 1.0 + 5.5, -5.0 + 1.0 + 5.5))
    assert (y_lo[2], y_hi[2]) == pytest.approx((5.0 - 1.0 - 5.5, 5.0 + 1.0 - 5.5))
    assert all(np.isnan(a[1]) for a in got.cross_section_m)


def test_cusp_thinner_than_the_tip_clearance_passes_over_the_disc():
    hull = HullUnderwater(run_length_m=200.0)
    got = _one(0.0, thickness_m=0.4, hull=hull, arrangement=CENTRE)  # 0.4 m < c_tip = 0.5 m
    assert got.propeller_index.tolist() == [NO_PROPELLER]
    assert np.isnan(got.arrival_time_s[0]) and np.isnan(got.entry_radius_fraction[0])


def test_rise_speed_balances_buoyancy_and_drag():
    h, cd = 0.8, 1.2
    w = float(terminal_rise_speed_m_s(h, cd))
    buoyancy_n_per_m2 = (1025.0 - 917.0) * 9.81 * h
    drag_n_per_m2 = 0.5 * 1025.0 * cd * w**2
    assert drag_n_per_m2 == pytest.approx(buoyancy_n_per_m2)


def test_a_short_run_leaves_the_cusp_deep_in_the_disc():
    # run 3 m at 3 m/s: 1 s of rise from the bottom (top face at T = 7.65 m)
    hull = HullUnderwater(run_length_m=3.0)
    w = math.sqrt(2 * 9.81 * 1.0 * (1025.0 - 917.0) / (1025.0 * 1.17))
    z_top = 7.65 - w * 1.0
    got = _one(0.0, hull=hull, arrangement=CENTRE)
    assert got.entry_radius_fraction[0] == pytest.approx((z_top - 5.0) / 2.0)
    assert got.entry_angle_deg[0] == pytest.approx(180.0)  # below the axis


def test_lateral_offset_gives_the_entry_angle_towards_port():
    # cusp 2 m wide (area 4 m²) centred 2 m to port of a centre shaft, hugging the hull: nearest point of
    # its cross-section (y 1 m, z 3.5 m) lies 1 m to port and 1.5 m above the axis
    hull = HullUnderwater(run_length_m=200.0)
    got = _one(2.0, hull=hull, arrangement=CENTRE)
    assert got.entry_radius_fraction[0] == pytest.approx(math.hypot(1.0, 1.5) / 2.0)
    assert got.entry_angle_deg[0] == pytest.approx(math.degrees(math.atan(1.0 / 1.5)))
    # 2.5 m to port, the nearest point (1.5 m, 1.5 m above) lies outside the 2 m disc: no contact
    assert _one(2.5, hull=hull, arrangement=CENTRE).propeller_index.tolist() == [NO_PROPELLER]


def test_cusp_outside_the_beam_or_on_the_bilge_reaches_none():
    for y in (0.5 * HULL.beam_m + 1.0, -(HULL.flat_half_width_m + 0.1)):
        got = _one(y)
        assert got.propeller_index.tolist() == [NO_PROPELLER]
        assert got.path.tolist() == [PATH_BILGE]


def test_shoulder_cusps_rise_beside_the_hull_unless_told_to_submerge():
    x_aft = -0.75 * HULL.bow_length_m  # in the shoulder region (start 0.5 L_b)
    y = 5.5  # on the default port shaft line
    got = _one(y, x_aft_m=x_aft)
    assert got.region.tolist() == ["shoulder"] and got.path.tolist() == [PATH_SHOULDER]
    submerged = _one(y, x_aft_m=x_aft, params=TransportParameters(shoulder_cusps_submerge=True))
    stem = _one(y, x_aft_m=-1.0)
    assert submerged.propeller_index.tolist() == stem.propeller_index.tolist() == [0]


def test_regions_follow_the_dispatch_rule():
    rng = np.random.default_rng(5)
    bow_x = rng.uniform(0, 300, 200)
    x_aft = rng.uniform(-40, 3, 200)
    got = transport_cusps(bow_x, bow_x + x_aft, np.zeros(200), np.full(200, 4.0), np.ones(200))
    expected = [bow_region(x, HULL.bow_length_m, 0.5) for x in x_aft]
    assert got.region.tolist() == expected


def _random_cusps(rng, n=400):
    bow_x = np.sort(rng.uniform(0, 385, n))
    return {
        "bow_x_m": bow_x,
        "centroid_x_m": bow_x + rng.uniform(-30, 2, n),
        "centroid_y_m": rng.uniform(-12, 12, n),
        "area_m2": rng.uniform(1, 14, n),
        "thickness_m": rng.uniform(0.5, 2.0, n),
    }


def test_symmetric_arrangement_gives_a_mirror_symmetric_assignment():
    cusps = _random_cusps(np.random.default_rng(1))
    mirrored = {**cusps, "centroid_y_m": -cusps["centroid_y_m"]}
    a, b = transport_cusp_table(cusps), transport_cusp_table(mirrored)
    swap = np.array([1, 0, NO_PROPELLER])  # index −1 maps to the last entry
    assert np.array_equal(b.propeller_index, swap[a.propeller_index])
    assert a.counts().sum() > 0
    np.testing.assert_allclose(b.entry_radius_fraction, a.entry_radius_fraction)
    np.testing.assert_allclose(b.entry_angle_deg, -a.entry_angle_deg)


def test_arrival_time_is_made_time_plus_distance_over_relative_speed():
    v = 2.5
    hull = HullUnderwater(run_length_m=200.0)
    for slip in (1.0, 0.5):
        got = _one(0.0, bow_x_m=40.0, x_aft_m=-4.0, speed_m_s=v, hull=hull, arrangement=CENTRE,
                   params=TransportParameters(slip_factor=slip))  # fmt: skip
        expected = 40.0 / v + (HULL.propeller_plane_aft_of_stem_m - 4.0) / (slip * v)
        assert got.arrival_time_s[0] == pytest.approx(expected)


def test_reaching_never_decreases_with_smaller_clearance_or_bilge_or_thicker_ice_hugging_the_hull():
    # not monotone in general: a thin cusp that hardly rises can pass below the disc (T > z_s + R), so
    # thickness and speed are monotone only for cusps on the hull (a long run)
    cusps = _random_cusps(np.random.default_rng(2))

    def reached(thickness_scale=1.0, clearance=0.86, bilge=2.5, run=15.0):
        table = {**cusps, "thickness_m": cusps["thickness_m"] * thickness_scale}
        arrangement = PropellerArrangement(tip_clearance_m=clearance)
        hull = HullUnderwater(bilge_radius_m=bilge, run_length_m=run)
        return transport_cusp_table(table, hull=hull, arrangement=arrangement).counts().sum()

    for key, values in {
        "clearance": [2.0, 1.5, 1.0, 0.5, 0.0],
        "bilge": [6.0, 4.0, 2.5, 1.0, 0.0],
    }.items():
        counts = [reached(**{key: value}) for value in values]
        assert counts == sorted(counts), key
        assert counts[-1] > counts[0], key
    hugging = [reached(thickness_scale=s, run=200.0) for s in (0.5, 0.8, 1.0, 1.5, 2.0)]
    assert hugging == sorted(hugging) and hugging[-1] > hugging[0]


def test_lateral_spread_is_reproducible_with_a_seed_and_needs_a_generator():
    cusps = _random_cusps(np.random.default_rng(3))
    params = TransportParameters(lateral_spread_m=1.0)
    a = transport_cusp_table(cusps, params=params, rng=np.random.default_rng(7))
    b = transport_cusp_table(cusps, params=params, rng=np.random.default_rng(7))
    assert np.array_equal(a.propeller_index, b.propeller_index)
    with pytest.raises(InputError, match=re.escape("transport.lateral_spread_m")):
        transport_cusp_table(cusps, params=params)


@pytest.mark.parametrize(
    ("build", "key"),
    [
        (lambda: TransportParameters(slip_factor=0.0), "transport.slip_factor"),
        (lambda: TransportParameters(slip_factor=1.2), "transport.slip_factor"),
        (lambda: TransportParameters(drag_coefficient=0.1), "transport.drag_coefficient"),
        (lambda: TransportParameters(lateral_spread_m=-1.0), "transport.lateral_spread_m"),
        (lambda: TransportParameters(shoulder_region_start=1.5), "transport.shoulder_region_start"),
        (lambda: HullUnderwater(draught_m=0.0), "transport.hull.draught_m"),
        (lambda: HullUnderwater(bilge_radius_m=11.0), "transport.hull.bilge_radius_m"),
        (lambda: HullUnderwater(run_length_m=0.0), "transport.hull.run_length_m"),
        (lambda: Propeller(0.0, diameter_m=0.0), "transport.propeller.diameter_m"),
        (lambda: PropellerArrangement(tip_clearance_m=-0.1), "transport.arrangement.tip_clearance_m"),
        (lambda: PropellerArrangement((Propeller(0.0, shaft_depth_m=2.0),)), "propellers[0].shaft_depth_m"),
        (lambda: PropellerArrangement(()), "transport.arrangement.propellers"),
        (lambda: _one(0.0, speed_m_s=0.0), "ship.speed_m_s"),
        (lambda: _one(0.0, arrangement=PropellerArrangement((Propeller(12.0),))), "offset_y_m"),
        (lambda: _one(0.0, thickness_m=0.0), "transport.cusps.thickness_m"),
        (lambda: _one(float("nan")), "transport.cusps.centroid_y_m"),
    ],
)
def test_bad_input_names_the_key(build, key):
    with pytest.raises(InputError, match=re.escape(key)) as err:
        build()
    assert "allowed" in str(err.value) or "outside" in str(err.value)


def test_the_discs_take_the_propeller_radius_with_their_bottom_above_the_base_line():
    """`TransportSettings.arrangement`: D = 2 R, z_s = T − R − 0.25 m (docs/model.md's parameter table:
    4.3 m and 5.25 m for R = 2.15 m and T = 7.65 m); a disc and the 0.86 m clearance above it fill the
    draught at R = (7.65 − 0.25 − 0.86) / 2 = 3.27 m."""
    assert TransportSettings().arrangement(2, 2.15) == PropellerArrangement()
    three = TransportSettings().arrangement(3, 1.5)
    assert [p.offset_y_m for p in three.propellers] == [5.5, 0.0, -5.5]
    assert all(p.diameter_m == 3.0 for p in three.propellers)
    assert all(p.shaft_depth_m == pytest.approx(5.9) for p in three.propellers)
    assert TransportSettings().arrangement(1, 3.27).propellers[0].offset_y_m == 0.0
    with pytest.raises(InputError) as info:
        TransportSettings().arrangement(2, 3.28)
    assert info.value.field == "propeller.radius_m"
