"""Shared plotting helpers: a headless figure factory and polygon collections."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")  # figures are written to files; never needs a display

import numpy as np
import shapely
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure

# thesis colour code for breaking patterns (Figs. 15–16, 18–24)
UNTOUCHED_COLOUR = "#4c72b0"  # blue
FLIPPED_COLOUR = "#f28e2b"  # orange
CUSP_COLOUR = "#d62728"  # red


def new_figure(width_in: float = 10.0, height_in: float = 4.0) -> tuple[Figure, object]:
    """A figure with one axes, created without pyplot (safe in threads, workers and notebooks)."""
    figure = Figure(figsize=(width_in, height_in), constrained_layout=True)
    return figure, figure.add_subplot(1, 1, 1)


def polygon_collection(polygons, **kwargs) -> PolyCollection:
    """One PolyCollection of the exteriors of all polygons (multipolygons contribute every part)."""
    parts = shapely.get_parts(np.asarray(polygons, dtype=object))
    exteriors = shapely.get_exterior_ring(parts)
    coords, ring = shapely.get_coordinates(exteriors, return_index=True)  # one call, not one per ring
    ends = np.cumsum(np.bincount(ring, minlength=len(exteriors)))
    verts = np.split(coords, ends[:-1]) if len(exteriors) else []
    return PolyCollection(verts, **kwargs)
