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
from floebreak.output.field_files import DOMAIN_RULE, FieldFileWarning, export_geojson, load_field, save_field


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


# --- field files validated like inline floes ------------------------------------------
def _write_field_file(
    path, columns, *, polygons=None, domain_m=(0.0, -20.0, 100.0, 20.0), crs=None, drop_crs=False
):
    """A GeoParquet field file built with pyarrow and shapely alone (not floebreak's writer), as another
    tool would write it: two 10 m squares apart unless `polygons` are given."""
    import pyarrow as pa

    if polygons is None:
        polygons = [shapely.box(20, -5, 30, 5), shapely.box(40, -5, 50, 5)]
    column = {"encoding": "WKB", "geometry_types": ["Polygon"], "crs": crs, "edges": "planar"}
    if drop_crs:
        del column["crs"]
    geo = {"version": "1.1.0", "primary_column": "geometry", "columns": {"geometry": column}}
    metadata = {b"geo": json.dumps(geo).encode()}
    if domain_m is not None:
        metadata[b"floebreak"] = json.dumps({"domain_m": domain_m}).encode()
    wkb = [shapely.to_wkb(p) for p in polygons]
    table = pa.table({"geometry": pa.array(wkb, pa.binary()), **columns})
    pq.write_table(table.replace_schema_metadata(metadata), path)
    return path


TWO = {"floe_id": [0, 1], "thickness_m": [1.0, 1.0]}
BAD_FILES = [
    # (what, columns, options, the message's place, the message's fragment)
    ("duplicate floe_id", {**TWO, "floe_id": [4, 4]}, {}, "row 2, column 'floe_id'", "4 repeats row 1"),
    (
        "floe_id as strings",
        {**TWO, "floe_id": ["a", "b"]},
        {},
        "row 1, column 'floe_id'",
        "'a' is not an integer",
    ),
    ("float floe_id", {**TWO, "floe_id": [0.0, 1.5]}, {}, "row 2, column 'floe_id'", "1.5 is not an integer"),
    (
        "thickness as strings",
        {**TWO, "thickness_m": ["thick", "1"]},
        {},
        "row 1, column 'thickness_m'",
        "'thick' is not a number",
    ),
    (
        "numeric strings",
        {**TWO, "thickness_m": ["1.0", "1.0"]},
        {},
        "row 1, column 'thickness_m'",
        "'1.0' is not a number",
    ),
    ("zero thickness", {**TWO, "thickness_m": [1.0, 0.0]}, {}, "row 2, column 'thickness_m'", "0.0"),
    ("null thickness", {**TWO, "thickness_m": [1.0, None]}, {}, "row 2, column 'thickness_m'", "nan"),
    ("domain_m text", TWO, {"domain_m": "abc"}, "metadata 'domain_m'", "'abc'"),
    ("domain_m NaN", TWO, {"domain_m": [0, 0, float("nan"), 1]}, "metadata 'domain_m'", "nan"),
    ("domain_m of 3", TWO, {"domain_m": [0, 0, 1]}, "metadata 'domain_m'", "[0, 0, 1]"),
    ("inverted domain_m", TWO, {"domain_m": [100, 20, 0, -20]}, "metadata 'domain_m'", "inverted"),
    ("geographic CRS", TWO, {"crs": "OGC:CRS84"}, "column 'geometry' (crs)", "'OGC:CRS84'"),
    (
        "projected CRS",
        TWO,
        {"crs": {"type": "ProjectedCRS", "name": "WGS 84 / UTM zone 33N"}},
        "(crs)",
        "UTM",
    ),
    ("no crs key (GeoParquet: CRS84)", TWO, {"drop_crs": True}, "(crs)", "OGC:CRS84"),
    (
        "overlapping polygons",
        TWO,
        {"polygons": [shapely.box(20, -5, 30, 5), shapely.box(29, -5, 39, 5)]},
        "row 2, column 'geometry'",
        "overlaps row 1",
    ),
]


@pytest.mark.parametrize(
    ("what", "columns", "options", "place", "fragment"), BAD_FILES, ids=[b[0] for b in BAD_FILES]
)
def test_a_bad_field_file_is_an_input_error_naming_file_row_and_column(
    tmp_path, what, columns, options, place, fragment
):
    path = _write_field_file(tmp_path / "f.parquet", columns, **options)
    with pytest.raises(InputError) as caught:
        load_field(path, field="field.file")
    message = str(caught.value)
    assert message.startswith(f"field.file: {str(path)!r}"), message
    assert place in message and fragment in message, message


def test_an_empty_field_file_is_an_input_error(tmp_path):
    path = _write_field_file(tmp_path / "f.parquet", {"floe_id": [], "thickness_m": []}, polygons=[])
    with pytest.raises(InputError, match="has no rows"):
        load_field(path)


def test_integral_float_ids_touching_floes_and_a_local_metre_crs_are_accepted(tmp_path):
    local = {
        "type": "EngineeringCRS",
        "name": "ship frame",
        "coordinate_system": {
            "subtype": "Cartesian",
            "axis": [
                {"name": "x", "direction": "east", "unit": "metre"},
                {"name": "y", "direction": "north", "unit": "metre"},
            ],
        },
    }
    touching = [shapely.box(20, -5, 30, 5), shapely.box(30, -5, 40, 5)]  # a shared edge: no area in common
    columns = {"floe_id": [3.0, 7.0], "thickness_m": [1, 2]}  # integer thickness is a number too
    path = _write_field_file(tmp_path / "f.parquet", columns, polygons=touching, crs=local)
    loaded = load_field(path)
    np.testing.assert_array_equal(loaded.floe_id, [3, 7])
    np.testing.assert_array_equal(loaded.thickness_m, [1.0, 2.0])
    assert loaded.domain_m == (0.0, -20.0, 100.0, 20.0)


def test_a_local_crs_in_feet_is_refused(tmp_path):
    feet = {"type": "EngineeringCRS", "coordinate_system": {"axis": [{"name": "x", "unit": "foot"}]}}
    path = _write_field_file(tmp_path / "f.parquet", TWO, crs=feet)
    with pytest.raises(InputError, match="crs"):
        load_field(path)
