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

GEO_METADATA_KEY = b"geo"
FLOEBREAK_METADATA_KEY = b"floebreak"


def _json_default(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, Path):
        return str(value)
    raise TypeError(f"not JSON serialisable: {type(value).__name__}")


def to_json(value: Any) -> str:
    return json.dumps(value, default=_json_default, sort_keys=True)


def _variable_width(items: list[bytes], arrow_type: pa.DataType) -> pa.Array | None:
    """A string or binary Arrow array of encoded items without nulls (offsets + data buffers), or None if
    the data exceed 32-bit offsets."""
    offsets = np.zeros(len(items) + 1, dtype=np.int64)
    np.cumsum(np.fromiter(map(len, items), dtype=np.int64, count=len(items)), out=offsets[1:])
    if offsets[-1] >= 2**31:
        return None
    buffers = [None, pa.py_buffer(offsets.astype(np.int32)), pa.py_buffer(b"".join(items))]
    return pa.Array.from_buffers(arrow_type, len(items), buffers, null_count=0)


def arrow_array(values: Any, binary: bool = False) -> pa.Array:
    """`values` as the Arrow array ``pa.array(values)`` gives (``pa.array(values, pa.binary())`` with
    `binary`).

    Built from buffers for numeric and bool numpy arrays and for lists of str (bytes with `binary`):
    ``pa.array`` imports pandas on its first call (≈ 0.25 s, to recognise pandas objects), which no
    writer here needs. Anything else (None values, mixed types, huge text) goes to ``pa.array``.
    """
    if isinstance(values, pa.Array):
        return values
    numeric = type(values) is np.ndarray and values.dtype.kind in "biuf" and values.dtype.isnative
    if numeric and values.ndim == 1:
        if values.dtype.kind == "b":  # Arrow booleans are bits, least significant first
            buffer = pa.py_buffer(np.packbits(values, bitorder="little"))
            return pa.Array.from_buffers(pa.bool_(), len(values), [None, buffer], null_count=0)
        data = np.ascontiguousarray(values)
        arrow_type = pa.from_numpy_dtype(data.dtype)
        return pa.Array.from_buffers(arrow_type, len(data), [None, pa.py_buffer(data)], null_count=0)
    items = values.tolist() if type(values) is np.ndarray else values
    if isinstance(items, list):
        kind, arrow_type = (bytes, pa.binary()) if binary else (str, pa.string())
        if not items:  # pa.array([]) is of type null
            return _variable_width([], arrow_type) if binary else pa.nulls(0)
        if all(type(v) is kind for v in items):
            array = _variable_width(items if binary else [v.encode("utf-8") for v in items], arrow_type)
            if array is not None:
                return array
    return pa.array(values, type=pa.binary()) if binary else pa.array(values)


def geoparquet_table(
    geometries: np.ndarray, columns: Mapping[str, Any], metadata: Mapping[str, Any]
) -> pa.Table:
    """An Arrow table with a WKB ``geometry`` column first, then `columns`, GeoParquet metadata attached."""
    geometries = np.asarray(geometries, dtype=object)
    wkb = shapely.to_wkb(geometries, output_dimension=2) if len(geometries) else np.array([], dtype=object)
    arrays: dict[str, Any] = {"geometry": arrow_array(list(wkb), binary=True)}
    for name, values in columns.items():
        arrays[name] = arrow_array(values)
    table = pa.table(arrays)
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
        table = pq.ParquetFile(path).read()  # one file: no dataset layer (pyarrow.dataset, ≈ 0.1 s to import)
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
