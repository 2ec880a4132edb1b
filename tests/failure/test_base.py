"""failure.base helpers: the polygon parts of an overlay result."""

from __future__ import annotations

import shapely

from floebreak.failure.base import polygon_parts


def test_polygon_parts_keeps_only_polygons_with_area():
    square = shapely.box(0.0, 0.0, 1.0, 1.0)
    other = shapely.box(2.0, 0.0, 3.0, 2.0)
    assert [p.area for p in polygon_parts(square)] == [1.0]
    assert [p.area for p in polygon_parts(shapely.MultiPolygon([square, other]))] == [1.0, 2.0]
    mixed = shapely.GeometryCollection([shapely.LineString([(0, 0), (1, 1)]), other, shapely.Point(5, 5)])
    assert [p.area for p in polygon_parts(mixed)] == [2.0]
    assert polygon_parts(shapely.Polygon()) == []
    assert polygon_parts(shapely.Polygon([(0, 0), (1, 1), (2, 2)])) == []  # degenerate: no area
    assert polygon_parts(shapely.intersection(square, other)) == []
