"""floebreak.testing: the shipped strategies draw only valid input."""

from __future__ import annotations

import math

import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from floebreak.testing import floe_polygons, observations, points_near


@settings(max_examples=60, deadline=None, derandomize=True)
@given(floe_polygons())
def test_floe_polygons_are_valid_polygons(polygon):
    assert shapely.get_type_id(polygon) == 3 and polygon.is_valid and polygon.area > 0


@settings(max_examples=30, deadline=None, derandomize=True)
@given(st.data(), floe_polygons())
def test_points_near_lie_in_the_enlarged_bounding_box(data, polygon):
    x, y = data.draw(points_near(polygon, spread=1.0))
    x0, y0, x1, y1 = polygon.bounds
    slack = 1e-12 * (1.0 + max(map(abs, polygon.bounds)))  # centre ± half-width rounds
    assert x0 - slack <= x <= x1 + slack and y0 - slack <= y <= y1 + slack


@settings(max_examples=30, deadline=None, derandomize=True)
@given(observations())
def test_observations_have_shares_summing_to_100_percent(obs):
    assert math.isclose(sum(obs.percentages), 100.0) and 0.05 <= obs.concentration <= 0.7
