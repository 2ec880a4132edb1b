"""Save and load floe fields: GeoParquet (exact round trip) and GeoJSON export."""

from __future__ import annotations

import json
import os
import warnings
from pathlib import Path

import numpy as np
import shapely

from floebreak.errors import InputError
from floebreak.ice.field import FloeField
from floebreak.io.atomic import atomic_path
from floebreak.io.geoparquet import read_geoparquet, write_geoparquet
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

    The domain (x_min, y_min, x_max, y_max) comes from the file's floebreak metadata (``domain_m``). A file
    without it (another tool's, or one that went through geopandas, which drops that metadata) is loaded with
    the domain `DOMAIN_RULE`, a `FieldFileWarning`, and ``metadata["domain_rule"]`` recording it: the
    bounding box of the floes is usually smaller than the generated domain, which moves the bow's start and
    end (``x_end``) and so changes the results.
    """
    geometries, columns, meta = read_geoparquet(path, field=field)
    missing = [name for name in _REQUIRED_COLUMNS if name not in columns]
    if missing:
        raise InputError(
            field, f"{str(path)!r} lacks columns {missing}", allowed="floe_id, thickness_m, geometry"
        )
    valid = shapely.is_valid(geometries) & ~shapely.is_empty(geometries)
    types = shapely.get_type_id(geometries)
    if not np.all(valid & np.isin(types, (3, 6))):
        bad = int(np.flatnonzero(~(valid & np.isin(types, (3, 6))))[0])
        raise InputError(
            field, f"row {bad} of {str(path)!r} is not a valid polygon", allowed="valid polygons"
        )
    thickness = np.asarray(columns["thickness_m"], dtype=float)
    if not np.all(np.isfinite(thickness) & (thickness > 0)):
        bad = int(np.flatnonzero(~(np.isfinite(thickness) & (thickness > 0)))[0])
        raise InputError(field, f"row {bad}: thickness_m = {thickness[bad]!r}", allowed="> 0 m")
    metadata = {**meta.get("field", {}), "source_file": Path(path).name}
    if "domain_m" in meta:
        domain = tuple(float(v) for v in meta["domain_m"])
    else:
        domain = tuple(float(v) for v in shapely.total_bounds(geometries))
        metadata["domain_rule"] = DOMAIN_RULE
        warnings.warn(
            f"{field}: {str(path)!r} has no floebreak domain metadata (written by another tool, or "
            f"round-tripped through one); the domain is {DOMAIN_RULE}: {list(domain)} m",
            FieldFileWarning,
            stacklevel=2,
        )
    diameter = columns.get("diameter_class_m", np.full(len(geometries), np.nan))
    return FloeField(
        polygons=geometries,
        thickness_m=thickness,
        diameter_class_m=np.asarray(diameter, dtype=float),
        floe_id=np.asarray(columns["floe_id"], dtype=np.int64),
        domain_m=domain,  # type: ignore[arg-type]
        metadata=metadata,
    )


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
