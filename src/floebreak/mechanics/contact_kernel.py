"""Compiled contact kernel: the geometry of `floebreak.mechanics.contact` for convex floes and a convex bow.

Why hand-written geometry next to shapely: a contact evaluation needs three GEOS overlays per floe (floe ∩
H_u, zone ∩ each panel footprint, waterline ∩ floe) and these cost ≈ 165 µs per floe, which capped the
stepping engine far below its goal (benchmarks/README.md). For the common case — a convex floe (circles,
Voronoi cells and every piece cut by a straight crack) against a convex upper hull with convex panel
footprints (both built-in hulls) — the same quantities follow from two textbook algorithms in compiled code,
several times faster (benchmarks/README.md):

- Sutherland–Hodgman clipping of the floe by the convex hull H_u gives the zone Z = F ∩ H_u (one zone: the
  intersection of two convex sets is connected), then Z clipped by each footprint Q_i gives A_h,i;
- Cyrus–Beck clipping of each upper-waterline segment by the convex floe gives the parts of the waterline
  inside F: the middle of the longest connected part is the zone centre ("midBow", thesis Alg. 5), and the
  clipped length of a panel's segment is the overlap used by the near-vertical guard.

A zone that does not reach the waterline (a piece already inside the hull) takes the waterline point nearest
to it. Anything else (a non-convex floe, a floe with holes, a non-convex user bow) is reported as "fallback"
and evaluated with shapely, so results never depend on the kernel's
limits. Tests compare both paths on random floes (tests/mechanics/test_contact_kernel.py).
"""

from __future__ import annotations

import numba
import numpy as np

NO_CONTACT, CONTACT, FALLBACK = 0, 1, 2

_CONVEX_TOLERANCE = 1e-9  # relative turn (cross product over edge lengths) still counted as straight


@numba.njit(cache=True, nogil=True)
def _signed_area(xs, ys, n):
    total = 0.0
    for i in range(n):
        j = i + 1 if i + 1 < n else 0
        total += xs[i] * ys[j] - xs[j] * ys[i]
    return 0.5 * total


@numba.njit(cache=True, nogil=True)
def _is_convex(xs, ys, n, orientation):
    """No vertex turns against `orientation` (+1 CCW, −1 CW) by more than the tolerance."""
    for i in range(n):
        h = i - 1 if i > 0 else n - 1
        j = i + 1 if i + 1 < n else 0
        ax, ay = xs[i] - xs[h], ys[i] - ys[h]
        bx, by = xs[j] - xs[i], ys[j] - ys[i]
        cross = ax * by - ay * bx
        scale = np.sqrt((ax * ax + ay * ay) * (bx * bx + by * by))
        if orientation * cross < -_CONVEX_TOLERANCE * scale:
            return False
    return True


@numba.njit(cache=True, nogil=True)
def _clip_convex(px, py, n, cx, cy, m, out_x, out_y, tmp_x, tmp_y):
    """Sutherland–Hodgman: polygon (px, py)[:n] clipped by the CCW convex polygon (cx, cy)[:m].

    Writes the result to out_x/out_y and returns its vertex count (0: empty). Scratch arrays must hold
    n + m vertices (a convex polygon gains at most one vertex per clipping half-plane).
    """
    k = n
    for i in range(n):
        out_x[i] = px[i]
        out_y[i] = py[i]
    for e in range(m):
        if k == 0:
            return 0
        ax, ay = cx[e], cy[e]
        f = e + 1 if e + 1 < m else 0
        ex, ey = cx[f] - ax, cy[f] - ay
        outside = False
        for i in range(k):
            if ex * (out_y[i] - ay) - ey * (out_x[i] - ax) < 0.0:
                outside = True
                break
        if not outside:  # the polygon lies wholly inside this half-plane (most hull edges): nothing to clip
            continue
        count = 0
        sx, sy = out_x[k - 1], out_y[k - 1]
        sd = ex * (sy - ay) - ey * (sx - ax)  # ≥ 0: inside (left of a CCW edge)
        for i in range(k):
            qx, qy = out_x[i], out_y[i]
            qd = ex * (qy - ay) - ey * (qx - ax)
            if qd >= 0.0:
                if sd < 0.0:
                    t = sd / (sd - qd)
                    tmp_x[count] = sx + t * (qx - sx)
                    tmp_y[count] = sy + t * (qy - sy)
                    count += 1
                tmp_x[count] = qx
                tmp_y[count] = qy
                count += 1
            elif sd >= 0.0:
                t = sd / (sd - qd)
                tmp_x[count] = sx + t * (qx - sx)
                tmp_y[count] = sy + t * (qy - sy)
                count += 1
            sx, sy, sd = qx, qy, qd
        for i in range(count):
            out_x[i] = tmp_x[i]
            out_y[i] = tmp_y[i]
        k = count
    return k


@numba.njit(cache=True, nogil=True)
def _segment_inside(x0, y0, x1, y1, px, py, n, orientation):
    """Cyrus–Beck: parameter interval [t_in, t_out] of segment (x0, y0)→(x1, y1) inside the convex polygon
    (px, py)[:n] of the given orientation (t_in ≥ t_out: no overlap), and whether the end point lies strictly
    inside (not on the boundary, where GEOS splits the line into two parts)."""
    t_in, t_out = 0.0, 1.0
    end_inside = True
    for i in range(n):
        j = i + 1 if i + 1 < n else 0
        ex, ey = px[j] - px[i], py[j] - py[i]
        d0 = orientation * (ex * (y0 - py[i]) - ey * (x0 - px[i]))
        d1 = orientation * (ex * (y1 - py[i]) - ey * (x1 - px[i]))
        if d1 <= 0.0:
            end_inside = False
        if d0 < 0.0 and d1 < 0.0:
            return 1.0, 0.0, False
        if d0 < 0.0:
            t_in = max(t_in, d0 / (d0 - d1))
        elif d1 < 0.0:
            t_out = min(t_out, d0 / (d0 - d1))
        if t_in >= t_out:
            return 1.0, 0.0, False
    return t_in, t_out, end_inside


@numba.njit(cache=True, nogil=True)
def _project(px, py, ax, ay, bx, by):
    """(squared distance, parameter t ∈ [0, 1]) of the point's projection on segment a→b."""
    ex, ey = bx - ax, by - ay
    length2 = ex * ex + ey * ey
    t = ((px - ax) * ex + (py - ay) * ey) / length2 if length2 > 0.0 else 0.0
    t = min(max(t, 0.0), 1.0)
    dx, dy = ax + t * ex - px, ay + t * ey - py
    return dx * dx + dy * dy, t


@numba.njit(cache=True, nogil=True)
def _nearest_on_waterline(zx, zy, k, waterline_xy, node_distance):
    """Arc length of the waterline point nearest to the polygon (zx, zy)[:k] that it does not meet: for two
    disjoint polylines the minimum distance is attained at a vertex of one of them."""
    best, best_s = np.inf, 0.0
    n_segments = waterline_xy.shape[0] - 1
    for p in range(n_segments):
        ax, ay = waterline_xy[p, 0], waterline_xy[p, 1]
        bx, by = waterline_xy[p + 1, 0], waterline_xy[p + 1, 1]
        length = node_distance[p + 1] - node_distance[p]
        for v in range(k):  # polygon vertices against waterline segments
            d2, t = _project(zx[v], zy[v], ax, ay, bx, by)
            if d2 < best:
                best, best_s = d2, node_distance[p] + t * length
    for p in range(n_segments + 1):  # waterline nodes against polygon edges
        for v in range(k):
            w = v + 1 if v + 1 < k else 0
            d2, t = _project(waterline_xy[p, 0], waterline_xy[p, 1], zx[v], zy[v], zx[w], zy[w])
            if d2 < best:
                best, best_s = d2, node_distance[p]
    return best_s


@numba.njit(cache=True, nogil=True)
def contact_batch(
    floe_x,
    floe_y,
    floe_start,
    floe_count,
    hull_x,
    hull_y,
    quad_x,
    quad_y,
    quad_bounds,
    waterline_xy,
    node_distance,
):
    """Contact geometry of many floes (bow frame) against one convex bow.

    floe_x, floe_y: all floes' open rings (no closing vertex), floe i at floe_start[i] : + floe_count[i].
    hull_x, hull_y: the CCW open ring of H_u. quad_x, quad_y: (n_panels, 4) CCW footprints Q_i; quad_bounds:
    their (x0, y0, x1, y1). Separate contiguous x and y arrays keep every call to the helpers on one array
    layout (one compiled specialisation each, so the first run compiles faster). waterline_xy: the upper
    waterline nodes (n_panels + 1); node_distance: arc length at each node.

    Returns per floe (status, A_u, centre x, centre y, centre panel, zone vertex start and count into
    zone_xy) and per row (floe, panel, A_h,i, length of the panel's waterline segment inside the floe),
    rows ordered by floe then panel.
    """
    n_floes = floe_start.shape[0]
    n_panels = quad_x.shape[0]
    m = hull_x.shape[0]
    status = np.zeros(n_floes, dtype=np.int8)
    a_u = np.zeros(n_floes)
    centre = np.zeros((n_floes, 2))
    centre_panel = np.zeros(n_floes, dtype=np.int64)
    zone_start = np.zeros(n_floes, dtype=np.int64)
    zone_count = np.zeros(n_floes, dtype=np.int64)
    zone_xy = np.empty((floe_x.shape[0] + n_floes * m, 2))
    row_floe = np.empty(n_floes * n_panels, dtype=np.int64)
    row_panel = np.empty(n_floes * n_panels, dtype=np.int64)
    row_a_h = np.empty(n_floes * n_panels)
    row_overlap = np.empty(n_floes * n_panels)
    max_n = 0
    for i in range(n_floes):
        max_n = max(max_n, floe_count[i])
    size = max_n + m + 8
    zx, zy = np.empty(size), np.empty(size)
    qx, qy = np.empty(size + 8), np.empty(size + 8)
    tx, ty = np.empty(size + 8), np.empty(size + 8)
    hx, hy = hull_x, hull_y
    hull_x0, hull_x1 = hx.min(), hx.max()
    hull_y0, hull_y1 = hy.min(), hy.max()
    seg_in = np.empty(n_panels)
    seg_out = np.empty(n_panels)
    n_rows = 0
    n_zone_xy = 0
    for i in range(n_floes):
        s, n = floe_start[i], floe_count[i]
        px = floe_x[s : s + n]
        py = floe_y[s : s + n]
        if px.max() <= hull_x0 or px.min() >= hull_x1 or py.max() <= hull_y0 or py.min() >= hull_y1:
            continue  # at most touching: no area in common
        orientation = 1.0 if _signed_area(px, py, n) > 0.0 else -1.0
        if not _is_convex(px, py, n, orientation):
            status[i] = FALLBACK
            continue
        k = _clip_convex(px, py, n, hx, hy, m, zx, zy, tx, ty)
        area = abs(_signed_area(zx, zy, k)) if k >= 3 else 0.0
        if not area > 0.0:
            continue
        # the waterline inside F: the longest connected part (first on a tie), in waterline order
        best_length, best_from, best_to = -1.0, 0.0, 0.0
        part_from, part_to, open_part = 0.0, 0.0, False
        f_x0, f_x1, f_y0, f_y1 = px.min(), px.max(), py.min(), py.max()
        for p in range(n_panels):
            x0, y0 = waterline_xy[p, 0], waterline_xy[p, 1]
            x1, y1 = waterline_xy[p + 1, 0], waterline_xy[p + 1, 1]
            if min(x0, x1) > f_x1 or max(x0, x1) < f_x0 or min(y0, y1) > f_y1 or max(y0, y1) < f_y0:
                t_in, t_out, end_inside = 1.0, 0.0, False  # bounding boxes apart: no overlap
            else:
                t_in, t_out, end_inside = _segment_inside(x0, y0, x1, y1, px, py, n, orientation)
            seg_in[p], seg_out[p] = t_in, t_out
            if t_in < t_out:
                length = node_distance[p + 1] - node_distance[p]
                d_in, d_out = node_distance[p] + t_in * length, node_distance[p] + t_out * length
                if open_part and t_in <= 0.0:
                    part_to = d_out
                else:
                    if open_part and part_to - part_from > best_length:
                        best_length, best_from, best_to = part_to - part_from, part_from, part_to
                    part_from, part_to, open_part = d_in, d_out, True
                if not end_inside:  # the part ends in this segment or on the floe's boundary at its end
                    if part_to - part_from > best_length:
                        best_length, best_from, best_to = part_to - part_from, part_from, part_to
                    open_part = False
            elif open_part:
                if part_to - part_from > best_length:
                    best_length, best_from, best_to = part_to - part_from, part_from, part_to
                open_part = False
        if open_part and part_to - part_from > best_length:
            best_length, best_from, best_to = part_to - part_from, part_from, part_to
        if best_length > 0.0:
            middle = 0.5 * (best_from + best_to)
        else:  # a zone that does not reach the waterline (a piece already inside the hull): nearest point
            middle = _nearest_on_waterline(zx, zy, k, waterline_xy, node_distance)
        status[i] = CONTACT
        a_u[i] = area
        panel = np.searchsorted(node_distance, middle) - 1  # as locating the point on the waterline
        panel = min(max(panel, 0), n_panels - 1)
        length = node_distance[panel + 1] - node_distance[panel]
        t = (middle - node_distance[panel]) / length if length > 0.0 else 0.0
        centre[i, 0] = waterline_xy[panel, 0] + t * (waterline_xy[panel + 1, 0] - waterline_xy[panel, 0])
        centre[i, 1] = waterline_xy[panel, 1] + t * (waterline_xy[panel + 1, 1] - waterline_xy[panel, 1])
        centre_panel[i] = panel
        zone_start[i], zone_count[i] = n_zone_xy, k
        for v in range(k):
            zone_xy[n_zone_xy + v, 0] = zx[v]
            zone_xy[n_zone_xy + v, 1] = zy[v]
        n_zone_xy += k
        z_x0, z_x1 = zx[:k].min(), zx[:k].max()
        z_y0, z_y1 = zy[:k].min(), zy[:k].max()
        for p in range(n_panels):
            if (
                quad_bounds[p, 0] > z_x1 or quad_bounds[p, 2] < z_x0
                or quad_bounds[p, 1] > z_y1 or quad_bounds[p, 3] < z_y0
            ):
                continue
            kq = _clip_convex(zx, zy, k, quad_x[p], quad_y[p], 4, qx, qy, tx, ty)
            a_h = abs(_signed_area(qx, qy, kq)) if kq >= 3 else 0.0
            if a_h > 0.0:
                row_floe[n_rows], row_panel[n_rows], row_a_h[n_rows] = i, p, a_h
                overlap = seg_out[p] - seg_in[p]
                seg_length = node_distance[p + 1] - node_distance[p]
                row_overlap[n_rows] = overlap * seg_length if overlap > 0.0 else 0.0
                n_rows += 1
    return (
        status,
        a_u,
        centre,
        centre_panel,
        zone_start,
        zone_count,
        zone_xy[:n_zone_xy],
        row_floe[:n_rows],
        row_panel[:n_rows],
        row_a_h[:n_rows],
        row_overlap[:n_rows],
    )


def ccw_ring(coords: np.ndarray) -> np.ndarray:
    """Open ring (closing vertex dropped) in counter-clockwise order."""
    ring = np.asarray(coords, dtype=float)
    if len(ring) > 1 and np.array_equal(ring[0], ring[-1]):
        ring = ring[:-1]
    x, y = ring[:, 0], ring[:, 1]
    signed = 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))
    return ring if signed > 0.0 else ring[::-1].copy()


def is_convex_ring(ring: np.ndarray) -> bool:
    """True if the CCW open ring turns left (or runs straight) at every vertex."""
    ring = np.ascontiguousarray(ring, dtype=float)
    return bool(_is_convex(ring[:, 0].copy(), ring[:, 1].copy(), len(ring), 1.0))


def compile_now() -> None:
    """Compile (or load from numba's on-disk cache) the kernel on a tiny input: `make` calls this at set-up so
    that the first run is not slowed by a one-off compilation of several seconds."""
    square_x, square_y = np.array([0.0, 1.0, 1.0, 0.0]), np.array([0.0, 0.0, 1.0, 1.0])
    quad_x, quad_y = square_x[None, :] - 0.5, square_y[None, :] - 0.5
    waterline = np.array([[-0.5, -0.5], [0.5, -0.5]])
    contact_batch(
        square_x, square_y, np.array([0]), np.array([4]), square_x - 0.5, square_y - 0.5, quad_x, quad_y,
        np.array([[-0.5, -0.5, 0.5, 0.5]]), waterline, np.array([0.0, 1.0]),
    )
    _is_convex(square_x, square_y, 4, 1.0)
