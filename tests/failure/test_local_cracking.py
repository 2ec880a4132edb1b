"""Local cracking (thesis §4.3, Alg. 6, Eq. 21, Fig. 12): a crack orthogonal to the bow that turns through a
Bezier curve into the bending line towards the stern.

Checked against the thesis' construction: the crack part starts at O − (ℓ/5) n̂ on the line through O along
n̂ (Alg. 6 startCusp); the Bezier part starts where the crack part ends and ends on the bending arc of radius
ξ_σ ℓ about O (Eq. 21: its last nodes are bending-line points); the bending part continues along that arc, one
5° chord further, towards the stern. On the floe: the cut starts at the bow and ends on the floe boundary, the
separated piece lies on the stern side of the crack line, and the area is conserved.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import shapely

from floebreak.failure import Fate, LocalCracking, Status
from floebreak.failure.bending import BendingSettings, bending_check
from floebreak.failure.local_cracking import frontmost_contact_point, local_crack_line
from floebreak.ice.field import circle_polygons
from floebreak.mechanics.classify import ClassificationParams, classify

PHI_RAD = math.radians(5.0)
CASES = [(5, 10.0, 0.3), (10, 10.0, 0.6), (10, 20.0, 0.5), (50, 10.0, 0.6), (15, 4.0, 0.3)]


def circle_against_panel(bow, panel: int, radius_m: float, penetration_m: float):
    """A circular floe pressed `penetration_m` into the middle of an upper-waterline panel."""
    upper = np.asarray(bow.upper_xy_m)
    mid = 0.5 * (upper[panel] + upper[panel + 1])
    normal = np.asarray(bow.panel_normals[panel])
    return circle_polygons(np.array([mid + (radius_m - penetration_m) * normal]), np.array([radius_m]), 128)[
        0
    ]


def stern_tangent(normal) -> np.ndarray:
    """Unit tangent of the waterline (⊥ n̂) that points aft (−x)."""
    t = np.array([-normal[1], normal[0]])
    return t if t[0] < 0 else -t


@pytest.mark.parametrize(("panel", "radius_m", "penetration_m"), CASES)
def test_line_parts_join_and_follow_the_thesis_construction(
    bow, context, make_input, kit, panel, radius_m, penetration_m
):
    floe = circle_against_panel(bow, panel, radius_m, penetration_m)
    inp = make_input(floe)
    check = bending_check(inp, context, BendingSettings())
    o = inp.zone.centre_xy_m
    u = np.asarray(inp.zone.centre_normal)
    ell = kit.ell_m(inp.thickness_m)
    big_r = check.breaking_radius_m
    x_int = frontmost_contact_point(floe, context.bow_geometry.waterline)
    line = local_crack_line(o, u, x_int, big_r, ell, PHI_RAD)
    crack, bezier, bend = line.crack_part, line.bezier_part, line.bend_part
    # crack part: starts at O − ℓ/5 n̂ and runs along n̂ through O
    np.testing.assert_allclose(crack[0], o - ell / 5.0 * u, atol=1e-9)
    rel = crack - o
    np.testing.assert_allclose(rel[:, 0] * u[1] - rel[:, 1] * u[0], 0.0, atol=1e-9)
    # C0: Bezier starts at the last crack point …
    np.testing.assert_array_equal(bezier[0], crack[-1])
    # … and ends on the bending arc, from which the bending part continues one 5° chord further
    assert np.hypot(*(bezier[-1] - o)) == pytest.approx(big_r, rel=1e-9)
    assert len(bend) >= 1
    np.testing.assert_allclose(np.hypot(*(bend - o).T), big_r, rtol=1e-9)
    chord = 2.0 * big_r * math.sin(PHI_RAD / 2.0)
    steps = np.hypot(*np.diff(np.vstack([bezier[-1:], bend]), axis=0).T)
    np.testing.assert_allclose(steps, chord, rtol=1e-9)
    # the bending part turns towards the stern and ends on the crack line behind O (angle π from n̂)
    t = stern_tangent(u)
    assert np.all((bend - o) @ t >= -1e-9)
    np.testing.assert_allclose(bend[-1], o - big_r * u, atol=1e-9)
    # the concatenated line is the three parts in order, the shared junction point once
    np.testing.assert_array_equal(line.line, np.concatenate([crack, bezier[1:], bend]))


@pytest.mark.parametrize(("panel", "radius_m", "penetration_m"), CASES)
def test_cut_runs_from_the_bow_contact_to_the_floe_boundary(
    bow, context, make_input, panel, radius_m, penetration_m
):
    floe = circle_against_panel(bow, panel, radius_m, penetration_m)
    inp = make_input(floe)
    outcome = LocalCracking().evaluate(inp, context)
    assert outcome.failed, outcome.status
    assert len(outcome.pieces) == 2
    assert all(piece.fate == Fate.FLOE for piece in outcome.pieces)
    a, b = (piece.polygon for piece in outcome.pieces)
    cut = shapely.line_merge(shapely.intersection(a.boundary, b.boundary))
    assert cut.geom_type == "LineString"  # one continuous cut through the floe
    ends = [shapely.Point(xy) for xy in shapely.get_coordinates(cut)[[0, -1]]]
    assert all(shapely.distance(end, floe.boundary) < 1e-9 for end in ends)
    hull = context.bow_geometry.hull_upper
    to_hull = sorted(shapely.distance(end, hull) for end in ends)
    assert to_hull[0] < 1e-9  # starts at the bow (in the contact)
    assert to_hull[1] > 0.5  # ends on the floe boundary away from the bow
    # the separated (smaller) piece lies on the stern side of the crack line through O
    small = min((a, b), key=lambda q: q.area)
    centroid = np.array(small.centroid.coords[0])
    assert (centroid - inp.zone.centre_xy_m) @ stern_tangent(inp.zone.centre_normal) > 0.0
    assert a.area + b.area == pytest.approx(floe.area, rel=1e-9)
    assert shapely.area(shapely.intersection(a, b)) <= 1e-9 * floe.area
    assert a.is_valid and b.is_valid


def test_no_local_cracking_below_the_bending_capacity(context, make_input, kit):
    """Same criterion as bending (thesis §4.3.1, Eq. 11): F_v = 0.12 MN < P_f ≈ 0.3 MN → no failure."""
    inp = make_input(kit.midbody_box(8.0, 20.0, 0.02))
    outcome = LocalCracking().evaluate(inp, context)
    assert outcome.status is Status.INTACT  # the floe holds: the policy tries no other mode
    assert outcome.pieces == ()


def test_a_symmetric_floe_cracks_locally_at_either_shoulder_as_the_mirror_of_the_other(
    bow, context, make_input
):
    """A floe wrapping the bow, mirror-symmetric, touching both shoulders (two zones): the piece cut at the
    starboard shoulder is the mirror image of the one cut at port. x_int (Eq. 21) is the frontmost point
    where the waterline meets the outline *at that zone*: the frontmost of the whole outline lies at one
    shoulder, and started the other shoulder's crack from across the hull (17.25 m² against 17.33 m²)."""
    inner, outer = 9.6, 11.6
    u_shape = shapely.difference(
        shapely.box(-40.0, -outer, 3.0, outer), shapely.box(-40.0, -inner, 1.0, inner)
    )
    inp = make_input(u_shape, crack_count=1)
    assert len(inp.contact.zones) == 2
    outcomes = {}
    for zone in inp.contact.zones:
        classification = classify(u_shape, 1.0, zone.centre_normal, ClassificationParams())
        at_zone = dataclasses.replace(inp, zone=zone, classification=classification)
        outcomes[np.sign(zone.centre_xy_m[1])] = LocalCracking().evaluate(at_zone, context)
    port, starboard = outcomes[1.0], outcomes[-1.0]
    assert port.status == starboard.status == Status.FAILED
    mirror = np.array([1.0, -1.0])
    for piece in port.pieces:
        image = shapely.transform(piece.polygon, lambda xy: xy * mirror)
        gaps = [shapely.hausdorff_distance(image, other.polygon) for other in starboard.pieces]
        assert min(gaps) < 1e-9
