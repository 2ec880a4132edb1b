"""The engaged interval of a blade in a cusp's cross-section (`floebreak.propeller.engagement`): hand cases
and a brute-force sweep over the shaft angle."""

from __future__ import annotations

import math

import numpy as np
import pytest

from floebreak.errors import InputError
from floebreak.propeller.engagement import engaged_interval

R, HUB = 2.15, 0.3 * 2.15


def _one(y_lo, y_hi, z_lo, z_hi, hub=HUB, tip=R):
    r_in, r_out = engaged_interval([y_lo], [y_hi], [z_lo], [z_hi], hub, tip)
    return float(r_in[0]), float(r_out[0])


def _brute(y_lo, y_hi, z_lo, z_hi, hub, tip, n=20_000):
    """Longest blade segment over n shaft angles, sampled (independent of the candidate set)."""
    theta = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    uy, uz = np.sin(theta), np.cos(theta)
    t_lo = np.full(n, hub)
    t_hi = np.full(n, tip)
    for lo, hi, u in ((y_lo, y_hi, uy), (z_lo, z_hi, uz)):
        with np.errstate(divide="ignore", invalid="ignore"):
            a, b = lo / u, hi / u
        enter = np.where(u > 0, a, np.where(u < 0, b, np.where(lo <= 0 <= hi, -np.inf, np.inf)))
        leave = np.where(u > 0, b, np.where(u < 0, a, np.where(lo <= 0 <= hi, np.inf, -np.inf)))
        t_lo, t_hi = np.maximum(t_lo, enter), np.minimum(t_hi, leave)
    length = t_hi - t_lo
    return float(length.max()) if np.any(length >= 0) else math.nan


def test_a_rectangle_over_the_top_of_the_disc_engages_from_the_tip_down_by_its_depth():
    # the blade pointing up (z up negative: z from −2.5 to −1.3 covers radii 1.3 … 2.15 straight up)
    r_in, r_out = _one(-1.0, 1.0, -2.5, -1.3)
    assert r_out == pytest.approx(R, abs=1e-12)
    assert r_in == pytest.approx(1.3, abs=1e-12)


def test_a_shallow_rectangle_at_the_top_engages_its_depth_below_the_tip():
    # top face above the tip, bottom 0.4 m below it: [R − 0.4, R]
    r_in, r_out = _one(-0.5, 0.5, -3.0, -(R - 0.4))
    assert (r_in, r_out) == pytest.approx((R - 0.4, R), abs=1e-12)


def test_a_rectangle_deep_inside_the_disc_engages_along_the_ray_through_its_far_corner():
    # y ∈ [−0.2, 0.2], z ∈ [−1.2, −0.8] (0.8–1.2 m above the axis): straight up the blade cuts 0.4 m; a ray
    # tilted towards the corner (0.2, −1.2) enters the near face z = −0.8 at t = 0.8 / cos θ and leaves at
    # the corner, t = √(0.2² + 1.2²): length √1.48 / 3 = 0.4055 m. Tilted less it leaves through the far
    # face (0.4 / cos θ, growing with θ), more through the side (0.2/sin θ − 0.8/cos θ, falling): the corner
    theta = math.atan2(0.2, 1.2)
    expected = (0.8 / math.cos(theta), math.hypot(0.2, 1.2))
    assert _one(-0.2, 0.2, -1.2, -0.8) == pytest.approx(expected, abs=1e-12)
    assert expected[1] - expected[0] == pytest.approx(math.sqrt(1.48) / 3.0, abs=1e-12)


def test_the_hub_cuts_off_a_rectangle_around_the_axis():
    # a rectangle around the shaft axis reaching 1.0 m up: the blade from the hub to the farthest corner
    r_in, r_out = _one(-0.3, 0.3, -1.0, 0.2)
    assert r_in == pytest.approx(HUB, abs=1e-12)
    assert r_out == pytest.approx(math.hypot(0.3, 1.0), abs=1e-12)


def test_a_rectangle_beside_the_disc_does_not_engage():
    r_in, r_out = _one(R + 0.01, R + 1.0, -0.5, 0.5)
    assert math.isnan(r_in) and math.isnan(r_out)


def test_a_rectangle_inside_the_hub_does_not_engage():
    r_in, r_out = _one(-0.1, 0.1, -0.1, 0.1)
    assert math.isnan(r_in) and math.isnan(r_out)


def test_a_rectangle_touching_the_tip_circle_engages_with_zero_length():
    r_in, r_out = _one(-0.5, 0.5, -3.0, -R)
    assert r_in == pytest.approx(R, abs=1e-12) and r_out == pytest.approx(R, abs=1e-12)


def test_nan_rectangles_give_nan():
    r_in, r_out = engaged_interval([np.nan, -1.0], [np.nan, 1.0], [np.nan, -3.0], [np.nan, -1.5], HUB, R)
    assert np.isnan(r_in[0]) and np.isnan(r_out[0])
    assert (r_in[1], r_out[1]) == pytest.approx((1.5, R), abs=1e-12)


def test_mirroring_y_gives_the_same_interval():
    rng = np.random.default_rng(7)
    y = rng.uniform(-3.0, 3.0, (200, 2))
    z = rng.uniform(-3.0, 3.0, (200, 2))
    y_lo, y_hi = y.min(axis=1), y.max(axis=1)
    z_lo, z_hi = z.min(axis=1), z.max(axis=1)
    a = engaged_interval(y_lo, y_hi, z_lo, z_hi, HUB, R)
    b = engaged_interval(-y_hi, -y_lo, z_lo, z_hi, HUB, R)
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])


def _refined(box, hub, tip, n=20_000):
    """The sampled maximum over n angles, refined by a ternary search (the length is unimodal near its
    maximum) between the best sample's neighbours."""
    theta = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    lengths = np.array([_length_at(box, hub, tip, t) for t in theta])
    if not np.any(lengths >= 0.0):
        return math.nan
    k = int(np.argmax(lengths))
    lo, hi = theta[k] - 2.0 * math.pi / n, theta[k] + 2.0 * math.pi / n
    for _ in range(200):
        a, b = lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0
        if _length_at(box, hub, tip, a) < _length_at(box, hub, tip, b):
            lo = a
        else:
            hi = b
    return max(float(lengths[k]), _length_at(box, hub, tip, 0.5 * (lo + hi)))


def _length_at(box, hub, tip, theta):
    """Length of the blade at angle theta inside the box (−inf where it misses)."""
    u = (math.sin(theta), math.cos(theta))
    t_lo, t_hi = hub, tip
    for (lo, hi), ui in zip((box[:2], box[2:]), u, strict=True):
        if ui == 0.0:
            if not lo <= 0.0 <= hi:
                return -math.inf
            continue
        a, b = sorted((lo / ui, hi / ui))
        t_lo, t_hi = max(t_lo, a), min(t_hi, b)
    return t_hi - t_lo if t_hi >= t_lo else -math.inf


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_a_brute_force_sweep_agrees_with_the_exact_length_to_1e_9(seed):
    rng = np.random.default_rng(seed)
    n = 15
    centre = rng.uniform(-2.6, 2.6, (n, 2))
    half = rng.uniform(0.02, 1.5, (n, 2))
    boxes = np.column_stack([centre[:, 0] - half[:, 0], centre[:, 0] + half[:, 0]])
    boxes = np.column_stack([boxes, centre[:, 1] - half[:, 1], centre[:, 1] + half[:, 1]])
    r_in, r_out = engaged_interval(*boxes.T, HUB, R)
    for k in range(n):
        expected = _refined(tuple(boxes[k]), HUB, R)
        if math.isnan(expected):
            assert math.isnan(r_in[k]) and math.isnan(r_out[k])
        else:
            assert r_out[k] - r_in[k] == pytest.approx(expected, abs=1e-9)
            assert HUB - 1e-12 <= r_in[k] <= r_out[k] <= R + 1e-12


def test_bad_radii_are_refused():
    with pytest.raises(InputError, match=r"engagement\.hub_radius_m"):
        engaged_interval([0.0], [1.0], [0.0], [1.0], 3.0, 2.0)
    with pytest.raises(InputError, match=r"engagement\.tip_radius_m"):
        engaged_interval([0.0], [1.0], [0.0], [1.0], 0.0, -1.0)
    with pytest.raises(InputError, match=r"engagement\.rectangle"):
        engaged_interval([1.0], [0.0], [0.0], [1.0], 0.5, 2.0)
