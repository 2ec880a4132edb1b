"""What a breaking-pattern figure draws (`BreakingPattern`), as plain data taken from a `SimulationResult`
without importing matplotlib.

A figure worker (`floebreak.output.figure_process`) is sent this, not the run's result: the result of a
100 km transit holds every piece of the run and pickles to hundreds of MB, which the worker would hold
once more (benchmarks/README.md, "Memory of the figure worker").
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import shapely

FATES = ("remaining", "flipped", "cusp")  # drawn in this order: cusps on top


@dataclass(frozen=True, eq=False)
class BreakingPattern:
    """The pieces a breaking-pattern figure draws and what frames it.

    Attributes:
        polygons: fate ("remaining", "flipped", "cusp") → the shapely polygons drawn (within `x_window_m`).
        counts: fate → the number of pieces of that fate in the whole run (the legend's counts).
        field_domain_m: (x_min, y_min, x_max, y_max) of the field [m].
        pieces_bounds_m: (x_min, y_min, x_max, y_max) of every piece of the run (the field's domain if
            none) [m].
        hull_upper_bounds_m: bounds of the bow's upper ice waterline polygon at x = 0 [m].
        upper_xy_m, lower_xy_m: the bow's upper and lower ice waterlines at x = 0, (n, 2) [m].
        bow_start_x_m, bow_end_x_m: the bow position at the run's first and last step [m].
        x_window_m: the x range drawn [m], or None for the whole field.
    """

    polygons: Mapping[str, np.ndarray]
    counts: Mapping[str, int]
    field_domain_m: tuple[float, float, float, float]
    pieces_bounds_m: tuple[float, float, float, float]
    hull_upper_bounds_m: tuple[float, float, float, float]
    upper_xy_m: np.ndarray
    lower_xy_m: np.ndarray
    bow_start_x_m: float
    bow_end_x_m: float
    x_window_m: tuple[float, float] | None = None


def breaking_pattern(result, x_window_m: tuple[float, float] | None = None) -> BreakingPattern:
    """The `BreakingPattern` of a `SimulationResult`: its remaining, flipped and cusp pieces (those whose
    bounds reach into `x_window_m`, if given; only these are decoded), with the run's counts and frame."""
    bounds = result.piece_bounds_m  # NaN for an empty piece
    shown = np.ones(len(bounds), dtype=bool)
    if x_window_m is not None:
        shown = (bounds[:, 0] <= x_window_m[1]) & (bounds[:, 2] >= x_window_m[0])
    polygons, counts = {}, {}
    for fate in FATES:
        of_fate = result.mask(fate)
        polygons[fate] = result.polygons(np.flatnonzero(of_fate & shown))
        counts[fate] = int(of_fate.sum())
    if len(bounds) and not np.isnan(bounds).all():  # as shapely.total_bounds of the pieces
        total = np.concatenate([np.nanmin(bounds[:, :2], axis=0), np.nanmax(bounds[:, 2:], axis=0)])
    else:
        total = np.array(result.field.domain_m)
    params = result.params
    return BreakingPattern(
        polygons=polygons,
        counts=counts,
        field_domain_m=tuple(float(v) for v in result.field.domain_m),
        pieces_bounds_m=tuple(float(v) for v in total),
        hull_upper_bounds_m=tuple(float(v) for v in shapely.bounds(result.bow.hull_upper)),
        upper_xy_m=np.asarray(result.bow.upper_xy_m, dtype=float),
        lower_xy_m=np.asarray(result.bow.lower_xy_m, dtype=float),
        bow_start_x_m=float(params.x_start_m),
        bow_end_x_m=float(params.x_start_m + (result.n_steps - 1) * params.step_m),
        x_window_m=None if x_window_m is None else (float(x_window_m[0]), float(x_window_m[1])),
    )
