"""Hypothesis strategies for floebreak's data, for its own tests and for users' (needs `hypothesis`, part of
the ``dev`` and ``testing`` extras).

Floe outlines (`floe_polygons`: star-shaped concave polygons, circles, rotated boxes — all valid), points
near an outline (`points_near`) and ice observations in Table 1's format (`observations`). Coordinates are
metres; every strategy draws only valid input, so a failing property is floebreak's, not the strategy's.

    from hypothesis import given
    from floebreak.testing import floe_polygons

    @given(floe_polygons())
    def test_area_is_positive(polygon):
        assert polygon.area > 0
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from hypothesis import strategies as st

from floebreak.ice.observations import Observation

coordinates_m = st.floats(-60.0, 60.0, allow_nan=False)
angles_rad = st.floats(0.0, 2.0 * math.pi, allow_nan=False, exclude_max=True)


@st.composite
def star_polygons(draw, max_vertices: int = 40) -> shapely.Polygon:
    """Star-shaped (generally concave) polygons about a random centre: simple by construction."""
    n = draw(st.integers(3, max_vertices))
    angles = np.sort(np.array(draw(st.lists(angles_rad, min_size=n, max_size=n, unique=True))))
    gaps = np.diff(np.concatenate([angles, [angles[0] + 2.0 * math.pi]]))
    if gaps.min() < 1e-3 or gaps.max() > math.pi - 1e-3:  # near-duplicate rays or a non-star outline
        angles = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False) + angles[0]
    radii = np.array(draw(st.lists(st.floats(0.5, 25.0), min_size=n, max_size=n)))
    centre = np.array([draw(coordinates_m), draw(coordinates_m)])
    ring = centre + radii[:, None] * np.stack([np.cos(angles), np.sin(angles)], axis=1)
    return shapely.Polygon(ring)


@st.composite
def circle_polygons(draw) -> shapely.Polygon:
    """Circles of radius 0.5–30 m as polygons of 8–128 vertices."""
    centre = (draw(coordinates_m), draw(coordinates_m))
    return shapely.Point(centre).buffer(draw(st.floats(0.5, 30.0)), quad_segs=draw(st.integers(2, 32)))


@st.composite
def box_polygons(draw) -> shapely.Polygon:
    """Rectangles of sides 0.5–40 m, rotated about their centroid."""
    x0, y0 = draw(coordinates_m), draw(coordinates_m)
    box = shapely.box(x0, y0, x0 + draw(st.floats(0.5, 40.0)), y0 + draw(st.floats(0.5, 40.0)))
    return shapely.affinity.rotate(box, draw(st.floats(0.0, 180.0)), origin="centroid")


def floe_polygons() -> st.SearchStrategy[shapely.Polygon]:
    """Valid floe outlines: star-shaped, circular or rectangular."""
    return st.one_of(star_polygons(), circle_polygons(), box_polygons())


@st.composite
def points_near(draw, polygon: shapely.Polygon, spread: float = 1.2) -> np.ndarray:
    """A point (x, y) in the polygon's bounding box enlarged by `spread` (mostly inside, sometimes not)."""
    x0, y0, x1, y1 = polygon.bounds
    cx, cy, hx, hy = (x0 + x1) / 2, (y0 + y1) / 2, spread * (x1 - x0) / 2, spread * (y1 - y0) / 2
    return np.array([draw(st.floats(cx - hx, cx + hx)), draw(st.floats(cy - hy, cy + hy))])


@st.composite
def observations(draw, diameters_m: tuple[float, float, float] = (2.5, 5.0, 10.0)) -> Observation:
    """Ice observations like thesis Table 1's rows: concentration 5–70 %, mean thickness 0.5 m, three
    diameter classes with random shares (in %, summing to 100)."""
    shares = draw(st.lists(st.integers(0, 10), min_size=3, max_size=3).filter(lambda s: sum(s) > 0))
    percentages = tuple(100.0 * s / sum(shares) for s in shares)
    return Observation(draw(st.floats(0.05, 0.7)), 0.5, diameters_m, percentages)
