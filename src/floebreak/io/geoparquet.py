"""GeoParquet 1.1 read/write with pyarrow + shapely WKB.

Coordinates are metres in the ship frame, not a geographic CRS, hence ``"crs": null``. The ``geo`` metadata
names the geometry types present (an empty list where a type has no GeoParquet name, which the
specification reads as "any type") and the file's bounding box (``bbox``, omitted for an empty table). Each
column whose name ends in a unit (``area_m2``, ``f_c_n``, `UNIT_SUFFIXES`) carries it as Arrow field metadata
``unit``. Provenance (versions, parameters, seed) is stored as JSON under the schema metadata key
``floebreak``. WKB keeps float64 coordinates bit for bit, so a write/read round trip is exact.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import shapely

from floebreak.errors import InputError
from floebreak.io.atomic import atomic_path
from floebreak.io.jsonable import to_json

GEO_METADATA_KEY = b"geo"
FLOEBREAK_METADATA_KEY = b"floebreak"


# shapely's geometry type ids → GeoParquet geometry type names (LinearRing, id 2, has none)
GEOMETRY_TYPE_NAMES = {
    0: "Point",
    1: "LineString",
    3: "Polygon",
    4: "MultiPoint",
    5: "MultiLineString",
    6: "MultiPolygon",
    7: "GeometryCollection",
}
# column-name suffix → unit (UCUM symbols), the longest suffix first
UNIT_SUFFIXES = {
    "_n_m": "N.m",
    "_knm": "kN.m",
    "_m_s": "m/s",
    "_m2": "m2",
    "_m3": "m3",
    "_kn": "kN",
    "_pa": "Pa",
    "_deg": "deg",
    "_rad": "rad",
    "_m": "m",
    "_n": "N",
    "_s": "s",
}


def column_unit(name: str) -> str | None:
    """The unit a column name ends in (`UNIT_SUFFIXES`), or None."""
    return next((unit for suffix, unit in UNIT_SUFFIXES.items() if name.endswith(suffix)), None)


def with_units(table: pa.Table) -> pa.Table:
    """`table` with each column's unit (`column_unit`) as Arrow field metadata ``unit``."""
    fields = []
    for field in table.schema:
        unit = column_unit(field.name)
        fields.append(field.with_metadata({"unit": unit}) if unit else field)
    return table.cast(pa.schema(fields, metadata=table.schema.metadata))


def geo_metadata(geometries: np.ndarray) -> dict[str, Any]:
    """The GeoParquet 1.1 ``geo`` metadata of a WKB column ``geometry`` holding `geometries`."""
    type_ids = set(shapely.get_type_id(geometries).tolist())
    known = type_ids <= set(GEOMETRY_TYPE_NAMES)
    column: dict[str, Any] = {
        "encoding": "WKB",
        "geometry_types": sorted(GEOMETRY_TYPE_NAMES[t] for t in type_ids) if known else [],
        "crs": None,
        "edges": "planar",
    }
    if len(geometries):
        column["bbox"] = [float(v) for v in shapely.total_bounds(geometries)]
    return {"version": "1.1.0", "primary_column": "geometry", "columns": {"geometry": column}}


def geoparquet_table(
    geometries: np.ndarray, columns: Mapping[str, Any], metadata: Mapping[str, Any]
) -> pa.Table:
    """An Arrow table with a WKB ``geometry`` column first, then `columns` (with units), GeoParquet metadata
    attached."""
    geometries = np.asarray(geometries, dtype=object)
    wkb = shapely.to_wkb(geometries, output_dimension=2) if len(geometries) else np.array([], dtype=object)
    table = pa.table({"geometry": pa.array(wkb, type=pa.binary()), **columns})
    schema_metadata = {
        GEO_METADATA_KEY: json.dumps(geo_metadata(geometries)).encode(),
        FLOEBREAK_METADATA_KEY: to_json(dict(metadata)).encode(),
    }
    return with_units(table.replace_schema_metadata(schema_metadata))


def write_geoparquet(
    path: str | os.PathLike[str],
    geometries: np.ndarray,
    columns: Mapping[str, Any],
    metadata: Mapping[str, Any],
    field: str = "output",
) -> Path:
    """Write a GeoParquet file atomically (temporary name, then rename)."""
    table = geoparquet_table(geometries, columns, metadata)
    with atomic_path(path, field=field) as temp:
        pq.write_table(table, temp)
    return Path(path)


def read_geoparquet(
    path: str | os.PathLike[str], field: str = "file"
) -> tuple[np.ndarray, dict[str, np.ndarray], dict[str, Any]]:
    """Read a GeoParquet file: (geometries, columns as numpy arrays, floebreak metadata).

    A missing, unreadable or non-GeoParquet file raises InputError naming `field`.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(field, f"{str(path)!r} does not exist or is not a file", allowed="a GeoParquet file")
    try:
        table = pq.read_table(path)
        schema_metadata = table.schema.metadata or {}
        geo = json.loads(schema_metadata[GEO_METADATA_KEY])
        geometry_column = geo["primary_column"]
        geometries = shapely.from_wkb(table.column(geometry_column).to_numpy(zero_copy_only=False))
        extra = json.loads(schema_metadata.get(FLOEBREAK_METADATA_KEY, b"{}"))
        columns = {
            name: table.column(name).to_numpy(zero_copy_only=False)
            for name in table.column_names
            if name != geometry_column
        }
    except InputError:
        raise
    except Exception as error:  # pyarrow, JSON and GEOS errors all mean: not a usable file
        raise InputError(
            field,
            f"{str(path)!r} is not a readable GeoParquet file ({type(error).__name__}: {error})",
            allowed="a GeoParquet file written by floebreak or another GeoParquet 1.x writer",
        ) from None
    return np.asarray(geometries, dtype=object), columns, extra
