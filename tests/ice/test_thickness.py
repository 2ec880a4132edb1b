"""Bounded random thickness (thesis §5.3.3, erratum 6)."""

import numpy as np
import pytest

from floebreak.errors import InputError
from floebreak.ice.thickness import bounded_random_thickness_m


def test_bates_moments_and_bounds():
    rng = np.random.default_rng(1)
    h = bounded_random_thickness_m(rng, 0.75, 1.25, size=20_000, summands=12)
    assert h.min() >= 0.75 and h.max() <= 1.25
    assert h.mean() == pytest.approx(1.0, abs=0.002)
    assert h.std() == pytest.approx(0.5 / np.sqrt(12 * 12), rel=0.03)  # Bates std = range / √(12 p)


def test_thesis_spread_implies_1180_summands():
    # thesis §5.3.3 reports σ = 0.0042 m over [0.75, 1.25] m → p_h ≈ 1180 (physics-notes erratum 6)
    h = bounded_random_thickness_m(np.random.default_rng(2), 0.75, 1.25, size=4000, summands=1180)
    assert h.std() == pytest.approx(0.0042, rel=0.06)


def test_thesis_literal_sum_is_biased_upwards():
    rng = np.random.default_rng(3)
    h = bounded_random_thickness_m(rng, 0.75, 1.25, size=4000, summands=4, thesis_sum_from_zero=True)
    # p+1 uniforms divided by p: mean fraction (p+1)/(2p) = 5/8 → mean 0.75 + 0.5·0.625
    assert h.mean() == pytest.approx(0.75 + 0.5 * 5 / 8, abs=0.01)


def test_same_seed_same_values():
    a = bounded_random_thickness_m(np.random.default_rng(7), 0.8, 1.2, size=5)
    b = bounded_random_thickness_m(np.random.default_rng(7), 0.8, 1.2, size=5)
    np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize(
    ("lo", "hi", "field"), [(0.0, 1.0, "thickness_min_m"), (1.2, 0.8, "thickness_range_m")]
)
def test_bad_ranges(lo, hi, field):
    with pytest.raises(InputError, match=field):
        bounded_random_thickness_m(np.random.default_rng(0), lo, hi, size=3)
