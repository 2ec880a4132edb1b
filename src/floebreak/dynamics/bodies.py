"""Rigid-body properties of a piece from its shapely polygon (field frame, metres): pure functions.

Mass ρ_i·A·h and the polar moment about the centroid from the polygon's vertices (exact for any simple
polygon, independent of the convex decomposition); convex parts for the collision shapes (Chipmunk takes
convex polygons only); the geometric integrals of the water drag (docs/model.md, "Ice motion").
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np
import shapely

_CONVEX_REL_TOL = 1e-12


@dataclass(frozen=True)
class BodyGeometry:
    """A piece in its body frame: the centroid at the origin, axes those of the field at angle 0."""

    centroid_xy_m: tuple[float, float]  # field frame, where the body was built
    area_m2: float
    polar_moment_m4: float  # ∫ r² dA about the centroid
    ring_xy_m: np.ndarray  # (n, 2) exterior ring, body frame, not closed, counter-clockwise
    convex_parts: tuple[np.ndarray, ...]  # body frame, each (k, 2) counter-clockwise
    yaw_form_m3: tuple[float, float]  # ∫ max(±s, 0)³ dl along the edge, s = (r × n)·ẑ: yaw form drag
    yaw_skin_m5: float  # ∫ r³ dA: yaw skin drag


def polygon_area_moment(ring_xy_m: np.ndarray) -> tuple[float, np.ndarray, float]:
    """(area, centroid, ∫r² dA about the centroid) of a simple polygon's ring (shoelace sums; the polar
    second moment J_o = 1/12 Σ c_i (x_i² + x_i x_j + x_j² + y_i² + y_i y_j + y_j²), c_i = x_i y_j − x_j y_i,
    moved to the centroid by the parallel-axis theorem). The sums run in a frame centred on the ring's box:
    in field coordinates (x up to 1e5 m on a long transit) J_o and A·|c|² are ~1e10 times J of a small piece,
    and their difference lost every digit (negative moments, a Chipmunk abort at 100 km)."""
    origin = (ring_xy_m.min(axis=0) + ring_xy_m.max(axis=0)) / 2.0
    local = ring_xy_m - origin
    x, y = local[:, 0], local[:, 1]
    xj, yj = np.roll(x, -1), np.roll(y, -1)
    cross = x * yj - xj * y
    area = _exact_sum(cross) / 2.0
    cx = _exact_sum((x + xj) * cross) / (6.0 * area)
    cy = _exact_sum((y + yj) * cross) / (6.0 * area)
    j_origin = _exact_sum(cross * (x * x + x * xj + xj * xj + y * y + y * yj + yj * yj)) / 12.0
    centroid = np.array([cx, cy]) + origin
    return abs(area), centroid, abs(j_origin) - abs(area) * (cx * cx + cy * cy)


def _exact_sum(terms: np.ndarray) -> float:
    """The correctly rounded sum (`math.fsum`): independent of the terms' order, so a mirrored polygon (its
    ring reversed, the same terms in another order, some negated) gets exactly the mirrored centroid and
    the same mass and moment (docs/model.md, "Determinism and symmetry")."""
    return math.fsum(terms.tolist())


def _ccw_ring(polygon: shapely.Polygon) -> np.ndarray:
    ring = np.asarray(shapely.orient_polygons(polygon).exterior.coords)[:-1]
    return ring.astype(float)


def _is_convex(polygon: shapely.Polygon) -> bool:
    return polygon.convex_hull.area - polygon.area <= _CONVEX_REL_TOL * polygon.area


def convex_parts(polygon: shapely.Polygon) -> list[shapely.Polygon]:
    """Convex polygons whose union is `polygon` exactly: the polygon itself if convex, else its constrained
    Delaunay triangles merged across shared edges while the merge stays convex (Hertel & Mehlhorn 1983:
    removing a diagonal keeps a part convex iff the angles at its two ends stay ≤ 180°). Deterministic:
    parts grown in GEOS's triangle order, each across its edges in ring order."""
    if _is_convex(polygon):
        return [polygon]
    triangles = shapely.get_coordinates(shapely.constrained_delaunay_triangles(polygon)).reshape(-1, 4, 2)
    points: dict[tuple[float, float], int] = {}
    cycles: list[list[int]] = []
    for tri in triangles[:, :3].tolist():
        ids = [points.setdefault((x, y), len(points)) for x, y in tri]
        (ax, ay), (bx, by), (cx, cy) = tri
        cycles.append(ids if (bx - ax) * (cy - ay) - (by - ay) * (cx - ax) > 0.0 else ids[::-1])
    xy = np.array(list(points), dtype=float)
    parts = [xy[cycle] for cycle in _merge_convex(cycles, xy.tolist())]
    return [shapely.Polygon(part) for part in parts]


def _merge_convex(cycles: list[list[int]], xy: list[list[float]]) -> list[list[int]]:
    """Counter-clockwise vertex cycles sharing edges, merged greedily while the merge stays convex."""
    owner = {(c[i], c[(i + 1) % len(c)]): k for k, c in enumerate(cycles) for i in range(len(c))}
    alive = [True] * len(cycles)
    for k, cycle in enumerate(cycles):
        if not alive[k]:
            continue
        i = 0
        while i < len(cycle):
            u, v = cycle[i], cycle[(i + 1) % len(cycle)]
            other = owner.get((v, u))
            if other is None or other == k or not _convex_merge(cycle, cycles[other], i, u, v, xy):
                i += 1
                continue
            merged = _joined(cycle, cycles[other], i, u)
            alive[other] = False
            for j in range(len(merged)):
                owner[(merged[j], merged[(j + 1) % len(merged)])] = k
            del owner[(u, v)], owner[(v, u)]
            cycles[k] = cycle = merged
            i = 0
    return [c for c, keep in zip(cycles, alive, strict=True) if keep]


def _joined(a: list[int], b: list[int], i: int, u: int) -> list[int]:
    """Cycle `a` (edge u → v at position i) and cycle `b` (edge v → u) without their shared edge."""
    j = b.index(u)
    after_v = a[i + 1 :] + a[: i + 1]  # v … u along a
    along_b = b[j:] + b[:j]  # u … v along b
    return after_v[:-1] + along_b[:-1]  # v … (before u) along a, then u … (before v) along b


def _convex_merge(a: list[int], b: list[int], i: int, u: int, v: int, xy: list[list[float]]) -> bool:
    """Whether removing the shared edge u → v (of `a`, at position i) keeps a convex union: a left turn
    (or straight) at u from a's vertex before it to b's after it, and at v from b's before to a's after."""
    j = b.index(u)
    a_before_u, a_after_v = a[i - 1], a[(i + 2) % len(a)]
    b_after_u, b_before_v = b[(j + 1) % len(b)], b[j - 2]
    return (
        _turn(xy[a_before_u], xy[u], xy[b_after_u]) >= 0.0
        and _turn(xy[b_before_v], xy[v], xy[a_after_v]) >= 0.0
    )


def _turn(p: list[float], q: list[float], r: list[float]) -> float:
    return (q[0] - p[0]) * (r[1] - q[1]) - (q[1] - p[1]) * (r[0] - q[0])


def _yaw_form_integrals(ring: np.ndarray) -> tuple[float, float]:
    """∫ max(s, 0)³ dl and ∫ max(−s, 0)³ dl over the edges, s = (r × n)·ẑ: the normal speed of the edge per
    unit yaw rate. s is linear along an edge (s0 → s1 over length L), so the integral is exact:
    L·(F(s1) − F(s0))/(s1 − s0) with F(σ) = max(σ, 0)⁴/4 (L·max(s0, 0)³ where s1 = s0). An edge of length 0
    (a repeated vertex) adds exactly 0: its normal is taken as (0, 0) rather than 0/0."""
    a, b = ring, np.roll(ring, -1, axis=0)
    edge = b - a
    length = np.hypot(edge[:, 0], edge[:, 1])
    divisor = np.where(length > 0.0, length, 1.0)
    nx, ny = edge[:, 1] / divisor, -edge[:, 0] / divisor  # outward for a counter-clockwise ring
    s0 = a[:, 0] * ny - a[:, 1] * nx
    s1 = b[:, 0] * ny - b[:, 1] * nx

    def positive_part(u0: np.ndarray, u1: np.ndarray) -> float:
        du = u1 - u0
        flat = np.abs(du) <= 1e-12 * np.maximum(np.abs(u0), 1e-300)
        f = (np.maximum(u1, 0.0) ** 4 - np.maximum(u0, 0.0) ** 4) / 4.0
        return _exact_sum(
            np.where(flat, length * np.maximum(u0, 0.0) ** 3, length * f / np.where(flat, 1.0, du))
        )

    return positive_part(s0, s1), positive_part(-s0, -s1)


# Dunavant's 7-point rule (degree 5) on the reference triangle: barycentric points and weights
_A1, _B1, _A2, _B2 = 0.059715871789770, 0.470142064105115, 0.797426985353087, 0.101286507323456
_RULE_POINTS = np.array(
    [[1 / 3, 1 / 3], [_A1, _B1], [_B1, _A1], [_B1, _B1], [_A2, _B2], [_B2, _A2], [_B2, _B2]]
)  # (u, v); the third coordinate is 1 − u − v
_RULE_WEIGHTS = np.array([0.225] + [0.132394152788506] * 3 + [0.125939180544827] * 3)
_SPLIT = 4  # each fan triangle split into _SPLIT² sub-triangles


def _sub_triangle_points() -> np.ndarray:
    """The rule's points in fan coordinates (u, v) of each of the _SPLIT² sub-triangles: (_SPLIT², 7, 2)."""
    n = _SPLIT
    up = [((i, j), (i + 1, j), (i, j + 1)) for i in range(n) for j in range(n - i)]
    down = [((i + 1, j), (i + 1, j + 1), (i, j + 1)) for i in range(n) for j in range(n - i - 1)]
    corners = np.array(up + down, dtype=float) / n  # (_SPLIT², 3, 2)
    c0, c1, c2 = corners[:, None, 0], corners[:, None, 1], corners[:, None, 2]
    return c0 + _RULE_POINTS[None, :, :1] * (c1 - c0) + _RULE_POINTS[None, :, 1:] * (c2 - c0)


_SUB_POINTS = _sub_triangle_points()


def _yaw_skin_integral(ring: np.ndarray) -> float:
    """∫ |r|³ dA over the polygon about its centroid: the signed fan of triangles (centroid, a_i, a_i+1),
    each split into 16 sub-triangles integrated by Dunavant's degree-5 rule (all points summed exactly: the
    same value for the mirrored, reversed ring)."""
    return abs(_yaw_skin_kernel(np.ascontiguousarray(ring, dtype=np.float64), _SUB_POINTS, _RULE_WEIGHTS))


@numba.njit(cache=True, nogil=True)
def _yaw_skin_kernel(ring, uv, weights):
    """The fan's terms (signed area a_i × b_i / 2 / _SPLIT² × weight × |point|³, the point u·a_i + v·b_i)
    and their correctly rounded sum, in one compiled pass (the same arithmetic as numpy's broadcast, and
    the same sum as `math.fsum`)."""
    n, m, q = len(ring), uv.shape[0], uv.shape[1]
    terms = np.empty(n * m * q)
    split2 = float(_SPLIT * _SPLIT)
    t = 0
    for i in range(n):
        j = i + 1 if i + 1 < n else 0
        ax, ay, bx, by = ring[i, 0], ring[i, 1], ring[j, 0], ring[j, 1]
        area = (ax * by - ay * bx) / 2.0
        for k in range(m):
            for p in range(q):
                u, v = uv[k, p, 0], uv[k, p, 1]
                radius = math.hypot(u * ax + v * bx, u * ay + v * by)
                terms[t] = area / split2 * weights[p] * math.pow(radius, 3.0)
                t += 1
    return _fsum(terms)


@numba.njit(cache=True, nogil=True)
def _fsum(terms):
    """The correctly rounded sum of finite `terms`: CPython's `math.fsum` (Shewchuk's partials, then the
    round-half-even correction of the last partials), for compiled callers."""
    partials = np.empty(len(terms) + 1)
    n = 0
    for k in range(len(terms)):
        x = terms[k]
        i = 0
        for j in range(n):
            y = partials[j]
            if abs(x) < abs(y):
                x, y = y, x
            hi = x + y
            lo = y - (hi - x)
            if lo != 0.0:
                partials[i] = lo
                i += 1
            x = hi
        n = i
        if x != 0.0:
            partials[n] = x
            n += 1
    return _round_partials(partials, n)


@numba.njit(cache=True, nogil=True)
def _round_partials(partials, n):
    """The sum of the non-overlapping `partials[:n]` (increasing magnitude), correctly rounded."""
    hi, lo = 0.0, 0.0
    if n == 0:
        return hi
    n -= 1
    hi = partials[n]
    while n > 0:
        x = hi
        n -= 1
        y = partials[n]
        hi = x + y
        lo = y - (hi - x)
        if lo != 0.0:
            break
    if n > 0 and ((lo < 0.0 and partials[n - 1] < 0.0) or (lo > 0.0 and partials[n - 1] > 0.0)):
        y = lo * 2.0
        x = hi + y
        if y == x - hi:
            hi = x
    return hi


def compile_now() -> None:
    """Compile the body kernels (or load them from numba's cache) ahead of a run."""
    _yaw_skin_integral(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]))


def centroid_and_radius(polygon: shapely.Polygon) -> tuple[tuple[float, float], float]:
    """The centroid of `polygon` (field frame) and its largest vertex distance from it, as `body_geometry`
    and the engine compute them (the same arithmetic, without the convex parts and drag integrals)."""
    ring = _ccw_ring(polygon)
    _, centroid, _ = polygon_area_moment(ring)
    local = ring - centroid
    return (float(centroid[0]), float(centroid[1])), float(np.hypot(local[:, 0], local[:, 1]).max())


def body_geometry(polygon: shapely.Polygon) -> BodyGeometry:
    """The body-frame geometry of `polygon` (a valid polygon without holes; field frame)."""
    ring_field = _ccw_ring(polygon)
    area, centroid, polar = polygon_area_moment(ring_field)
    ring = _without_repeats(ring_field - centroid)
    local = shapely.Polygon(ring)
    parts = tuple(_ccw_ring(p) for p in convex_parts(local))
    return BodyGeometry(
        (float(centroid[0]), float(centroid[1])),
        area,
        polar,
        ring,
        parts,
        _yaw_form_integrals(ring),
        _yaw_skin_integral(ring),
    )


def _without_repeats(ring_xy_m: np.ndarray) -> np.ndarray:
    """The ring without each vertex equal to the one before it (cyclically). A crack that ends within
    round-off of a vertex leaves two vertices ~1e-16 m apart, which the shift to the centroid can round to
    one point: an edge of length 0 in the body frame."""
    keep = np.any(ring_xy_m != np.roll(ring_xy_m, 1, axis=0), axis=1)
    return ring_xy_m[keep]


def projected_width_m(ring_xy_m: np.ndarray, direction_xy: np.ndarray) -> float:
    """Width of the polygon's shadow across the unit `direction_xy` (both in the same frame): max − min of
    the vertices' projection on the perpendicular; exact for any polygon (its shadow is one interval)."""
    p = ring_xy_m[:, 1] * direction_xy[0] - ring_xy_m[:, 0] * direction_xy[1]
    return float(p.max() - p.min())
