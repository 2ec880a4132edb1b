"""GeoParquet 1.1 read/write with pyarrow + shapely WKB.

Coordinates are metres in the ship frame, not a geographic CRS, hence ``"crs": null``. Provenance
(versions, parameters, seed) is stored as JSON under the schema metadata key ``floebreak``. WKB keeps
float64 coordinates bit for bit, so a write/read round trip is exact.
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


def geoparquet_table(
    geometries: np.ndarray, columns: Mapping[str, Any], metadata: Mapping[str, Any]
) -> pa.Table:
    """An Arrow table with a WKB ``geometry`` column first, then `columns`, GeoParquet metadata attached."""
    geometries = np.asarray(geometries, dtype=object)
    wkb = shapely.to_wkb(geometries, output_dimension=2) if len(geometries) else np.array([], dtype=object)
    table = pa.table({"geometry": pa.array(wkb, type=pa.binary()), **columns})
    types = sorted({t for t in shapely.get_type_id(geometries).tolist()}) if len(geometries) else []
    type_names = {3: "Polygon", 6: "MultiPolygon", 1: "Point", 2: "LineString", 5: "MultiLineString"}
    geo = {
        "version": "1.1.0",
        "primary_column": "geometry",
        "columns": {
            "geometry": {
                "encoding": "WKB",
                "geometry_types": [type_names.get(t, "Unknown") for t in types],
                "crs": None,
                "edges": "planar",
            }
        },
    }
    schema_metadata = {
        GEO_METADATA_KEY: json.dumps(geo).encode(),
        FLOEBREAK_METADATA_KEY: to_json(dict(metadata)).encode(),
    }
    return table.replace_schema_metadata(schema_metadata)


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
