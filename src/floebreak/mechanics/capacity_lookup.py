"""The bending capacity as the thesis' App. A.4 code looks it up (physics-notes §1.7; erratum 12).

App. A.4 reads Erceg et al.'s capacity tables, indexed by the ice thickness h ∈ {0.3, 0.6, 0.9, 1.2} m, the
loading radius r ∈ {0.1, 0.3, 0.6, 1.0, 1.5} m and the wedge angle γ ∈ {1, 2, …, 59, 60, 90, 105, 135, 165,
180}°, and returns the plain mean of the eight table values at the grid points that bracket (h, r, γ), not
an interpolation (defect 1). Its thickness bracket is (1.2 m, the first grid value above h) for every h off
the grid below 1.2 m (defect 2: ``h_vec[np.where(h_vec > h)[0][-1]]`` is the *largest* grid value), so the
capacity at h = 1.0 m is the one at 1.2 m, and at h = 0.8 m the mean of those at 0.9 and 1.2 m. r is
clipped to [0.1, 1.5] m and γ capped at 180°.

Erceg's tables are not published: as physics-notes §1.7 advises, a table value is Eq. 1.4 at its grid
point, through the `capacity_n` the caller passes. This is the reading the `thesis` profile takes, because
the thesis' Table 7 was computed with it (docs/model.md §11); the default evaluates Eq. 1.4 at (h, r, Θ).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Final

A4_THICKNESS_GRID_M: Final = (0.0, 0.3, 0.6, 0.9, 1.2)
A4_RADIUS_GRID_M: Final = (0.1, 0.3, 0.6, 1.0, 1.5)
A4_ANGLE_GRID_DEG: Final = (*range(1, 60), 60, 90, 105, 135, 165, 180)
_ON_GRID: Final = 1e-10  # App. A.4's test for a value on the grid


def thickness_corners_m(thickness_m: float) -> tuple[float, float]:
    """The two thicknesses App. A.4 averages over for `thickness_m` (its lines 43–51, defect 2)."""
    grid = A4_THICKNESS_GRID_M
    if any(abs(thickness_m - value) < _ON_GRID for value in grid[1:]):
        return thickness_m, thickness_m
    if thickness_m > grid[-1]:
        return grid[-1], grid[-1]
    above = [value for value in grid if value > thickness_m]
    return above[-1], above[0]  # "h1": the largest grid value above h, not the one below it


def bracket(value: float, grid: Sequence[float]) -> tuple[float, float]:
    """(the grid value before the first one above `value`, that first one), or `value` twice on the grid.

    Below the first grid value the "value before" is the last one, as the code's index −1 gives.
    """
    if any(abs(value - point) < _ON_GRID for point in grid):
        return value, value
    first_above = next(i for i, point in enumerate(grid) if point > value)
    return grid[first_above - 1], grid[first_above]


def thesis_a4_capacity_n(
    thickness_m: float,
    loading_radius_m: float,
    opening_rad: float,
    capacity_n: Callable[[float, float, float], float],
) -> float:
    """Bending capacity [N] as App. A.4 returns it: the mean of `capacity_n(h_i, r_j, Θ_k)` over the eight
    bracketing grid points of (h, r, Θ) (the code's thickness bracket, r clipped to [0.1, 1.5] m, Θ capped
    at 180°). `capacity_n(h, r, Θ)` gives a table value: P_f of Eq. 1.4 in N, Θ in radians."""
    radius = min(max(loading_radius_m, A4_RADIUS_GRID_M[0]), A4_RADIUS_GRID_M[-1])
    angle_deg = min(math.degrees(opening_rad), A4_ANGLE_GRID_DEG[-1])
    corners = [
        (h, r, angle)
        for h in thickness_corners_m(thickness_m)
        for r in bracket(radius, A4_RADIUS_GRID_M)
        for angle in bracket(angle_deg, A4_ANGLE_GRID_DEG)
    ]
    # corners coincide on the grid (h = 1.0 m has 1.2 m twice): each distinct one is evaluated once
    values = {corner: capacity_n(corner[0], corner[1], math.radians(corner[2])) for corner in set(corners)}
    return sum(values[corner] for corner in corners) / len(corners)
