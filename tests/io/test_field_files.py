"""GeoParquet round trip, GeoJSON export and corrupt-file errors for floe fields."""

from __future__ import annotations

import json

import numpy as np
import pyarrow.parquet as pq
import pytest
import shapely

from floebreak.errors import InputError
from floebreak.ice.generation import generate_field
from floebreak.ice.observations import get_observation
from floebreak.io.field_files import export_geojson, load_field, save_field


@pytest.fixture(scope="module")
def floe_field():
    obs = get_observation("2019-12-18T20:20")
    return generate_field(obs, 120.0, 50.0, np.random.default_rng(4), thickness_range_m=(0.75, 1.25), seed=4)


def test_geoparquet_round_trip_is_exact(tmp_path, floe_field):
    path = save_field(floe_field, tmp_path / "field.parquet")
    loaded = load_field(path)
    assert all(shapely.equals_exact(loaded.polygons, floe_field.polygons, tolerance=0.0))
    np.testing.assert_array_equal(loaded.thickness_m, floe_field.thickness_m)
    np.testing.assert_array_equal(loaded.floe_id, floe_field.floe_id)
    np.testing.assert_array_equal(loaded.diameter_class_m, floe_field.diameter_class_m)
    assert loaded.domain_m == floe_field.domain_m
    assert loaded.metadata["seed"] == 4
    geo = json.loads(pq.read_schema(path).metadata[b"geo"])
    assert geo["columns"]["geometry"]["crs"] is None
    assert list(tmp_path.iterdir()) == [path]  # no temporary file left behind


def test_geojson_has_one_feature_per_floe(tmp_path, floe_field):
    path = export_geojson(floe_field, tmp_path / "field.geojson")
    data = json.loads(path.read_text())
    assert len(data["features"]) == floe_field.n_floes


def test_corrupt_file_is_an_input_error(tmp_path):
    bad = tmp_path / "bad.parquet"
    bad.write_bytes(b"not a parquet file")
    with pytest.raises(InputError):
        load_field(bad)


def test_unwritable_output_leaves_nothing(tmp_path, floe_field):
    with pytest.raises(InputError):
        save_field(floe_field, tmp_path / "missing-dir" / "field.parquet")
    assert list(tmp_path.iterdir()) == []
