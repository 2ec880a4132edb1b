"""GeoParquet files: an exact round trip of geometries, columns and metadata."""

from __future__ import annotations

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
import shapely

from floebreak.errors import InputError
from floebreak.io.geoparquet import read_geoparquet, write_geoparquet


def test_round_trip_is_exact(tmp_path):
    polygons = np.array([shapely.box(0.1, 0.2, 1.0 / 3.0, 2.0), shapely.Point(0, 0).buffer(np.pi)])
    columns = {
        "area_m2": shapely.area(polygons),
        "fate": np.array(["cusp", "flipped"], dtype=object),
        "created_step": np.array([-1, 7]),
        "ok": np.array([True, False]),
    }
    path = write_geoparquet(tmp_path / "t.parquet", polygons, columns, {"seed": np.int64(3)})
    geometries, read, meta = read_geoparquet(path)
    assert all(shapely.equals_exact(a, b, tolerance=0.0) for a, b in zip(geometries, polygons, strict=True))
    assert read["area_m2"].tolist() == columns["area_m2"].tolist()
    assert read["fate"].tolist() == ["cusp", "flipped"] and read["ok"].tolist() == [True, False]
    assert read["created_step"].dtype == np.int64 and meta == {"seed": 3}
    schema = pq.read_schema(path)
    assert schema.field("geometry").type == pa.binary() and schema.field("fate").type == pa.string()


def test_an_empty_table_round_trips(tmp_path):
    path = write_geoparquet(tmp_path / "e.parquet", np.array([], dtype=object), {"area_m2": np.zeros(0)}, {})
    geometries, columns, _ = read_geoparquet(path)
    assert len(geometries) == 0 and len(columns["area_m2"]) == 0


def test_a_file_that_is_not_geoparquet_is_refused_naming_the_field(tmp_path):
    path = tmp_path / "plain.parquet"
    pq.write_table(pa.table({"x": [1.0]}), path)
    with pytest.raises(InputError, match=r"field\.file"):
        read_geoparquet(path, field="field.file")
