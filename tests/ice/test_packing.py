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


def energy_by_array_expressions(flat, radii, pairs, gap, clustering, middle):
    """The energy and gradient of `packing._energy` as numpy array expressions (its form before the pair
    terms were compiled): the compiled version must give the same bits, or every generated field changes."""
    n = len(radii)
    xy = flat.reshape(n, 2)
    i, j = pairs[:, 0], pairs[:, 1]
    delta = xy[i] - xy[j]
    dist = np.sqrt(np.einsum("ij,ij->i", delta, delta))
    coincident = dist < 1e-9
    if np.any(coincident):
        inward = middle - xy[i[coincident]] + 1e-3
        delta[coincident] = 1e-9 * inward / np.hypot(*inward.T)[:, None]
        dist[coincident] = 1e-9
    surface_gap = dist - radii[i] - radii[j]
    overlap = np.maximum(0.0, gap - surface_gap)
    energy = float(np.dot(overlap, overlap))
    coef = -2.0 * overlap / dist
    if clustering > 0.0 and len(pairs):
        nearest = np.full(n, np.inf)
        order = np.argsort(surface_gap)[::-1]
        nearest[i[order]] = surface_gap[order]
        nearest[j[order]] = np.minimum(nearest[j[order]], surface_gap[order])
        nearest[i[order]] = np.minimum(nearest[i[order]], surface_gap[order])
        reachable = (surface_gap > 0.0) & (surface_gap < packing.CLUSTERING_REACH)
        pull_i = (surface_gap == nearest[i]) & reachable
        pull_j = (surface_gap == nearest[j]) & reachable
        weight = clustering / n
        energy += weight * float(np.sum(np.where(pull_i, surface_gap, 0.0) ** 2))
        energy += weight * float(np.sum(np.where(pull_j, surface_gap, 0.0) ** 2))
        coef = coef + 2.0 * weight * surface_gap * (pull_i.astype(float) + pull_j.astype(float)) / dist
    force = coef[:, None] * delta
    grad = np.empty_like(xy)
    for axis in (0, 1):
        grad[:, axis] = np.bincount(i, force[:, axis], n) - np.bincount(j, force[:, axis], n)
    return energy, grad.ravel()


@pytest.mark.parametrize("clustering", [0.0, 0.05])
def test_compiled_energy_gives_the_bits_of_the_array_expressions(clustering):
    rng = np.random.default_rng(8)
    for n in (2, 30, 400):
        radii = rng.uniform(0.2, 2.0, n)
        xy = rng.uniform(0.0, 2.0 * np.sqrt(n), (n, 2))
        xy[1] = xy[0]  # two circles on the same spot (the coincident branch)
        pairs = np.array([(a, b) for a in range(n) for b in range(a + 1, n)])
        middle = np.array([np.sqrt(n), np.sqrt(n)])
        expected = energy_by_array_expressions(xy.ravel(), radii, pairs, 0.01, clustering, middle)
        energy, grad = packing._energy(xy.ravel(), radii, pairs, 0.01, clustering, middle)
        assert energy == expected[0]
        np.testing.assert_array_equal(grad, expected[1])


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
