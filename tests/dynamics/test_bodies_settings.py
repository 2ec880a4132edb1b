"""Mass properties of pieces and the bad inputs of the ice-motion settings."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import shapely
from shapely import affinity

from floebreak.dynamics import IceMotionSettings, body_geometry
from floebreak.dynamics.bodies import (
    _RULE_WEIGHTS,
    _SUB_POINTS,
    _fsum,
    _yaw_form_integrals,
    _yaw_skin_integral,
    projected_width_m,
)
from floebreak.errors import InputError


def test_rectangle_moment_is_m_a2_plus_b2_over_12():
    g = body_geometry(affinity.rotate(shapely.box(3, 4, 7, 6), 33.0))
    assert g.area_m2 == pytest.approx(8.0)
    assert g.polar_moment_m4 == pytest.approx(8.0 * (16 + 4) / 12)
    assert g.centroid_xy_m == pytest.approx((5.0, 5.0))


@pytest.mark.parametrize("x_m", [0.0, 1.0e3, 1.0e5])
def test_a_thin_piece_far_down_the_transit_keeps_its_moment(x_m):
    """A 2 m × 0.05 m strip turned by 30°, at x up to 100 km (a long transit's field frame): its centroid and
    its moment about it are the rectangle's, A(a² + b²)/12, to the precision its coordinates carry. Computed
    from field coordinates, the polar moment at the origin and A·|c|² are 1e10 times the strip's own moment
    and their difference was noise, often negative (Chipmunk aborted a 100 km run on one)."""
    a, b, angle = 2.0, 0.05, math.radians(30.0)
    centre = (x_m + 0.3, 137.9)
    strip = affinity.rotate(shapely.box(-a / 2, -b / 2, a / 2, b / 2), angle, origin=(0, 0), use_radians=True)
    geometry = body_geometry(affinity.translate(strip, *centre))
    ulp = np.spacing(max(abs(centre[0]), abs(centre[1])))  # the coordinates' own resolution
    assert geometry.centroid_xy_m == pytest.approx(centre, abs=8 * ulp)
    assert geometry.polar_moment_m4 == pytest.approx(a * b * (a * a + b * b) / 12.0, rel=1e-6)


def test_concave_piece_decomposes_exactly_and_its_moment_follows_the_parallel_axis_theorem():
    ell = shapely.Polygon([(0, 0), (3, 0), (3, 1), (1, 1), (1, 3), (0, 3)])
    g = body_geometry(ell)
    parts = [shapely.Polygon(p) for p in g.convex_parts]
    assert len(parts) > 1
    for p in parts:
        assert p.convex_hull.area == pytest.approx(p.area, rel=1e-12)
    assert shapely.union_all(parts).symmetric_difference(shapely.Polygon(g.ring_xy_m)).area < 1e-12
    # two rectangles 3×1 (centre (1.5, .5)) and 1×2 (centre (.5, 2)); centroid (1.1, 1.1)
    cx = cy = (3 * 1.5 * 0 + 3 * 0.5 + 2 * 2.0) / 5.0
    assert g.centroid_xy_m == pytest.approx((1.1, 1.1)) and cy == pytest.approx(1.1) and cx == cx
    rects = [(3.0, 1.0, 1.5, 0.5), (1.0, 2.0, 0.5, 2.0)]
    j = sum(a * b * (a * a + b * b) / 12 + a * b * ((x - 1.1) ** 2 + (y - 1.1) ** 2) for a, b, x, y in rects)
    assert g.polar_moment_m4 == pytest.approx(j, rel=1e-12)


def test_yaw_drag_integrals_of_a_disc():
    r = 3.0
    g = body_geometry(shapely.Point(0, 0).buffer(r, 512))
    assert g.yaw_skin_m5 == pytest.approx(2 * math.pi * r**5 / 5, rel=1e-3)  # ∫ r³ dA
    assert max(g.yaw_form_m3) < 1e-6 * r**4  # a disc's edge moves tangentially: no form drag in yaw


def _square_yaw_form_m3(half_side_m: float) -> float:
    """K± of a square about its centre: on each edge s = (r × n)·ẑ runs linearly from +a to −a (a the
    half-side), so ∫ max(s, 0)³ dl = ∫₀ᵃ s³ ds = a⁴/4 per edge, a⁴ over the four."""
    return half_side_m**4


def test_yaw_form_integral_of_a_ring_with_a_repeated_vertex_counts_the_empty_edge_as_zero():
    a = 1.5
    ring = np.array([[-a, -a], [a, -a], [a, -a], [a, a], [-a, a]])  # (a, −a) twice: an edge of length 0
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # 0/0 for the edge's normal was the failure
        plus, minus = _yaw_form_integrals(ring)
    expected = _square_yaw_form_m3(a)
    assert plus == pytest.approx(expected, rel=1e-12) and minus == pytest.approx(expected, rel=1e-12)


def test_two_vertices_that_meet_in_the_body_frame_give_one():
    """A crack ending 5e-17 m from a vertex (the centred floe of a crash): the two vertices are
    distinct in the field frame and one point once the centroid (1, 1) is subtracted."""
    polygon = shapely.Polygon([(0, 0), (2, 0), (2, 5e-17), (2, 2), (0, 2)])
    assert polygon.is_valid
    g = body_geometry(polygon)
    edges = np.diff(np.vstack([g.ring_xy_m, g.ring_xy_m[:1]]), axis=0)
    assert len(g.ring_xy_m) == 4 and np.all(np.hypot(edges[:, 0], edges[:, 1]) > 0.0)
    assert g.yaw_form_m3 == pytest.approx((_square_yaw_form_m3(1.0),) * 2, rel=1e-12)
    assert g.area_m2 == pytest.approx(4.0, rel=1e-15)


def test_projected_width_of_a_square_seen_diagonally():
    ring = body_geometry(shapely.box(0, 0, 2, 2)).ring_xy_m
    assert projected_width_m(ring, [1.0, 0.0]) == pytest.approx(2.0)
    assert projected_width_m(ring, [math.sqrt(0.5), math.sqrt(0.5)]) == pytest.approx(2 * math.sqrt(2))


@pytest.mark.parametrize(
    ("key", "value"),
    [
        ("form_drag_coefficient", 0.0),
        ("form_drag_coefficient", -1.0),
        ("skin_drag_coefficient", 0.0),
        ("ice_ice_friction", -0.1),
        ("ice_hull_friction", -0.1),
        ("ice_ice_restitution", 1.5),
        ("ice_hull_restitution", -0.2),
        ("added_mass_coefficient", -0.1),
        ("added_inertia_coefficient", -0.1),
        ("window_ahead_m", 0.0),
        ("window_behind_m", -5.0),
        ("window_side_m", 0.0),
        ("time_step_s", 0.0),
    ],
)
def test_bad_setting_names_its_key(key, value):
    with pytest.raises(InputError, match=rf"ice_motion\.{key}"):
        IceMotionSettings(**{key: value})


def test_time_step_that_cannot_resolve_the_speed_is_an_input_error():
    s = IceMotionSettings(time_step_s=0.1)  # 0.25·1 m per step allows 2.5 m/s
    s.check_time_step(2.5)
    with pytest.raises(InputError, match=r"ice_motion\.time_step_s"):
        s.check_time_step(3.0)


def test_zero_ice_ice_restitution_with_a_hull_restitution_is_refused():
    IceMotionSettings(ice_ice_restitution=0.0, ice_hull_restitution=0.0)
    with pytest.raises(InputError, match=r"ice_motion\.ice_ice_restitution"):
        IceMotionSettings(ice_ice_restitution=0.0, ice_hull_restitution=0.1)


def test_compiled_exact_sum_rounds_as_math_fsum():
    """The yaw skin integral's compiled sum against Python's `math.fsum` on sums that a plain running sum
    gets wrong: cancellation of huge terms, and the half-even ties across partials."""
    rng = np.random.default_rng(7)
    cases = [
        [],
        [1e100, 1.0, -1e100, 1e-100],
        [1.0, 1e-16, 1e-16],  # a plain sum gives 1.0, the exact sum rounds up
        [1.0, 2.0**-53, 2.0**-106],  # above the tie: rounds up
        [1.0, 2.0**-53, -(2.0**-106)],  # below the tie: rounds down
        *(rng.standard_normal(200) * 10.0 ** rng.integers(-20, 20, 200) for _ in range(20)),
    ]
    for terms in cases:
        assert _fsum(np.array(terms, dtype=float)) == math.fsum(list(terms))


def test_yaw_skin_integral_is_the_numpy_fan_sum_to_the_bit():
    """The compiled fan quadrature gives exactly the terms of the same quadrature written as one numpy
    broadcast (summed by `math.fsum`), for concave and random rings."""
    rng = np.random.default_rng(3)
    rings = [
        np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 1.0], [1.0, 1.0], [1.0, 3.0], [0.0, 3.0]]) - [1.5, 1.2],
        *(rng.standard_normal((int(rng.integers(3, 40)), 2)) * 7.0 for _ in range(30)),
    ]
    for ring in rings:
        a, b = ring, np.roll(ring, -1, axis=0)
        area = (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]) / 2.0
        uv = _SUB_POINTS
        pts = uv[:, None, :, 0, None] * a[None, :, None, :] + uv[:, None, :, 1, None] * b[None, :, None, :]
        # cubed by libm's pow, element by element, as the kernel does: numpy's vectorised power takes
        # other (SIMD) code paths on CPUs with AVX-512, and differs from pow in the last bit there
        radius = np.hypot(pts[..., 0], pts[..., 1])
        radius_cubed = np.array([math.pow(r, 3.0) for r in radius.ravel().tolist()]).reshape(radius.shape)
        terms = area[None, :, None] / 16 * _RULE_WEIGHTS[None, None, :] * radius_cubed
        assert _yaw_skin_integral(ring) == abs(math.fsum(terms.ravel().tolist()))
