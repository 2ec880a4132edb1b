"""GeoParquet files: an exact round trip of geometries, columns and metadata; GeoParquet 1.1 metadata;
Arrow columns built from buffers equal to what ``pa.array`` gives."""

from __future__ import annotations

import json

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
import shapely

from floebreak.errors import InputError
from floebreak.io.geoparquet import arrow_array, read_geoparquet, write_geoparquet


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


def _geo(path) -> dict:
    return json.loads(pq.read_schema(path).metadata[b"geo"])["columns"]["geometry"]


def test_geo_metadata_follows_geoparquet_1_1(tmp_path):
    polygons = np.array([shapely.box(-1.0, 0.5, 2.0, 3.0), shapely.MultiPolygon([shapely.box(4, 4, 5, 6)])])
    path = write_geoparquet(tmp_path / "t.parquet", polygons, {"area_m2": shapely.area(polygons)}, {})
    column = _geo(path)
    assert column["encoding"] == "WKB" and column["crs"] is None and column["edges"] == "planar"
    assert column["geometry_types"] == ["MultiPolygon", "Polygon"]
    assert column["bbox"] == [-1.0, 0.5, 5.0, 6.0]  # [xmin, ymin, xmax, ymax] of both polygons


@pytest.mark.parametrize(
    ("geometry", "types"),
    [
        (shapely.Point(1, 2), ["Point"]),
        (shapely.LineString([(0, 0), (1, 1)]), ["LineString"]),
        (shapely.LinearRing([(0, 0), (1, 0), (1, 1)]), []),  # no GeoParquet name: "any type"
    ],
)
def test_geometry_types_are_geoparquet_names_or_empty(tmp_path, geometry, types):
    path = write_geoparquet(tmp_path / "t.parquet", np.array([geometry]), {}, {})
    assert _geo(path)["geometry_types"] == types


def test_an_empty_table_has_no_types_and_no_bbox(tmp_path):
    path = write_geoparquet(tmp_path / "t.parquet", np.array([], dtype=object), {"area_m2": np.zeros(0)}, {})
    column = _geo(path)
    assert column["geometry_types"] == [] and "bbox" not in column


def test_units_are_arrow_field_metadata(tmp_path):
    columns = {"area_m2": np.ones(1), "f_c_n": np.ones(1), "psi_deg": np.ones(1), "step": np.arange(1)}
    path = write_geoparquet(tmp_path / "t.parquet", np.array([shapely.box(0, 0, 1, 1)]), columns, {})
    schema = pq.read_schema(path)
    units = {name: (schema.field(name).metadata or {}).get(b"unit") for name in columns}
    assert units == {"area_m2": b"m2", "f_c_n": b"N", "psi_deg": b"deg", "step": None}


COLUMNS = [
    np.arange(7, dtype=np.int64),
    np.array([0.5, np.nan, -0.0, np.inf, 1e300]),
    np.arange(10, dtype=np.int32)[::3],  # not contiguous
    np.array([True, False, True, True, False, False, False, False, True, True]),
    np.zeros(0),
    np.zeros(0, dtype=bool),
    np.array(["cusp", "flipped", "", "bending>cracking", "ü"], dtype=object),
    ["remaining", "cusp"],
    [],  # pa.array([]) is of type null
    np.array([], dtype=object),
    ["a", None],  # nulls: left to pa.array
    [1, 2],  # not str: left to pa.array
]


@pytest.mark.parametrize("values", COLUMNS, ids=range(len(COLUMNS)))
def test_arrow_array_is_what_pa_array_gives(values):
    built, expected = arrow_array(values), pa.array(values)
    assert built.type == expected.type
    assert built.null_count == expected.null_count
    assert repr(built.to_pylist()) == repr(expected.to_pylist())  # repr: NaN == NaN, -0.0 kept


@pytest.mark.parametrize("values", [[b"\x01\x03", b"", b"wkb"], []])
def test_arrow_array_binary(values):
    assert arrow_array(values, binary=True).equals(pa.array(values, type=pa.binary()))


def test_big_endian_numbers_are_left_to_pa_array():
    with pytest.raises(pa.ArrowNotImplementedError):  # as pa.array: "Byte-swapped arrays not supported"
        arrow_array(np.arange(4.0).astype(">f8"))
