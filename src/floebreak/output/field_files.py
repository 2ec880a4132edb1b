"""Save and load floe fields: GeoParquet (exact round trip) and GeoJSON export."""

from __future__ import annotations

import json
import os
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow.parquet as pq
import shapely

from floebreak.errors import InputError
from floebreak.ice.field import FloeField, first_overlap
from floebreak.io.atomic import atomic_path
from floebreak.io.geoparquet import GEO_METADATA_KEY, read_geoparquet, write_geoparquet
from floebreak.io.jsonable import jsonable
from floebreak.io.provenance import provenance

_REQUIRED_COLUMNS = ("floe_id", "thickness_m")
DOMAIN_RULE = "the bounding box of the floes"


class FieldFileWarning(UserWarning):
    """A field file was loaded, but not exactly as floebreak wrote it (e.g. its domain was inferred)."""


def field_columns(floe_field: FloeField) -> dict[str, np.ndarray]:
    return {
        "floe_id": floe_field.floe_id,
        "thickness_m": floe_field.thickness_m,
        "diameter_class_m": floe_field.diameter_class_m,
        "area_m2": floe_field.area_m2,
    }


def save_field(floe_field: FloeField, path: str | os.PathLike[str], field: str = "out") -> Path:
    """Write `floe_field` as GeoParquet (``"crs": null``) with provenance metadata, atomically."""
    meta = provenance(kind="floe_field", domain_m=list(floe_field.domain_m), field=dict(floe_field.metadata))
    return write_geoparquet(path, floe_field.polygons, field_columns(floe_field), meta, field=field)


def load_field(path: str | os.PathLike[str], field: str = "field.file") -> FloeField:
    """Read a field written by `save_field` (or any GeoParquet with floe_id and thickness_m columns).

    The file is checked as inline floes are (`FIELD_FILE_RULES`); anything else is an InputError naming
    `field`, the file, and the row (counted from 1, as in the CSV readers) and column at fault.

    The domain (x_min, y_min, x_max, y_max) comes from the file's floebreak metadata (``domain_m``). A file
    without it (another tool's, or one that went through geopandas, which drops that metadata) is loaded with
    the domain `DOMAIN_RULE`, a `FieldFileWarning`, and ``metadata["domain_rule"]`` recording it: the
    bounding box of the floes is usually smaller than the generated domain, which moves the bow's start and
    end (``x_end``) and so changes the results.
    """
    where = _Where(field, str(path))
    _check_crs(path, where)
    geometries, columns, meta = read_geoparquet(path, field=field)
    missing = [name for name in _REQUIRED_COLUMNS if name not in columns]
    if missing:
        raise InputError(
            field, f"{where.file} lacks columns {missing}", allowed="floe_id, thickness_m, geometry"
        )
    if len(geometries) == 0:
        raise InputError(field, f"{where.file} has no rows", allowed="at least one floe")
    _check_polygons(geometries, where)
    thickness = _number_column(columns, "thickness_m", where)
    bad = np.flatnonzero(~(np.isfinite(thickness) & (thickness > 0)))
    if bad.size:
        value = float(thickness[bad[0]])
        raise InputError(where.at(bad[0], "thickness_m"), f"{value!r}", value=value, allowed="> 0 m")
    floe_id = _floe_ids(columns, where)
    diameter = (
        _number_column(columns, "diameter_class_m", where)
        if "diameter_class_m" in columns
        else np.full(len(geometries), np.nan)
    )
    metadata = {**meta.get("field", {}), "source_file": Path(path).name}
    if "domain_m" in meta:
        domain = _domain(meta["domain_m"], where)
    else:
        domain = tuple(float(v) for v in shapely.total_bounds(geometries))
        metadata["domain_rule"] = DOMAIN_RULE
        warnings.warn(
            f"{field}: {where.file} has no floebreak domain metadata (written by another tool, or "
            f"round-tripped through one); the domain is {DOMAIN_RULE}: {list(domain)} m",
            FieldFileWarning,
            stacklevel=2,
        )
    return FloeField(
        polygons=geometries,
        thickness_m=thickness,
        diameter_class_m=diameter,
        floe_id=floe_id,
        domain_m=domain,  # type: ignore[arg-type]
        metadata=metadata,
    )


FIELD_FILE_RULES = """\
- at least one row; a valid, non-empty Polygon or MultiPolygon per row;
- no two floes share a positive area (`floebreak.ice.field.first_overlap`, the rule of inline floes);
- ``floe_id``: integers, unique; floats are accepted only where exactly integral (3.0, not 3.5), since a
  tool that stores ids as floats (e.g. after a null) keeps their values exactly below 2**53;
- ``thickness_m`` (and ``diameter_class_m``, if present, NaN meaning none): numbers, not text; thickness
  finite and > 0;
- ``domain_m`` in the floebreak metadata, if present: four finite numbers x_min < x_max, y_min < y_max;
- the geometry column's CRS: ``null`` (floebreak's own) or a local engineering CRS in metres. Coordinates
  are metres in the ship frame; a geographic or projected CRS (longitude/latitude, UTM) is refused, since
  reading its coordinates as metres of the ship frame would be wrong.
"""


@dataclass(frozen=True)
class _Where:
    """Names places in a field file for InputError keys: ``field.file: 'f.parquet', row 3, column 'x'``."""

    field: str
    path: str

    @property
    def file(self) -> str:
        return repr(self.path)

    def at(self, index: int | None = None, column: str | None = None) -> str:
        text = f"{self.field}: {self.file}"
        if index is not None:
            text += f", row {int(index) + 1}"
        if column is not None:
            text += f", column {column!r}"
        return text


def _check_crs(path: str | os.PathLike[str], where: _Where) -> None:
    """InputError unless the geometry column's CRS is null or a local engineering CRS in metres. An absent
    ``crs`` means OGC:CRS84 (longitude/latitude) in GeoParquet 1.x."""
    try:
        geo = json.loads((pq.read_schema(path).metadata or {})[GEO_METADATA_KEY])
        column = geo["columns"][geo["primary_column"]]
    except Exception:  # not GeoParquet at all: read_geoparquet says so, with its reason
        return
    crs = column["crs"] if "crs" in column else "OGC:CRS84 (no 'crs' key: GeoParquet's default)"
    if crs is None or _is_local_metres(crs):
        return
    name = crs.get("name", crs.get("type", "a CRS")) if isinstance(crs, dict) else str(crs)
    raise InputError(
        f"{where.at(column='geometry')} (crs)",
        f"coordinates in {name!r}, but floebreak reads metres in the ship frame (x forward, y to port)",
        allowed='"crs": null or a local engineering CRS in metres: project the floes to metres, move them '
        'into the ship frame (the bow starts at the origin) and write the file with "crs": null',
    )


def _is_local_metres(crs: Any) -> bool:
    """Whether a PROJJSON CRS is an engineering (local) CRS whose axes, where they say, are in metres."""
    if not isinstance(crs, dict) or crs.get("type") != "EngineeringCRS":
        return False
    axes = crs.get("coordinate_system", {}).get("axis", [])
    units = [axis.get("unit", "metre") for axis in axes if isinstance(axis, dict)]
    return all(unit in ("metre", "meter", "m") or _unit_name(unit) in ("metre", "meter") for unit in units)


def _unit_name(unit: Any) -> str | None:
    return unit.get("name") if isinstance(unit, dict) else None


def _check_polygons(geometries: np.ndarray, where: _Where) -> None:
    valid = shapely.is_valid(geometries) & ~shapely.is_empty(geometries)
    good = valid & np.isin(shapely.get_type_id(geometries), (3, 6))
    if not np.all(good):
        bad = int(np.flatnonzero(~good)[0])
        reason = shapely.is_valid_reason(geometries[bad]) if geometries[bad] is not None else "null"
        raise InputError(
            where.at(bad, "geometry"), f"not a valid polygon ({reason})", allowed="valid polygons"
        )
    overlap = first_overlap(geometries)
    if overlap is not None:
        i, j = overlap
        raise InputError(
            where.at(j, "geometry"),
            f"overlaps row {i + 1}",
            allowed="floes that do not overlap (they may touch: a shared edge has no area)",
        )


def _number_column(columns: dict[str, np.ndarray], name: str, where: _Where) -> np.ndarray:
    """A numeric column as float; InputError naming the first row whose value is not a number."""
    values = np.asarray(columns[name])
    if values.dtype.kind in "iuf":
        return values.astype(float)
    for index, value in enumerate(values.tolist()):
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise InputError(
                where.at(index, name),
                f"{value!r} is not a number",
                allowed="numbers (a numeric column, not text)",
            )
    return values.astype(float)  # object column of numbers and None (nulls → NaN)


def _floe_ids(columns: dict[str, np.ndarray], where: _Where) -> np.ndarray:
    """The floe_id column as int64: integers, or exactly integral floats (`FIELD_FILE_RULES`), unique."""
    values = np.asarray(columns["floe_id"])
    if values.dtype.kind in "iu":
        ok = values <= np.iinfo(np.int64).max  # uint64 beyond int64
    elif values.dtype.kind == "f":
        ok = np.isfinite(values) & (values == np.round(values)) & (np.abs(values) < 2.0**53)
    else:
        ok = np.array([isinstance(v, int) and not isinstance(v, bool) for v in values.tolist()])
    if not ok.all():
        bad = int(np.flatnonzero(~ok)[0])
        value = values[bad].item() if isinstance(values[bad], np.generic) else values[bad]
        raise InputError(
            where.at(bad, "floe_id"),
            f"{value!r} is not an integer id",
            value=value,
            allowed="integers (floats only when exactly integral, below 2**53)",
        )
    ids = values.astype(np.int64)
    unique, counts = np.unique(ids, return_counts=True)
    if unique.size != ids.size:
        repeated = unique[counts > 1]
        rows = np.flatnonzero(ids == repeated[0])
        raise InputError(
            where.at(rows[1], "floe_id"),
            f"{int(repeated[0])} repeats row {rows[0] + 1}",
            value=int(repeated[0]),
            allowed="unique floe ids",
        )
    return ids


def _domain(value: Any, where: _Where) -> tuple[float, float, float, float]:
    """The metadata's ``domain_m`` as four finite numbers with x_min < x_max and y_min < y_max."""
    key = f"{where.at()}, metadata 'domain_m'"
    allowed = "[x_min, y_min, x_max, y_max]: four finite numbers [m], x_min < x_max, y_min < y_max"
    numbers = isinstance(value, list | tuple) and len(value) == 4
    if numbers:
        numbers = all(isinstance(v, int | float) and not isinstance(v, bool) for v in value)
    if not numbers or not all(np.isfinite(value)):
        raise InputError(key, f"{value!r}", value=value, allowed=allowed)
    x0, y0, x1, y1 = (float(v) for v in value)
    if not (x0 < x1 and y0 < y1):
        raise InputError(key, f"{list(value)!r} is empty or inverted", value=value, allowed=allowed)
    return x0, y0, x1, y1


def export_geojson(floe_field: FloeField, path: str | os.PathLike[str], field: str = "out") -> Path:
    """Write the field as a GeoJSON FeatureCollection (coordinates in metres, ship frame)."""
    features = []
    for polygon, floe_id, thickness, diameter, area in zip(
        floe_field.polygons,
        floe_field.floe_id,
        floe_field.thickness_m,
        floe_field.diameter_class_m,
        floe_field.area_m2,
        strict=True,
    ):
        features.append(
            {
                "type": "Feature",
                "geometry": shapely.geometry.mapping(polygon),
                "properties": {
                    "floe_id": int(floe_id),
                    "thickness_m": float(thickness),
                    "diameter_class_m": None if np.isnan(diameter) else float(diameter),
                    "area_m2": float(area),
                },
            }
        )
    document = {
        "type": "FeatureCollection",
        "features": features,
        "floebreak": jsonable(provenance(domain_m=list(floe_field.domain_m))),
    }
    with atomic_path(path, field=field) as temp:
        temp.write_text(json.dumps(document), encoding="utf-8")
    return Path(path)
