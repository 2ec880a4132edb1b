"""Floe fields: the ice the ship meets (thesis §2).

A `FloeField` is plain data: one shapely polygon, thickness, id and diameter class per floe, plus the
rectangular domain it was generated in and provenance metadata. Coordinates are metres in the ship
frame (x forward, y to port; the bow tip starts at the origin), so the field lies ahead of the bow at
x ≥ 0 and is centred on the ship track.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from types import MappingProxyType
from typing import Any

import numpy as np
import shapely

from floebreak.errors import InputError


@dataclass(frozen=True, eq=False)
class FloeField:
    """An immutable field of floes.

    Attributes:
        polygons: object array of shapely Polygons, one per floe.
        thickness_m: float array, thickness per floe [m].
        diameter_class_m: float array, observed equivalent-diameter class per floe [m] (NaN if none).
        floe_id: int64 array of unique ids (0 … n−1 for generated fields).
        domain_m: (x_min, y_min, x_max, y_max) of the rectangle the field was generated in [m].
        metadata: provenance (generator, its parameters, seed, shifts applied).
    """

    polygons: np.ndarray
    thickness_m: np.ndarray
    diameter_class_m: np.ndarray
    floe_id: np.ndarray
    domain_m: tuple[float, float, float, float]
    metadata: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        polygons = np.asarray(self.polygons, dtype=object)
        n = polygons.shape[0]
        thickness = np.asarray(self.thickness_m, dtype=float).reshape(-1)
        diameter = np.asarray(self.diameter_class_m, dtype=float).reshape(-1)
        ids = np.asarray(self.floe_id, dtype=np.int64).reshape(-1)
        for name, array in (("thickness_m", thickness), ("diameter_class_m", diameter), ("floe_id", ids)):
            if array.shape[0] != n:
                raise ValueError(f"{name} has {array.shape[0]} entries for {n} polygons")
        if n and not np.all(thickness > 0.0):
            raise InputError("thickness_m", "every floe needs a positive thickness", allowed="> 0 m")
        if np.unique(ids).shape[0] != n:
            raise ValueError("floe_id values must be unique")
        for array in (polygons, thickness, diameter, ids):
            array.setflags(write=False)
        object.__setattr__(self, "polygons", polygons)
        object.__setattr__(self, "thickness_m", thickness)
        object.__setattr__(self, "diameter_class_m", diameter)
        object.__setattr__(self, "floe_id", ids)
        object.__setattr__(self, "domain_m", tuple(float(v) for v in self.domain_m))
        object.__setattr__(self, "metadata", MappingProxyType(dict(self.metadata)))

    # --- derived quantities -------------------------------------------------------------------
    @property
    def n_floes(self) -> int:
        return int(self.polygons.shape[0])

    @property
    def area_m2(self) -> np.ndarray:
        """Area of every floe polygon [m²]."""
        return shapely.area(self.polygons)

    @property
    def ice_area_m2(self) -> float:
        return float(self.area_m2.sum())

    @property
    def domain_area_m2(self) -> float:
        x0, y0, x1, y1 = self.domain_m
        return (x1 - x0) * (y1 - y0)

    @property
    def concentration(self) -> float:
        """Ice-covered fraction of the domain (polygon areas / domain area)."""
        return self.ice_area_m2 / self.domain_area_m2 if self.domain_area_m2 > 0 else 0.0

    # --- transformations ----------------------------------------------------------------------
    def shifted(self, dx_m: float, dy_m: float = 0.0, reason: str = "") -> FloeField:
        """The same field translated by (dx, dy); the shift is recorded in the metadata."""
        moved = shapely.transform(self.polygons, lambda xy: xy + np.array([dx_m, dy_m]))
        x0, y0, x1, y1 = self.domain_m
        shifts = [
            *self.metadata.get("shifts_m", []),
            {"dx_m": float(dx_m), "dy_m": float(dy_m), "reason": reason},
        ]
        return replace(
            self,
            polygons=moved,
            domain_m=(x0 + dx_m, y0 + dy_m, x1 + dx_m, y1 + dy_m),
            metadata={**self.metadata, "shifts_m": shifts},
        )

    def with_thickness(self, thickness_m: np.ndarray | float) -> FloeField:
        """The same floes with new thickness values (scalar or one per floe)."""
        values = np.broadcast_to(np.asarray(thickness_m, dtype=float), (self.n_floes,)).copy()
        return replace(self, thickness_m=values)

    def subset(self, mask: np.ndarray) -> FloeField:
        """The floes selected by a boolean mask or index array."""
        return replace(
            self,
            polygons=self.polygons[mask],
            thickness_m=self.thickness_m[mask],
            diameter_class_m=self.diameter_class_m[mask],
            floe_id=self.floe_id[mask],
        )


def diameter_classes_m(floe_field: FloeField) -> tuple[float, ...]:
    """The observed diameter classes of `floe_field`'s floes [m], ascending (NaN, no class, left out)."""
    classes = floe_field.diameter_class_m
    return tuple(float(d) for d in np.unique(classes[~np.isnan(classes)]))


def circle_polygons(centers_m: np.ndarray, radii_m: np.ndarray, vertices: int) -> np.ndarray:
    """Regular polygons with `vertices` corners inscribed in the given circles (vectorised).

    An inscribed polygon never reaches outside its circle, so circles that do not overlap give
    polygons that do not overlap; its area is (n/2π)·sin(2π/n) of the circle's (0.9984 for n = 64).
    """
    centers = np.asarray(centers_m, dtype=float).reshape(-1, 2)
    radii = np.asarray(radii_m, dtype=float).reshape(-1)
    angles = 2.0 * np.pi * np.arange(vertices) / vertices
    ring = np.stack([np.cos(angles), np.sin(angles)], axis=1)  # (v, 2)
    coords = centers[:, None, :] + radii[:, None, None] * ring[None, :, :]
    return shapely.polygons(coords)


def first_overlap(polygons: np.ndarray) -> tuple[int, int] | None:
    """The first pair (i, j), i < j, of `polygons` that share a positive area — in the order a loop over j,
    then i, meets them — or None. Polygons that only touch (a shared edge or corner, zero area) do not
    overlap. The one overlap rule of floe fields, for inline floes and field files alike.

    Candidate pairs come from a spatial index (10 000 floes: the pairs that touch, not all 5e7 pairs)."""
    polygons = np.asarray(polygons, dtype=object)
    first, second = shapely.STRtree(polygons).query(polygons, predicate="intersects")
    pairs = first < second
    first, second = first[pairs], second[pairs]
    overlap = shapely.area(shapely.intersection(polygons[first], polygons[second])) > 0.0
    if not overlap.any():
        return None
    order = np.lexsort((first[overlap], second[overlap]))[0]
    return int(first[overlap][order]), int(second[overlap][order])
