"""GeoParquet round trip, GeoJSON export and corrupt-file errors for floe fields."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pyarrow.parquet as pq
import pytest
import shapely

from floebreak.errors import InputError
from floebreak.ice.generation import generate_field
from floebreak.ice.observations import get_observation
from floebreak.io.field_files import DOMAIN_RULE, FieldFileWarning, export_geojson, load_field, save_field


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


def _without_floebreak_metadata(path, out):
    """The file as another tool (e.g. geopandas) writes it back: the `geo` metadata, no `floebreak` key."""
    table = pq.read_table(path)
    metadata = {k: v for k, v in table.schema.metadata.items() if k != b"floebreak"}
    pq.write_table(table.replace_schema_metadata(metadata), out)
    return out


def test_a_file_without_domain_metadata_warns_and_takes_the_floes_bounds(tmp_path, floe_field):
    path = _without_floebreak_metadata(save_field(floe_field, tmp_path / "f.parquet"), tmp_path / "g.parquet")
    with pytest.warns(FieldFileWarning, match="no floebreak domain metadata"):
        loaded = load_field(path)
    bounds = shapely.total_bounds(floe_field.polygons)
    assert loaded.domain_m == tuple(bounds)
    assert loaded.domain_m != floe_field.domain_m  # the generated domain is larger than the floes' box
    assert loaded.metadata["domain_rule"] == DOMAIN_RULE


def test_a_file_floebreak_wrote_loads_without_warning(tmp_path, floe_field):
    path = save_field(floe_field, tmp_path / "f.parquet")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert "domain_rule" not in load_field(path).metadata
