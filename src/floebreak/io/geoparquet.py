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
from collections.abc import Callable, Iterable, Mapping, Sequence
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
# Rows per Parquet row group of a large table: a table is converted to WKB and Arrow one row group at a time,
# so writing holds a few copies of one group rather than of the whole table (a long transit's pieces,
# contact records). A table of at most this many rows is one row group, as ``pyarrow.parquet.write_table``
# writes it.
ROW_GROUP_ROWS = 16_384


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

    Built from buffers for numeric and bool numpy arrays and for lists of str (bytes with `binary`), because
    ``pa.array`` imports pandas on its first call, which costs > 5 % of a run (benchmarks/README.md, "Simple
    over clever"). Anything else (None values, mixed types, huge text) goes to ``pa.array``.
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
    return as_schema(table, pa.schema(fields, metadata=table.schema.metadata))


def as_schema(table: pa.Table, schema: pa.Schema) -> pa.Table:
    """`table` with `schema` (its types, field and schema metadata), as ``table.cast(schema)``, but cast
    only if a column's type differs: `Table.cast` imports pyarrow.compute (≈ 0.1 s of a run's CPU)."""
    if table.schema.equals(schema, check_metadata=False):
        return pa.Table.from_arrays(table.columns, schema=schema)
    return table.cast(schema)


def geo_metadata(geometries: np.ndarray) -> dict[str, Any]:
    """The GeoParquet 1.1 ``geo`` metadata of a WKB column ``geometry`` holding `geometries`."""
    return geo_metadata_of_parts([geometries])


def geo_metadata_of_parts(parts: Iterable[np.ndarray]) -> dict[str, Any]:
    """`geo_metadata` of the geometries of all `parts` together (one part at a time in memory)."""
    type_ids: set[int] = set()
    boxes = []
    for geometries in parts:
        type_ids |= set(shapely.get_type_id(geometries).tolist())
        if len(geometries):
            boxes.append(shapely.total_bounds(geometries))
    known = type_ids <= set(GEOMETRY_TYPE_NAMES)
    column: dict[str, Any] = {
        "encoding": "WKB",
        "geometry_types": sorted(GEOMETRY_TYPE_NAMES[t] for t in type_ids) if known else [],
        "crs": None,
        "edges": "planar",
    }
    if boxes:  # total bounds (NaN-skipping, as shapely.total_bounds) of the parts' total bounds
        box = np.array(boxes)
        if np.isnan(box).all():
            column["bbox"] = [float("nan")] * 4
        else:
            low, high = np.nanmin(box[:, :2], axis=0), np.nanmax(box[:, 2:], axis=0)
            column["bbox"] = [float(v) for v in (*low, *high)]
    return {"version": "1.1.0", "primary_column": "geometry", "columns": {"geometry": column}}


def geoparquet_table(
    geometries: np.ndarray,
    columns: Mapping[str, Any],
    metadata: Mapping[str, Any],
    geo: Mapping[str, Any] | None = None,
) -> pa.Table:
    """An Arrow table with a WKB ``geometry`` column first, then `columns` (with units), GeoParquet metadata
    attached (`geo`: that of a whole table this one is a row group of; default `geo_metadata(geometries)`)."""
    geometries = np.asarray(geometries, dtype=object)
    wkb = shapely.to_wkb(geometries, output_dimension=2) if len(geometries) else np.array([], dtype=object)
    arrays = {"geometry": arrow_array(list(wkb), binary=True)}
    table = pa.table(arrays | {name: arrow_array(values) for name, values in columns.items()})
    schema_metadata = {
        GEO_METADATA_KEY: json.dumps(geo or geo_metadata(geometries)).encode(),
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
    """Write a GeoParquet file atomically (temporary name, then rename), in row groups of `ROW_GROUP_ROWS`."""
    geometries = np.asarray(geometries, dtype=object)
    return write_geoparquet_groups(
        path,
        row_groups(len(geometries)),
        lambda rows: geometries[rows],
        lambda rows: (geometries[rows], {k: v[rows] for k, v in columns.items()}),
        metadata,
        field=field,
    )


def write_geoparquet_groups(
    path: str | os.PathLike[str],
    groups: Sequence[Any],
    geometries_of: Callable[[Any], np.ndarray],
    table_of: Callable[[Any], tuple[np.ndarray, Mapping[str, Any]]],
    metadata: Mapping[str, Any],
    field: str = "output",
) -> Path:
    """Write a GeoParquet file atomically, one row group per item of `groups`: `table_of(group)` gives its
    (geometries, columns), `geometries_of(group)` its geometries alone (a first pass, for the ``geo``
    metadata of the whole file). Only one group's table is in memory at a time."""
    geo = geo_metadata_of_parts(geometries_of(group) for group in groups)
    with atomic_path(path, field=field) as temp:
        write_row_groups(temp, (geoparquet_table(*table_of(group), metadata, geo) for group in groups))
    return Path(path)


def row_groups(n_rows: int, size: int | None = None) -> list[slice]:
    """Slices of `size` rows (default `ROW_GROUP_ROWS`) covering `n_rows` (one empty slice for an empty
    table)."""
    size = size or ROW_GROUP_ROWS
    return [slice(start, start + size) for start in range(0, n_rows, size)] or [slice(0, 0)]


def write_row_groups(path: str | os.PathLike[str], tables: Iterable[pa.Table]) -> None:
    """Write `tables` (same schema, metadata included) as one Parquet file, each as its own row group(s)."""
    writer = None
    try:
        for table in tables:
            if writer is None:
                writer = pq.ParquetWriter(path, table.schema)
            writer.write_table(as_schema(table, writer.schema))  # a chunk's types as the first one's
    finally:
        if writer is not None:
            writer.close()


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
