"""Floe-field generation (thesis §2.1, errata 1–5): counts, concentration, no overlap, bounds, seeds."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from floebreak.errors import InputError
from floebreak.ice.generation import ConcentrationError, floe_counts, generate_field, largest_remainder
from floebreak.ice.observations import Observation, get_observation, thesis_observations
from floebreak.testing import observations

# Circles reach every Table 1 row; the 89 % one (7.5/15/60 m) needs the corner-insertion fallback.
CIRCLE_ROWS = list(thesis_observations())


def field_size_m(observation: Observation) -> tuple[float, float]:
    """A field large enough for a few of the largest floes (L = 2 W, W = 4 d_max, at least 50 m)."""
    width = max(50.0, 4.0 * observation.largest_diameter_m)
    if observation.concentration < 0.3 or 300.0 in observation.diameter_classes_m:
        width *= 2.0  # few floes per class otherwise: the rounding of whole floes would dominate
    return 2.0 * width, width


def assert_valid_field(floe_field, observation):
    polygons = floe_field.polygons
    x0, y0, x1, y1 = floe_field.domain_m
    bounds = shapely.bounds(polygons)
    assert np.all(bounds[:, 0] >= x0) and np.all(bounds[:, 1] >= y0)
    assert np.all(bounds[:, 2] <= x1) and np.all(bounds[:, 3] <= y1)
    tree = shapely.STRtree(polygons)
    pairs = tree.query(polygons, predicate="intersects")
    assert np.all(pairs[0] == pairs[1]), "two floes touch or overlap"
    assert abs(floe_field.concentration - observation.concentration) <= 0.01


def test_largest_remainder_sums_to_total_and_is_proportional():
    counts = largest_remainder(np.array([0.2, 0.4, 0.4]), 17)
    assert counts.sum() == 17
    assert np.all(np.abs(counts - np.array([3.4, 6.8, 6.8])) < 1.0)


def test_floe_counts_follow_the_corrected_thesis_formula():
    obs = get_observation("2019-12-18T20:20")
    area = 400.0 * 50.0
    counts = floe_counts(obs, area)
    # independent: Ā = Σ p π d²/4 = π/4 (0.2·2.5² + 0.4·7.5² + 0.4·15²) = 70.2 m²; m = ⌈0.44 · 20000 / Ā⌉
    mean_area = np.pi / 4 * (0.2 * 2.5**2 + 0.4 * 7.5**2 + 0.4 * 15.0**2)
    m = int(np.ceil(0.44 * area / mean_area))
    assert abs(counts.total - m) <= 3
    assert abs(counts.circle_concentration - 0.44) < 0.01
    # thesis-literal area factor 1/2 (erratum 1) halves the count and the concentration
    thesis = floe_counts(obs, area, floe_area_factor=0.5)
    assert thesis.total == pytest.approx(counts.total / 2, abs=3)
    assert thesis.circle_concentration == pytest.approx(0.22, abs=0.01)


@pytest.mark.parametrize("key", CIRCLE_ROWS)
def test_every_table1_row_with_circles(key):
    obs = get_observation(key)
    length, width = field_size_m(obs)
    floe_field = generate_field(obs, length, width, np.random.default_rng(3))
    assert_valid_field(floe_field, obs)
    counts = floe_counts(obs, length * width)
    for diameter, count in zip(counts.diameter_classes_m, counts.counts, strict=True):
        assert np.sum(floe_field.diameter_class_m == diameter) == count


@pytest.mark.parametrize("key", list(thesis_observations()))
def test_every_table1_row_with_voronoi(key):
    obs = get_observation(key)
    length, width = field_size_m(obs)
    floe_field = generate_field(obs, length, width, np.random.default_rng(3), generator="voronoi")
    assert_valid_field(floe_field, obs)


def test_dense_row_is_placed_by_corner_insertion():
    obs = get_observation("2019-12-18T22:30")  # 89 %: 31 floes of 60 m alone cover 76 % of 480 m × 240 m
    floe_field = generate_field(obs, 480.0, 240.0, np.random.default_rng(0))
    assert floe_field.metadata["placement"] == "corner"
    assert_valid_field(floe_field, obs)


def test_unreachable_concentration_reports_the_concentration_reached():
    # 93 % with the 89 % row's classes: 60 m floes alone would cover 80 %, four across a 240 m wide field
    obs = Observation(0.93, 0.8, (7.5, 15.0, 60.0), (40.0, 40.0, 20.0))
    with pytest.raises(ConcentrationError) as info:
        generate_field(obs, 480.0, 240.0, np.random.default_rng(0))
    # the user's number, not the cover of the rounded floe counts: 65, 65, 33 floes of 7.5, 15, 60 m cover
    # π/4 (65·7.5² + 65·15² + 33·60²) / (480·240) = 93.5 %
    assert str(info.value).startswith(
        "concentration: 0.93 (93 %) not reached by 'circles' in this 480 m × 240 m field: highest "
        "concentration reached "
    )
    assert "93.5" not in str(info.value)
    assert 0.3 < info.value.reached < obs.concentration
    reached = f"{100 * info.value.reached:.2f} %, the cover of the floes it placed without overlap"
    assert reached in str(info.value)


@pytest.mark.parametrize("generator", ["circles", "sqp"])
def test_full_cover_by_circles_is_refused_before_placing(generator):
    # circles always leave gaps: 100 % cannot be reached, whatever the field (Thue: equal circles ≤ π/√12)
    obs = Observation(1.0, 0.8, (5.0, 20.0), (60.0, 40.0))
    with pytest.raises(InputError) as info:
        generate_field(obs, 100.0, 50.0, np.random.default_rng(0), generator=generator)
    assert info.value.field == "concentration"
    assert str(info.value).startswith(f"concentration: 1 (100 %) cannot be reached by {generator!r}: ")
    assert "90.7 %" in str(info.value) and "voronoi" in str(info.value)
    field = generate_field(obs, 100.0, 50.0, np.random.default_rng(0), generator="voronoi")
    assert field.concentration == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize(
    ("key", "length_m", "width_m"), [("2019-12-18T20:20", 200.0, 50.0), ("2019-12-18T22:30", 480.0, 240.0)]
)
def test_same_seed_same_field_different_seed_different_field(key, length_m, width_m):
    obs = get_observation(key)
    a = generate_field(obs, length_m, width_m, np.random.default_rng(7))
    b = generate_field(obs, length_m, width_m, np.random.default_rng(7))
    c = generate_field(obs, length_m, width_m, np.random.default_rng(8))
    assert all(shapely.equals_exact(a.polygons, b.polygons, tolerance=0.0))
    assert not all(shapely.equals_exact(a.polygons, c.polygons, tolerance=1e-6))


def test_sqp_reference_gives_a_valid_small_field():
    obs = get_observation("2019-12-18T20:20")
    floe_field = generate_field(obs, 100.0, 50.0, np.random.default_rng(1), generator="sqp")
    assert_valid_field(floe_field, obs)


def test_thickness_options():
    obs = get_observation("2019-12-18T20:20")
    rng = np.random.default_rng(2)
    assert np.all(generate_field(obs, 100.0, 50.0, rng).thickness_m == obs.mean_thickness_m)
    assert np.all(generate_field(obs, 100.0, 50.0, rng, thickness_m=1.0).thickness_m == 1.0)
    h = generate_field(obs, 100.0, 50.0, rng, thickness_range_m=(0.75, 1.25)).thickness_m
    assert np.all((h >= 0.75) & (h <= 1.25)) and np.ptp(h) > 0.0


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"length_m": 400.0, "width_m": 10.0}, "width_m"),  # narrower than the 15 m floes
        ({"length_m": -1.0}, "length_m"),
        ({"generator": "hexagons"}, "generator"),
        ({"thickness_m": 0.0}, "thickness_m"),
    ],
)
def test_bad_input_names_the_field(kwargs, field):
    args = {"length_m": 200.0, "width_m": 50.0, **kwargs}
    with pytest.raises(InputError) as info:
        generate_field(get_observation("2019-12-18T20:20"), rng=np.random.default_rng(0), **args)
    assert info.value.field == field


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(obs=observations(), seed=st.integers(0, 2**16))
def test_random_valid_observations_give_valid_fields(obs, seed):
    try:
        floe_field = generate_field(obs, 120.0, 60.0, np.random.default_rng(seed))
    except InputError as error:  # only the documented refusal: too few floes to represent c within 1 pp
        assert error.field in ("length_m", "concentration")
        return
    assert_valid_field(floe_field, obs)
