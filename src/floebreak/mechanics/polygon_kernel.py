"""Compiled polygon queries for the failure modes (numba): fan probes in intact ice, ray length inside a floe.

Why not shapely: the bending fan (72 probe points per contact, physics-notes §2.5 step 3) and the crack's
indentation depth (thesis Alg. 5: the crack line behind the wedge origin) run at nearly every contact. As
GEOS calls wrapped in small-array numpy they cost ≈ 170 µs each, a fifth of a breaking run; compiled, a few
µs. Tests compare both against GEOS on random polygons (tests/mechanics/test_polygon_kernel.py).

A polygon is passed as `ring_arrays(geometry)`: the vertices of all its closed rings (as
`shapely.get_coordinates` lists them) and the ring start offsets. The even–odd rule over all rings counts
holes and several parts right. Points exactly on a boundary may go either way (GEOS counts them outside);
probes and rays of the failure modes are never placed there on purpose.
"""

from __future__ import annotations

import numba
import numpy as np
import shapely

from floebreak.mechanics.contact_kernel import _line_parameters


def ring_arrays(geometry: shapely.Geometry) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(x, y, offsets): the vertices of every closed ring of a polygon or multipolygon, and where each ring
    starts (offsets[-1] = number of vertices)."""
    xy = shapely.get_coordinates(geometry)
    return np.ascontiguousarray(xy[:, 0]), np.ascontiguousarray(xy[:, 1]), _ring_offsets(xy)


@numba.njit(cache=True, nogil=True)
def _ring_offsets(xy):
    """Ring starts in a list of closed rings: a ring ends at the first vertex equal to its start (valid
    polygons' rings do not touch themselves)."""
    offsets = [0]
    start = 0
    n = xy.shape[0]
    while start < n:
        end = start + 1
        while end < n and not (xy[end, 0] == xy[start, 0] and xy[end, 1] == xy[start, 1]):
            end += 1
        start = end + 1
        offsets.append(min(start, n))
    return np.array(offsets, dtype=np.int64)


@numba.njit(cache=True, nogil=True)
def _inside_rings(x, y, xs, ys, offsets):
    """Even–odd point-in-polygon test over all closed rings."""
    inside = False
    for r in range(len(offsets) - 1):
        for i in range(offsets[r], offsets[r + 1] - 1):
            yi, yj = ys[i], ys[i + 1]
            if (yi > y) != (yj > y):
                if x < (xs[i + 1] - xs[i]) * (y - yi) / (yj - yi) + xs[i]:
                    inside = not inside
    return inside


@numba.njit(cache=True, nogil=True)
def _pairwise_sum(values, n):
    """Σ values[:n] in numpy's summation order (eight partial sums for n ≤ 128), so that the fan's centre
    angle comes out as `np.sum` gives it."""
    if n < 8:
        total = 0.0
        for i in range(n):
            total += values[i]
        return total
    r = np.empty(8)
    for j in range(8):
        r[j] = values[j]
    i = 8
    while i < n - (n % 8):
        for j in range(8):
            r[j] += values[i + j]
        i += 8
    total = (r[0] + r[1]) + (r[2] + r[3]) + ((r[4] + r[5]) + (r[6] + r[7]))
    while i < n:
        total += values[i]
        i += 1
    return total


@numba.njit(cache=True, nogil=True)
def _block_nearest_normal(kept):
    """(first index, length) of the circular run of True values nearest to the fan normal, which lies between
    the last index and index 0 (ray k at (k + ½) φ from it). Distance of ray k: min(k + ½, n − k − ½) steps;
    the longer run on a tie, the first in circular order from the first False index on a full tie."""
    n = len(kept)
    n_kept = 0
    for k in range(n):
        n_kept += kept[k]
    if n_kept == 0:
        return 0, 0
    if n_kept == n:
        return 0, n
    if kept[0]:  # the run through index 0 is nearest (distance ½); it wraps round from the last False index
        first_false = 0
        while kept[first_false]:
            first_false += 1
        last_false = n - 1
        while kept[last_false]:
            last_false -= 1
        return (last_false + 1) % n, (n - 1 - last_false) + first_false
    start = 0
    while kept[start]:
        start += 1
    best_start, best_length, best_distance = -1, 0, np.inf
    s = 0
    while s < n:
        k = (start + s) % n
        if not kept[k]:
            s += 1
            continue
        run_start, distance, length = k, np.inf, 0
        while s < n and kept[(start + s) % n]:
            j = (start + s) % n
            distance = min(distance, min(j + 0.5, n - j - 0.5))
            length += 1
            s += 1
        if distance < best_distance or (distance == best_distance and length > best_length):
            best_start, best_length, best_distance = run_start, length, distance
    return best_start, best_length


@numba.njit(cache=True, nogil=True)
def intact_fan(xs, ys, offsets, hull_x, hull_y, hull_offsets, ox, oy, normal_angle, reach, n_rays):
    """(number of rays in the intact-ice block, centre angle) seen from O (physics-notes §2.5 step 3).

    Ray k points at normal_angle + (k + ½) φ, φ = 2π / n_rays; it counts when its probe at distance `reach`
    lies inside the floe and outside the hull H_u; the block is the run of counted rays nearest to the normal.
    """
    step = 2.0 * np.pi / n_rays
    angles = np.empty(n_rays)
    kept = np.zeros(n_rays, dtype=np.bool_)
    for k in range(n_rays):
        angles[k] = normal_angle + (k + 0.5) * step
        px, py = ox + reach * np.cos(angles[k]), oy + reach * np.sin(angles[k])
        kept[k] = _inside_rings(px, py, xs, ys, offsets) and not _inside_rings(
            px, py, hull_x, hull_y, hull_offsets
        )
    first, length = _block_nearest_normal(kept)
    if length == 0 or length == n_rays:
        return length, normal_angle
    sines, cosines = np.empty(length), np.empty(length)
    for i in range(length):
        angle = angles[(first + i) % n_rays]
        sines[i], cosines[i] = np.sin(angle), np.cos(angle)
    return length, np.arctan2(_pairwise_sum(sines, length), _pairwise_sum(cosines, length))


@numba.njit(cache=True, nogil=True)
def inside_length_from(xs, ys, offsets, ox, oy, ex, ey, connect_tolerance):
    """Length of the part of segment O → O + e inside the polygon that starts at O (within
    `connect_tolerance` of it); 0 if none. Parts that meet at a boundary point count as one (GEOS merges them
    too)."""
    n = offsets[-1]
    hits = np.empty(n + 2)
    hits[0], count = 0.0, 1
    for r in range(len(offsets) - 1):
        for i in range(offsets[r], offsets[r + 1] - 1):
            t, u, kind = _line_parameters(ox, oy, ex, ey, xs[i], ys[i], xs[i + 1] - xs[i], ys[i + 1] - ys[i])
            if kind == 0 and 0.0 < t < 1.0 and 0.0 <= u <= 1.0:
                hits[count] = t
                count += 1
    hits[count] = 1.0
    count += 1
    hits = np.sort(hits[:count])
    length_e = np.sqrt(ex * ex + ey * ey)
    inside_from, total = -1.0, 0.0
    for i in range(count - 1):
        a, b = hits[i], hits[i + 1]
        if b <= a:
            continue
        mid = 0.5 * (a + b)
        if _inside_rings(ox + mid * ex, oy + mid * ey, xs, ys, offsets):
            if inside_from < 0.0:
                if a * length_e > connect_tolerance:
                    return 0.0  # the first inside part starts away from O
                inside_from = a
            total = b - inside_from
        elif inside_from >= 0.0:
            break
    return total * length_e


@numba.njit(cache=True, nogil=True)
def _segment_gap(ax, ay, bx, by, cx, cy, dx, dy):
    """Distance between closed segments ab and cd (0 if they cross or touch)."""
    d1 = (dx - cx) * (ay - cy) - (dy - cy) * (ax - cx)
    d2 = (dx - cx) * (by - cy) - (dy - cy) * (bx - cx)
    d3 = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    d4 = (bx - ax) * (dy - ay) - (by - ay) * (dx - ax)
    if ((d1 > 0.0 and d2 < 0.0) or (d1 < 0.0 and d2 > 0.0)) and (
        (d3 > 0.0 and d4 < 0.0) or (d3 < 0.0 and d4 > 0.0)
    ):
        return 0.0  # a proper crossing
    return min(
        min(_point_segment_distance(ax, ay, cx, cy, dx, dy), _point_segment_distance(bx, by, cx, cy, dx, dy)),
        min(_point_segment_distance(cx, cy, ax, ay, bx, by), _point_segment_distance(dx, dy, ax, ay, bx, by)),
    )


@numba.njit(cache=True, nogil=True)
def _point_segment_distance(px, py, ax, ay, bx, by):
    ex, ey = bx - ax, by - ay
    length2 = ex * ex + ey * ey
    u = 0.0 if length2 == 0.0 else min(1.0, max(0.0, ((px - ax) * ex + (py - ay) * ey) / length2))
    qx, qy = ax + u * ex - px, ay + u * ey - py
    return np.sqrt(qx * qx + qy * qy)


@numba.njit(cache=True, nogil=True)
def _edge_x_at(y, ax, ay, bx, by, leftmost):
    """x of edge ab at height y (y within its range); a horizontal edge gives its left or right end."""
    if ay == by:
        return min(ax, bx) if leftmost else max(ax, bx)
    return ax + (y - ay) * (bx - ax) / (by - ay)


@numba.njit(cache=True, nogil=True)
def advance_to_contact(xs, ys, offsets, hull_x, hull_y, hull_offsets, clearance):
    """How far the hull can move in +x before it touches the polygon: the smallest t > 0 at which a vertex of
    one lies on an edge of the other (the first contact of two translating polygons is such an event).

    0 if they are not apart by more than `clearance` now (touching, overlapping, one inside the other); inf
    if the hull, moving in +x, never meets the polygon.
    """
    n, m = offsets[-1], hull_offsets[-1]
    p_x0, p_x1, p_y0, p_y1 = xs[:n].min(), xs[:n].max(), ys[:n].min(), ys[:n].max()
    h_x0, h_x1, h_y0, h_y1 = hull_x[:m].min(), hull_x[:m].max(), hull_y[:m].min(), hull_y[:m].max()
    if p_y0 > h_y1 + clearance or p_y1 < h_y0 - clearance or p_x1 < h_x0 - clearance:
        return np.inf  # beside the hull's path, or behind it
    if p_x0 <= h_x1 + clearance:  # the boxes meet: are the outlines apart by more than `clearance`?
        for r in range(len(offsets) - 1):
            for i in range(offsets[r], offsets[r + 1] - 1):
                ax, ay, bx, by = xs[i], ys[i], xs[i + 1], ys[i + 1]
                for s in range(len(hull_offsets) - 1):
                    for j in range(hull_offsets[s], hull_offsets[s + 1] - 1):
                        cx, cy, dx, dy = hull_x[j], hull_y[j], hull_x[j + 1], hull_y[j + 1]
                        if (
                            min(ax, bx) > max(cx, dx) + clearance
                            or max(ax, bx) < min(cx, dx) - clearance
                            or min(ay, by) > max(cy, dy) + clearance
                            or max(ay, by) < min(cy, dy) - clearance
                        ):
                            continue
                        if _segment_gap(ax, ay, bx, by, cx, cy, dx, dy) <= clearance:
                            return 0.0
        if _inside_rings(hull_x[0], hull_y[0], xs, ys, offsets) or _inside_rings(
            xs[0], ys[0], hull_x, hull_y, hull_offsets
        ):
            return 0.0
    # the hull's vertices moving onto the polygon's edges, and the polygon's vertices met by the hull's edges
    return min(
        _x_ray_travel(hull_x, hull_y, hull_offsets, xs, ys, offsets, 1.0),
        _x_ray_travel(xs, ys, offsets, hull_x, hull_y, hull_offsets, -1.0),
    )


@numba.njit(cache=True, nogil=True)
def _x_ray_travel(vx, vy, v_offsets, ex, ey, e_offsets, direction):
    """The smallest t > 0 at which a vertex of the first rings, moved by t along x (`direction` +1 or −1),
    lies on an edge of the second rings; inf if none does."""
    travel = np.inf
    for s in range(len(v_offsets) - 1):
        for j in range(v_offsets[s], v_offsets[s + 1] - 1):
            x, y = vx[j], vy[j]
            for r in range(len(e_offsets) - 1):
                for i in range(e_offsets[r], e_offsets[r + 1] - 1):
                    ay, by = ey[i], ey[i + 1]
                    if y < min(ay, by) or y > max(ay, by):
                        continue
                    t = direction * (_edge_x_at(y, ex[i], ay, ex[i + 1], by, direction > 0.0) - x)
                    if 0.0 < t < travel:
                        travel = t
    return travel


def compile_now() -> None:
    """Compile (or load from numba's on-disk cache) the kernels on a tiny input; see `compile_kernels`."""
    xs, ys, offsets = ring_arrays(shapely.box(0.0, 0.0, 1.0, 1.0))
    intact_fan(xs, ys, offsets, xs - 2.0, ys, offsets, 0.5, 0.5, 0.0, 0.2, 72)
    inside_length_from(xs, ys, offsets, 0.5, 0.5, -2.0, 0.0, 1e-6)
    advance_to_contact(xs, ys, offsets, xs - 2.0, ys, offsets, 1e-9)
