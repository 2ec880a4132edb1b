"""Circle placement (floebreak.ice.packing): the dense corner-insertion fallback against known packings; the
relaxation energy against its array form and finite differences."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from floebreak.ice import packing
from floebreak.ice.packing import corner_circles


def brute_force_min_gap_m(centers_m: np.ndarray, radii_m: np.ndarray) -> float:
    """Smallest surface gap d_ij − r_i − r_j over all pairs, computed independently of the package."""
    i, j = np.triu_indices(len(radii_m), 1)
    d = np.hypot(*(centers_m[i] - centers_m[j]).T)
    return float(np.min(d - radii_m[i] - radii_m[j]))


def assert_inside(centers_m, radii_m, domain_m):
    x0, y0, x1, y1 = domain_m
    assert np.all(centers_m[:, 0] - radii_m >= x0) and np.all(centers_m[:, 0] + radii_m <= x1)
    assert np.all(centers_m[:, 1] - radii_m >= y0) and np.all(centers_m[:, 1] + radii_m <= y1)


def test_four_equal_circles_fill_a_square_and_a_fifth_does_not_fit():
    # the densest packing of 4 equal circles in a square is the 2 × 2 grid: side 4 r (+ gaps);
    # 5 circles need side (2 + 2√2) r ≈ 4.83 r (known optimum), so the fifth must be refused
    gap = 0.01
    domain = (0.0, 0.0, 4.0 + 2.0 * gap, 4.0 + 2.0 * gap)
    four = corner_circles(np.ones(4), domain, np.random.default_rng(0), gap_m=gap)
    assert four.overlap_free and four.placed is None
    assert brute_force_min_gap_m(four.centers_m, four.radii_m) >= gap - 1e-9
    assert_inside(four.centers_m, four.radii_m, domain)
    five = corner_circles(np.ones(5), domain, np.random.default_rng(0), gap_m=gap)
    assert not five.overlap_free
    assert five.placed is not None and int(five.placed.sum()) == 4


def test_dense_three_class_field_without_overlap():
    # the 89 % Table 1 row in 480 m × 240 m: 31 × 60 m, 63 × 15 m, 63 × 7.5 m floes, circle cover
    # Σ π r² / A = π (31·30² + 63·7.5² + 63·3.75²) / 115 200 = 88.2 %
    radii = np.repeat([30.0, 7.5, 3.75], [31, 63, 63])
    domain = (0.0, -120.0, 480.0, 120.0)
    packing = corner_circles(radii, domain, np.random.default_rng(4))
    assert packing.overlap_free and packing.placed is None
    assert brute_force_min_gap_m(packing.centers_m, packing.radii_m) >= 0.01 - 1e-9
    assert_inside(packing.centers_m, packing.radii_m, domain)
    assert np.sum(np.pi * radii**2) / (480.0 * 240.0) > 0.88


def test_corner_insertion_is_random_given_the_generator():
    radii = np.repeat([3.0, 1.0], [10, 30])
    domain = (0.0, 0.0, 30.0, 20.0)
    a = corner_circles(radii, domain, np.random.default_rng(1))
    b = corner_circles(radii, domain, np.random.default_rng(1))
    c = corner_circles(radii, domain, np.random.default_rng(2))
    assert np.array_equal(a.centers_m, b.centers_m)
    assert not np.allclose(a.centers_m, c.centers_m)


def pair_terms_by_array_expressions(xy, radii, i, j, gap, middle):
    """`packing._pair_terms` as the numpy array expressions `_energy` used before they were compiled: the
    compiled terms must give the same bits, or every generated field changes."""
    delta = xy[i] - xy[j]
    dist = np.sqrt(np.einsum("ij,ij->i", delta, delta))
    coincident = dist < 1e-9
    if np.any(coincident):
        inward = middle - xy[i[coincident]] + 1e-3
        delta[coincident] = 1e-9 * inward / np.hypot(*inward.T)[:, None]
        dist[coincident] = 1e-9
    surface_gap = dist - radii[i] - radii[j]
    overlap = np.maximum(0.0, gap - surface_gap)
    return delta, dist, surface_gap, overlap, -2.0 * overlap / dist


def test_compiled_pair_terms_and_gradient_give_the_bits_of_the_array_expressions():
    rng = np.random.default_rng(8)
    for n in (2, 30, 400):
        radii = rng.uniform(0.2, 2.0, n)
        xy = rng.uniform(0.0, 2.0 * np.sqrt(n), (n, 2))
        xy[1] = xy[0]  # two circles on the same spot (the coincident branch)
        i, j = np.triu_indices(n, 1)
        middle = np.array([np.sqrt(n), np.sqrt(n)])
        expected = pair_terms_by_array_expressions(xy, radii, i, j, 0.01, middle)
        for got, want in zip(packing._pair_terms(xy, radii, i, j, 0.01, middle), expected, strict=True):
            np.testing.assert_array_equal(got, want)
        # the gradient as np.bincount sums it, for any per-pair coefficient (clustering changes it)
        coef = rng.normal(size=len(i))
        force = coef[:, None] * expected[0]
        want = np.stack(
            [np.bincount(i, force[:, a], n) - np.bincount(j, force[:, a], n) for a in (0, 1)], axis=1
        )
        np.testing.assert_array_equal(packing._gradient(i, j, coef, expected[0], n), want)


def test_energy_gradient_matches_finite_differences():
    rng = np.random.default_rng(9)
    n = 12
    radii = rng.uniform(0.5, 1.5, n)
    xy = rng.uniform(0.0, 6.0, 2 * n)
    pairs = np.array([(a, b) for a in range(n) for b in range(a + 1, n)])
    middle = np.array([3.0, 3.0])
    _, grad = packing._energy(xy, radii, pairs, 0.01, 0.0, middle)
    step = 1e-6
    for k in range(2 * n):
        up, down = xy.copy(), xy.copy()
        up[k] += step
        down[k] -= step
        numeric = (
            packing._energy(up, radii, pairs, 0.01, 0.0, middle)[0]
            - packing._energy(down, radii, pairs, 0.01, 0.0, middle)[0]
        ) / (2 * step)
        assert grad[k] == pytest.approx(numeric, rel=1e-5, abs=1e-7)


def test_a_failed_dense_packing_marks_the_circles_it_could_not_place():
    """Four large circles fill most of the box; forty middle ones (distinct radii, so no corner fallback)
    cannot fit beside them, so the ten small ones are never tried: the packing names the placed circles, and
    the never-tried ones have no centre (NaN, not stale memory)."""
    radii = np.r_[np.full(4, 1.0), np.linspace(0.40, 0.45, 40), np.linspace(0.10, 0.12, 10)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # scaling the centres must not meet uninitialised values
        result = packing.relax_circles(radii, (0.0, 0.0, 4.2, 4.2), np.random.default_rng(1))
    assert not result.overlap_free
    assert result.placed is not None
    assert result.placed[:4].all() and not result.placed[4:].any()
    assert np.isfinite(result.centers_m[:44]).all()  # the placed group and the one that did not fit
    assert np.isnan(result.centers_m[44:]).all()


def test_a_circle_as_wide_as_the_domain_is_placed_where_the_bounds_fix_it():
    """A circle whose diameter is the domain's width and height has one admissible centre, the middle; when
    the bounds fix every coordinate of a round, scipy's optimiser does no iteration and reports none — fuzz
    campaign: a 60 m × 60 m field with a 60 m floe ended in an AttributeError."""
    radii = np.array([30.0, 2.0])  # the 2 m circle fits in a corner: (2, 2) is 39.6 m from the middle
    result = packing.relax_circles(radii, (0.0, 0.0, 60.0, 60.0), np.random.default_rng(1))
    assert result.centers_m[0] == pytest.approx([30.0, 30.0], abs=packing.DEFAULT_GAP_M)


def test_sqp_places_a_circle_as_wide_as_the_domain_where_the_bounds_fix_it():
    """As for the relaxation: with every coordinate fixed by the bounds SLSQP does no iteration and reports
    none — fuzz campaign (seed 3, scenarios 3363–3364: an sqp field as wide as its largest floe) ended in an
    AttributeError."""
    radii = np.array([30.0])
    result = packing.sqp_circles(radii, (0.0, 0.0, 60.0, 60.0), np.random.default_rng(1))
    assert result.centers_m[0] == pytest.approx([30.0, 30.0], abs=packing.DEFAULT_GAP_M)
    assert result.iterations == 0
