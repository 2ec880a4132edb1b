"""Circle placement (floebreak.ice.packing): the dense corner-insertion fallback against known packings."""

from __future__ import annotations

import numpy as np

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
