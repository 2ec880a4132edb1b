"""Compiled contact kernel: the geometry of `floebreak.mechanics.contact` for a convex bow, in numba.

Why hand-written geometry next to shapely: a contact evaluation needs three GEOS overlays per floe (floe ∩
H_u, zone ∩ each panel footprint, waterline ∩ floe) at ≈ 165 µs per floe, which capped the stepping engine
far below its goal (benchmarks/README.md). Against a convex upper hull H_u with convex panel footprints Q_i
(both built-in hulls), the same quantities follow from textbook algorithms in compiled code, several times
faster:

- Sutherland–Hodgman clipping of the floe F by H_u gives A_u = area(F ∩ H_u), then that clipped polygon
  clipped by each Q_i gives A_h,i. For a non-convex F the clipped outline may carry zero-width bridges, but
  its signed area is still exact.
- Zones: F ∩ H_u is one zone if F is convex (two convex sets meet in a connected set), or if ∂F and ∂H_u
  cross at most twice (one arc of ∂F inside H_u closes with one arc of ∂H_u inside F).
- Each upper-waterline segment is cut where it meets ∂F, and the pieces inside F (even–odd test) form the
  parts of waterline ∩ F, split at ∂F as GEOS splits them (parts that only touch there joined): the middle
  of the longest part (of the span of tied ones) is the zone centre ("midBow", thesis Alg. 5), and the
  length inside F per panel is the overlap of the near-vertical guard.
- A convex zone that does not reach the waterline (a piece already inside the hull) takes the waterline
  point nearest to it.

Anything else — more than one possible zone, boundaries that touch or run along each other, a non-convex
zone clear of the waterline, a floe with holes, a non-convex user bow — is reported as "fallback". GEOS then
separates the zones, and `zone_rows` (below) gives their panel rows and centres with the same helpers
(GEOS throughout for holes and degenerate cases), so results never depend on the kernel's limits. Tests
compare both paths on random convex, non-convex and two-zone floes (tests/mechanics/test_contact_kernel.py).

Forces (`zone_forces`, `panel_forces`): A_l, contact areas and the Eq. 7–10 forces of all zones of a batch.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from floebreak.mechanics.classify import box_extents

NO_CONTACT, CONTACT, FALLBACK = 0, 1, 2

_CONVEX_TOLERANCE = 1e-9  # relative turn (cross product over edge lengths) still counted as straight
# a zone centre this close [m] to a waterline node lies on the node: a mirror-symmetric floe on the centreline
# has its centre on the stem up to the rounding of the arc lengths (≈ 1e-14 m)
ON_NODE_M = 1e-9


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
def _clip_convex(px, py, n, cx, cy, m, out_x, out_y, tmp_x, tmp_y, capacity):
    """Sutherland–Hodgman: polygon (px, py)[:n] clipped by the CCW convex polygon (cx, cy)[:m].

    Writes the result to out_x/out_y and returns its vertex count (0: empty; −1: more than `capacity`
    vertices). The subject may be non-convex: the output then may contain zero-width bridges along the clip
    edges, but its signed area is still that of the intersection.
    """
    k = n
    for i in range(n):
        out_x[i] = px[i]
        out_y[i] = py[i]
    # the subject's bounding box holds every clipped polygon too: a half-plane that holds its four corners
    # cuts nothing (most hull edges for a floe near the bow) and is skipped after four tests
    x0, x1, y0, y1 = px[:n].min(), px[:n].max(), py[:n].min(), py[:n].max()
    for e in range(m):
        if k == 0:
            return 0
        ax, ay = cx[e], cy[e]
        f = e + 1 if e + 1 < m else 0
        ex, ey = cx[f] - ax, cy[f] - ay
        if (
            ex * (y0 - ay) - ey * (x0 - ax) >= 0.0
            and ex * (y0 - ay) - ey * (x1 - ax) >= 0.0
            and ex * (y1 - ay) - ey * (x0 - ax) >= 0.0
            and ex * (y1 - ay) - ey * (x1 - ax) >= 0.0
        ):
            continue
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
            if count + 2 > capacity:
                return -1
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
def _line_parameters(x0, y0, dx, dy, ax, ay, ex, ey):
    """Where the lines of segments (x0, y0) + t (dx, dy) and (ax, ay) + u (ex, ey) meet: (t, u, kind), kind
    0 = crossing lines (t, u valid), 1 = parallel, 2 = collinear."""
    wx, wy = ax - x0, ay - y0
    denom = dx * ey - dy * ex
    w_cross_d = wx * dy - wy * dx
    if denom == 0.0:
        return 0.0, 0.0, 2 if w_cross_d == 0.0 else 1
    return (wx * ey - wy * ex) / denom, w_cross_d / denom, 0


@numba.njit(cache=True, nogil=True)
def _boundary_hits(x0, y0, x1, y1, px, py, n, hits):
    """Parameters t ∈ [0, 1] where segment (x0, y0)→(x1, y1) meets the boundary of polygon (px, py)[:n],
    sorted into `hits`; returns their count, or −1 if the segment runs along a boundary edge."""
    dx, dy = x1 - x0, y1 - y0
    s_x0, s_x1, s_y0, s_y1 = min(x0, x1), max(x0, x1), min(y0, y1), max(y0, y1)
    count = 0
    for i in range(n):
        j = i + 1 if i + 1 < n else 0
        if (
            min(px[i], px[j]) > s_x1 or max(px[i], px[j]) < s_x0
            or min(py[i], py[j]) > s_y1 or max(py[i], py[j]) < s_y0
        ):
            continue  # boxes apart: no hit, no overlap
        t, u, kind = _line_parameters(x0, y0, dx, dy, px[i], py[i], px[j] - px[i], py[j] - py[i])
        if kind == 2:  # collinear: an overlap along the boundary is left to GEOS
            d2 = dx * dx + dy * dy
            ta = ((px[i] - x0) * dx + (py[i] - y0) * dy) / d2
            tb = ((px[j] - x0) * dx + (py[j] - y0) * dy) / d2
            if max(min(ta, tb), 0.0) < min(max(ta, tb), 1.0):
                return -1
        elif kind == 0 and 0.0 <= t <= 1.0 and 0.0 <= u <= 1.0:
            k = count  # insertion sort: a handful of hits per segment
            while k > 0 and hits[k - 1] > t:
                hits[k] = hits[k - 1]
                k -= 1
            hits[k] = t
            count += 1
    return count


@numba.njit(cache=True, nogil=True)
def _inside(x, y, px, py, n):
    """Even–odd point-in-polygon test."""
    inside = False
    j = n - 1
    for i in range(n):
        if (py[i] > y) != (py[j] > y):
            if x < (px[j] - px[i]) * (y - py[i]) / (py[j] - py[i]) + px[i]:
                inside = not inside
        j = i
    return inside


@numba.njit(cache=True, nogil=True)
def _crossings(px, py, n, hx, hy, m):
    """Proper crossings between the boundaries of two polygons; −1 if they touch or overlap anywhere (a
    degenerate contact whose zones are left to GEOS)."""
    count = 0
    h_x0, h_x1, h_y0, h_y1 = hx.min(), hx.max(), hy.min(), hy.max()
    for i in range(n):
        j = i + 1 if i + 1 < n else 0
        x0, y0, x1, y1 = px[i], py[i], px[j], py[j]
        if min(x0, x1) > h_x1 or max(x0, x1) < h_x0 or min(y0, y1) > h_y1 or max(y0, y1) < h_y0:
            continue
        dx, dy = x1 - x0, y1 - y0
        e_x0, e_x1, e_y0, e_y1 = min(x0, x1), max(x0, x1), min(y0, y1), max(y0, y1)
        for a in range(m):
            b = a + 1 if a + 1 < m else 0
            if (
                min(hx[a], hx[b]) > e_x1 or max(hx[a], hx[b]) < e_x0
                or min(hy[a], hy[b]) > e_y1 or max(hy[a], hy[b]) < e_y0
            ):
                continue  # the two edges' boxes are apart: they cannot meet
            t, u, kind = _line_parameters(x0, y0, dx, dy, hx[a], hy[a], hx[b] - hx[a], hy[b] - hy[a])
            if kind == 2:
                return -1
            if kind == 1:
                continue
            if 0.0 < t < 1.0 and 0.0 < u < 1.0:
                count += 1
            elif 0.0 <= t <= 1.0 and 0.0 <= u <= 1.0:
                return -1
    return count


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
    disjoint polylines the minimum distance is attained at a vertex of one of them. Segments whose bounding
    box is already farther than the best distance found are skipped."""
    best, best_s = np.inf, 0.0
    z_x0, z_x1, z_y0, z_y1 = zx[:k].min(), zx[:k].max(), zy[:k].min(), zy[:k].max()
    n_segments = waterline_xy.shape[0] - 1
    for p in range(n_segments):
        ax, ay = waterline_xy[p, 0], waterline_xy[p, 1]
        bx, by = waterline_xy[p + 1, 0], waterline_xy[p + 1, 1]
        gap_x = max(min(ax, bx) - z_x1, z_x0 - max(ax, bx), 0.0)
        gap_y = max(min(ay, by) - z_y1, z_y0 - max(ay, by), 0.0)
        if gap_x * gap_x + gap_y * gap_y >= best:
            continue
        length = node_distance[p + 1] - node_distance[p]
        for v in range(k):  # polygon vertices against this waterline segment
            d2, t = _project(zx[v], zy[v], ax, ay, bx, by)
            if d2 < best:
                best, best_s = d2, node_distance[p] + t * length
        for node in (p, p + 1):  # its end nodes against the polygon's edges
            for v in range(k):
                w = v + 1 if v + 1 < k else 0
                d2, t = _project(waterline_xy[node, 0], waterline_xy[node, 1], zx[v], zy[v], zx[w], zy[w])
                if d2 < best:
                    best, best_s = d2, node_distance[node]
    return best_s


@numba.njit(cache=True, nogil=True)
def _ring_layout(floe_index, n_floes):
    """Start and length of each floe's open ring (closing vertex dropped) in a vertex list grouped by floe,
    and the longest ring's length."""
    floe_start = np.zeros(n_floes, dtype=np.int64)
    floe_count = np.zeros(n_floes, dtype=np.int64)
    for v in range(floe_index.shape[0] - 1, -1, -1):
        floe_start[floe_index[v]] = v
        floe_count[floe_index[v]] += 1
    max_n = 0
    for i in range(n_floes):
        floe_count[i] = max(floe_count[i] - 1, 0)
        max_n = max(max_n, floe_count[i])
    return floe_start, floe_count, max_n


@numba.njit(cache=True, nogil=True)
def _waterline_parts(px, py, n, waterline_xy, node_distance, hits, seg_overlap, part_from, part_to):
    """The upper waterline inside polygon (px, py)[:n], split where it crosses the polygon's boundary (as GEOS
    splits waterline ∩ F, with the parts that only touch there joined, `_merge_touching`): the parts as
    arc-length intervals in waterline order (`part_from`, `part_to`), and per waterline segment the length
    inside (`seg_overlap`). Returns the number of parts, or −1 if the waterline runs along the boundary
    somewhere."""
    n_panels = waterline_xy.shape[0] - 1
    n_parts = 0
    start, end, open_part = 0.0, 0.0, False
    f_x0, f_x1, f_y0, f_y1 = px[:n].min(), px[:n].max(), py[:n].min(), py[:n].max()
    for p in range(n_panels):
        seg_overlap[p] = 0.0
        x0, y0 = waterline_xy[p, 0], waterline_xy[p, 1]
        x1, y1 = waterline_xy[p + 1, 0], waterline_xy[p + 1, 1]
        if min(x0, x1) > f_x1 or max(x0, x1) < f_x0 or min(y0, y1) > f_y1 or max(y0, y1) < f_y0:
            if open_part:  # bounding boxes apart: no overlap
                part_from[n_parts], part_to[n_parts] = start, end
                n_parts += 1
                open_part = False
            continue
        n_hits = _boundary_hits(x0, y0, x1, y1, px, py, n, hits)
        if n_hits < 0:
            return -1
        seg_length = node_distance[p + 1] - node_distance[p]
        for j in range(n_hits + 1):
            a = hits[j - 1] if j > 0 else 0.0
            b = hits[j] if j < n_hits else 1.0
            if not b > a:
                continue
            t = 0.5 * (a + b)
            if not _inside(x0 + t * (x1 - x0), y0 + t * (y1 - y0), px, py, n):
                if open_part:
                    part_from[n_parts], part_to[n_parts] = start, end
                    n_parts += 1
                    open_part = False
                continue
            seg_overlap[p] += (b - a) * seg_length
            d_a, d_b = node_distance[p] + a * seg_length, node_distance[p] + b * seg_length
            if open_part and j == 0:  # goes on through the node from the previous segment
                end = d_b
            else:
                if open_part:
                    part_from[n_parts], part_to[n_parts] = start, end
                    n_parts += 1
                start, end, open_part = d_a, d_b, True
            if j < n_hits:  # ends on F's boundary (inside this segment or exactly at its end node)
                part_from[n_parts], part_to[n_parts] = start, end
                n_parts += 1
                open_part = False
    if open_part:
        part_from[n_parts], part_to[n_parts] = start, end
        n_parts += 1
    return _merge_touching(part_from, part_to, n_parts)


@numba.njit(cache=True, nogil=True)
def _merge_touching(part_from, part_to, n_parts):
    """Join the parts (in waterline order) that meet at a point of ∂F, within `ON_NODE_M`: a vertex of F on
    the waterline with ice on both sides (the stem reaching a floe's far corner) splits waterline ∩ F but
    not the line of contact. Kept apart, the two halves tie and the first (port) one became the centre, so
    a symmetric floe was loaded off the centreline. Returns the number of parts."""
    if n_parts == 0:
        return 0
    m = 0
    for q in range(1, n_parts):
        if part_from[q] - part_to[m] <= ON_NODE_M:
            part_to[m] = part_to[q]
        else:
            m += 1
            part_from[m], part_to[m] = part_from[q], part_to[q]
    return m + 1


@numba.njit(cache=True, nogil=True)
def _waterline_point(distance, waterline_xy, node_distance):
    """(x, y, panel) of the upper waterline at arc length `distance` (the panel as locating the point on the
    waterline gives it)."""
    n_panels = waterline_xy.shape[0] - 1
    panel = np.searchsorted(node_distance, distance) - 1
    panel = min(max(panel, 0), n_panels - 1)
    length = node_distance[panel + 1] - node_distance[panel]
    t = (distance - node_distance[panel]) / length if length > 0.0 else 0.0
    x = waterline_xy[panel, 0] + t * (waterline_xy[panel + 1, 0] - waterline_xy[panel, 0])
    y = waterline_xy[panel, 1] + t * (waterline_xy[panel + 1, 1] - waterline_xy[panel, 1])
    return x, y, panel


@numba.njit(cache=True, nogil=True)
def centre_normal(x, y, panel, waterline_xy, panel_normals):
    """Outward normal of the waterline at its point (x, y) on `panel`: the panel's normal as given, or, at a
    node i between two panels (within `ON_NODE_M`), the node normal of thesis Eq. 20, (y_(i−1) − y_(i+1),
    x_(i+1) − x_(i−1)) normalised, pointing outwards. Which panel a node's arc length falls on is decided by
    rounding; the node normal takes neither side's panel — at the stem of a symmetric bow it is the
    centreline, so a floe centred on it is classified and cracked mirror-symmetrically."""
    n_panels = panel_normals.shape[0]
    node = -1
    for i in (panel + 1, panel):
        if node < 0 and 0 < i < n_panels:  # an interior node: both neighbours exist
            dx, dy = waterline_xy[i, 0] - x, waterline_xy[i, 1] - y
            if dx * dx + dy * dy <= ON_NODE_M * ON_NODE_M:
                node = i
    if node < 0:
        return panel_normals[panel, 0], panel_normals[panel, 1]
    ux = waterline_xy[node - 1, 1] - waterline_xy[node + 1, 1]
    uy = waterline_xy[node + 1, 0] - waterline_xy[node - 1, 0]
    norm = np.hypot(ux, uy)
    if ux * panel_normals[panel, 0] + uy * panel_normals[panel, 1] < 0.0:
        norm = -norm
    return ux / norm, uy / norm


@numba.njit(cache=True, nogil=True)
def centre_normals(centre_xy, centre_panel, waterline_xy, panel_normals):
    """`centre_normal` of every zone centre: an (n, 2) array."""
    out = np.empty((centre_panel.shape[0], 2))
    for z in range(centre_panel.shape[0]):
        out[z, 0], out[z, 1] = centre_normal(
            centre_xy[z, 0], centre_xy[z, 1], centre_panel[z], waterline_xy, panel_normals
        )
    return out


@numba.njit(cache=True, nogil=True)
def _panel_rows(zx, zy, k, zone, quad_x, quad_y, quad_bounds, min_overlap, scratch, rows, n_rows):
    """Append the rows (zone, panel, A_h,i = area(Z ∩ Q_i) > min_overlap) of zone polygon (zx, zy)[:k] to
    `rows` (row_zone, row_panel, row_a_h) from index n_rows; the new row count, or −1 if the scratch space
    (qx, qy, tx, ty, capacity) ran out. Z may be non-convex: the clipped outline's signed area is exact."""
    qx, qy, tx, ty = scratch
    capacity = qx.shape[0]
    row_zone, row_panel, row_a_h = rows
    z_x0, z_x1 = zx[:k].min(), zx[:k].max()
    z_y0, z_y1 = zy[:k].min(), zy[:k].max()
    for p in range(quad_x.shape[0]):
        if (
            quad_bounds[p, 0] > z_x1 or quad_bounds[p, 2] < z_x0
            or quad_bounds[p, 1] > z_y1 or quad_bounds[p, 3] < z_y0
        ):
            continue
        kq = _clip_convex(zx, zy, k, quad_x[p], quad_y[p], 4, qx, qy, tx, ty, capacity)
        if kq < 0:
            return -1
        a_h = abs(_signed_area(qx, qy, kq)) if kq >= 3 else 0.0
        if a_h > min_overlap:
            row_zone[n_rows], row_panel[n_rows], row_a_h[n_rows] = zone, p, a_h
            n_rows += 1
    return n_rows


@numba.njit(cache=True, nogil=True)
def contact_batch(
    floe_coords,
    floe_index,
    n_floes,
    hull_x,
    hull_y,
    quad_x,
    quad_y,
    quad_bounds,
    waterline_xy,
    node_distance,
    panel_normals,
    min_overlap,
):
    """Contact geometry of many floes (bow frame) against one convex bow.

    floe_coords, floe_index: the floes' closed exterior rings and the floe of each vertex, as from
    `shapely.get_coordinates(floes, return_index=True)` (polygons without holes); n_floes: their number.
    hull_x, hull_y: the CCW open ring of H_u. quad_x, quad_y: (n_panels, 4) CCW footprints Q_i; quad_bounds:
    their (x0, y0, x1, y1). Separate contiguous x and y arrays keep every call to the helpers on one array
    layout (one compiled specialisation each, so the first run compiles faster). waterline_xy: the upper
    waterline nodes (n_panels + 1); node_distance: arc length at each node; panel_normals: outward unit
    normals. Zones and rows of at most `min_overlap` area are not contacts.

    Returns the status of every floe; per zone (one per floe with status CONTACT, in floe order): the floe,
    A_u, centre xy, centre panel, floe area, floe extent along the centre's normal (`centre_normal`) and along
    the panel (the classification box of thesis Alg. 2); per row (zone, panel, A_h,i, length of the panel's
    waterline segment inside the floe), rows ordered by zone then panel."""
    floe_start, floe_count, max_n = _ring_layout(floe_index, n_floes)
    n_panels = quad_x.shape[0]
    status = np.zeros(n_floes, dtype=np.int8)
    a_u, centre, centre_panel = np.zeros(n_floes), np.zeros((n_floes, 2)), np.zeros(n_floes, dtype=np.int64)
    floe_area, extent = np.zeros(n_floes), np.zeros((n_floes, 2))
    rows = (np.empty(n_floes * n_panels, dtype=np.int64), np.empty(n_floes * n_panels, dtype=np.int64),
            np.empty(n_floes * n_panels))
    row_overlap = np.empty(n_floes * n_panels)
    scratch = _batch_scratch(max_n, hull_x.shape[0], n_panels)
    ring_x, ring_y = np.empty(max_n), np.empty(max_n)
    hull_box = (hull_x.min(), hull_x.max(), hull_y.min(), hull_y.max())
    n_rows = 0
    for i in range(n_floes):
        s, n = floe_start[i], floe_count[i]
        if n < 3:
            continue
        for v in range(n):  # the open ring (closing vertex dropped), copied into contiguous scratch
            ring_x[v] = floe_coords[s + v, 0]
            ring_y[v] = floe_coords[s + v, 1]
        px, py = ring_x[:n], ring_y[:n]
        state, k, area, middle, signed_area = _floe_zone(
            px, py, n, hull_x, hull_y, hull_box, waterline_xy, node_distance, min_overlap, scratch
        )
        if state != CONTACT:
            status[i] = state
            continue
        zx, zy, seg_overlap = scratch[0], scratch[1], scratch[9]
        status[i] = CONTACT
        a_u[i] = area
        centre[i, 0], centre[i, 1], panel = _waterline_point(middle, waterline_xy, node_distance)
        centre_panel[i] = panel
        floe_area[i] = abs(signed_area)
        normal_x, normal_y = centre_normal(centre[i, 0], centre[i, 1], panel, waterline_xy, panel_normals)
        norm = np.hypot(normal_x, normal_y)
        normal_x, normal_y = normal_x / norm, normal_y / norm
        extent[i, 0], extent[i, 1] = box_extents(px, py, n, normal_x, normal_y)
        first_row = n_rows
        n_rows = _panel_rows(
            zx, zy, k, i, quad_x, quad_y, quad_bounds, min_overlap, scratch[2:6], rows, n_rows
        )
        if n_rows < 0:  # scratch space exhausted: drop this floe's rows, GEOS takes it
            n_rows = first_row
            status[i] = FALLBACK
            continue
        for r in range(first_row, n_rows):
            row_overlap[r] = seg_overlap[rows[1][r]]
    owner = np.flatnonzero(status == CONTACT)
    row_zone = _zone_of_rows(status, owner, rows[0], n_rows)
    return (status, owner, a_u[owner], centre[owner], centre_panel[owner], floe_area[owner], extent[owner],
            row_zone, rows[1][:n_rows], rows[2][:n_rows], row_overlap[:n_rows])


@numba.njit(cache=True, nogil=True)
def _batch_scratch(max_n, m, n_panels):
    """Scratch arrays of `contact_batch`: (zx, zy, qx, qy, tx, ty, hits, part_from, part_to, seg_overlap).
    A half-plane adds at most one vertex to a convex polygon, more to a non-convex one: generous space, and a
    floe that would exceed it goes to GEOS."""
    capacity = 4 * (max_n + m) + 16
    return (
        np.empty(capacity), np.empty(capacity), np.empty(capacity), np.empty(capacity),
        np.empty(capacity), np.empty(capacity), np.empty(max_n + 1),
        np.empty(n_panels * (max_n + 2)), np.empty(n_panels * (max_n + 2)), np.empty(n_panels),
    )


@numba.njit(cache=True, nogil=True)
def _floe_zone(px, py, n, hx, hy, hull_box, waterline_xy, node_distance, min_overlap, scratch):
    """The contact zone Z = F ∩ H_u of one floe ring (px, py)[:n], left in scratch (zx, zy)[:k]:
    (state, k, A_u, waterline position of the zone centre, signed floe area); state NO_CONTACT, CONTACT or
    FALLBACK (GEOS decides)."""
    zx, zy, _, _, tx, ty, hits, part_from, part_to, seg_overlap = scratch
    capacity = zx.shape[0]
    m = hx.shape[0]
    hull_x0, hull_x1, hull_y0, hull_y1 = hull_box
    if px.max() <= hull_x0 or px.min() >= hull_x1 or py.max() <= hull_y0 or py.min() >= hull_y1:
        return NO_CONTACT, 0, 0.0, 0.0, 0.0  # at most touching: no area in common
    signed_area = _signed_area(px, py, n)
    orientation = 1.0 if signed_area > 0.0 else -1.0
    convex = _is_convex(px, py, n, orientation)
    # F ∩ H_u is one zone if F is convex, or if the two boundaries cross at most twice (one arc of ∂F
    # inside H_u closes with one arc of ∂H_u inside F); anything else is left to GEOS
    if not convex:
        crossings = _crossings(px, py, n, hx, hy, m)
        if crossings < 0 or crossings > 2:
            return FALLBACK, 0, 0.0, 0.0, signed_area
    k = _clip_convex(px, py, n, hx, hy, m, zx, zy, tx, ty, capacity)
    if k < 0:
        return FALLBACK, 0, 0.0, 0.0, signed_area
    area = abs(_signed_area(zx, zy, k)) if k >= 3 else 0.0
    if not area > min_overlap:
        return NO_CONTACT, k, area, 0.0, signed_area
    # the waterline inside F, split where it meets F's boundary (as GEOS does): the longest part (the span
    # of the tied ones, `_longest_span`) and, per segment, the length inside F
    n_parts = _waterline_parts(px, py, n, waterline_xy, node_distance, hits, seg_overlap, part_from, part_to)
    if n_parts < 0:
        return FALLBACK, k, area, 0.0, signed_area
    best_length, best_from, best_to = _longest_span(part_from, part_to, np.ones(n_parts, dtype=np.bool_))
    if best_length > 0.0:
        return CONTACT, k, area, 0.5 * (best_from + best_to), signed_area
    if convex:  # a zone clear of the waterline (a piece already inside the hull): the nearest point
        return CONTACT, k, area, _nearest_on_waterline(zx, zy, k, waterline_xy, node_distance), signed_area
    # the clipped outline of a non-convex floe may carry zero-width bridges: GEOS finds the point
    return FALLBACK, k, area, 0.0, signed_area


@numba.njit(cache=True, nogil=True)
def _zone_of_rows(status, owner, row_floe, n_rows):
    """The zone index (among the floes with status CONTACT) of each row."""
    zone_of_floe = np.full(status.shape[0], -1, dtype=np.int64)
    zone_of_floe[owner] = np.arange(owner.shape[0])
    row_zone = np.empty(n_rows, dtype=np.int64)
    for r in range(n_rows):
        row_zone[r] = zone_of_floe[row_floe[r]]
    return row_zone


@numba.njit(cache=True, nogil=True)
def _longest_span(part_from, part_to, usable):
    """(length, from, to) of the longest of the `usable` parts (arc-length intervals in waterline order);
    where several tie as the longest within `ON_NODE_M` (a symmetric floe straddling the stem: one part
    each side), the span from the first tied part's start to the last one's end, whose middle is then the
    zone centre — mirror-equivariant, where the first (port) part was not. Length −1 when none is usable."""
    best = -1.0
    for q in range(usable.shape[0]):
        if usable[q] and part_to[q] - part_from[q] > best:
            best = part_to[q] - part_from[q]
    span_from, span_to, first = 0.0, 0.0, True
    for q in range(usable.shape[0]):
        if usable[q] and part_to[q] - part_from[q] >= best - ON_NODE_M:
            if first:
                span_from, first = part_from[q], False
            span_to = part_to[q]
    return best, span_from, span_to


@numba.njit(cache=True, nogil=True)
def _longest_part_of_zone(
    zx, zy, k, several, part_from, part_to, n_parts, waterline_xy, node_distance, limit
):
    """`_longest_span` of the floe's `n_parts` waterline parts; with `several` zones in the floe, only parts
    whose middle lies within √limit of the zone ring (zx, zy)[:k] count. Length −1 when none does."""
    usable = np.ones(n_parts, dtype=np.bool_)
    for q in range(n_parts if several else 0):  # several zones: the part must lie on this zone's boundary
        middle = 0.5 * (part_from[q] + part_to[q])
        mx, my, _ = _waterline_point(middle, waterline_xy, node_distance)
        nearest = np.inf
        for v in range(k):
            w = v + 1 if v + 1 < k else 0
            d2, _ = _project(mx, my, zx[v], zy[v], zx[w], zy[w])
            nearest = min(nearest, d2)
        usable[q] = nearest <= limit
    return _longest_span(part_from[:n_parts], part_to[:n_parts], usable)


@numba.njit(cache=True, nogil=True)
def zone_rows(
    zone_coords, zone_index, n_zones, zone_floe, floe_coords, floe_index, n_floes, quad_x, quad_y,
    quad_bounds, waterline_xy, node_distance, min_overlap, on_boundary,
):
    """Panel rows and centres of zones found by GEOS (the connected parts of F ∩ H_u of floes with several).

    zone_coords, zone_index: the zones' closed exterior rings and the zone of each vertex (polygons without
    holes); zone_floe: each zone's floe; floe_coords, floe_index: the floes' closed exterior rings. Rows:
    (zone, panel, A_h,i = area(Z ∩ Q_i) > min_overlap, length of the panel's waterline segment inside the
    floe), ordered by zone then panel. Centre ("midBow", thesis Alg. 5): the middle of the longest part (the
    span of tied ones, `_longest_span`) of waterline ∩ F on the zone's boundary (its middle within
    `on_boundary` of the boundary; every part if the floe has one zone); `centre_found` False where no part
    bounds the zone (the caller finds the nearest waterline point). Returns (ok, rows…, centre, centre_panel,
    centre_found); ok False: a degenerate case (the waterline along a floe edge, scratch space exhausted) —
    GEOS evaluates everything."""
    n_panels = quad_x.shape[0]
    floe_start, floe_count, max_floe_n = _ring_layout(floe_index, n_floes)
    zone_start, zone_count, max_zone_n = _ring_layout(zone_index, n_zones)
    zones_of_floe = np.zeros(n_floes, dtype=np.int64)
    for z in range(n_zones):
        zones_of_floe[zone_floe[z]] += 1
    hits = np.empty(max_floe_n + 1)
    seg_overlap = np.zeros((n_floes, n_panels))
    capacity_parts = n_panels * (max_floe_n + 2)
    part_from, part_to = np.empty((n_floes, capacity_parts)), np.empty((n_floes, capacity_parts))
    n_parts = np.zeros(n_floes, dtype=np.int64)
    row_zone = np.empty(n_zones * n_panels, dtype=np.int64)
    row_panel = np.empty(n_zones * n_panels, dtype=np.int64)
    row_a_h = np.empty(n_zones * n_panels)
    row_overlap = np.empty(n_zones * n_panels)
    centre = np.zeros((n_zones, 2))
    centre_panel = np.zeros(n_zones, dtype=np.int64)
    centre_found = np.zeros(n_zones, dtype=np.bool_)
    ok = True
    for f in range(n_floes):
        s, n = floe_start[f], floe_count[f]
        px, py = floe_coords[s : s + n, 0].copy(), floe_coords[s : s + n, 1].copy()
        count = _waterline_parts(
            px, py, n, waterline_xy, node_distance, hits, seg_overlap[f], part_from[f], part_to[f]
        )
        if count < 0:
            ok = False
        n_parts[f] = max(count, 0)
    capacity = 4 * (max_zone_n + 4) + 16
    scratch = (np.empty(capacity), np.empty(capacity), np.empty(capacity), np.empty(capacity))
    rows = (row_zone, row_panel, row_a_h)
    limit = on_boundary * on_boundary
    n_rows = 0
    for z in range(n_zones if ok else 0):
        s, k = zone_start[z], zone_count[z]
        zx, zy = zone_coords[s : s + k, 0].copy(), zone_coords[s : s + k, 1].copy()
        f = zone_floe[z]
        first_row = n_rows
        n_rows = _panel_rows(zx, zy, k, z, quad_x, quad_y, quad_bounds, min_overlap, scratch, rows, n_rows)
        if n_rows < 0:
            ok, n_rows = False, 0
            break
        for r in range(first_row, n_rows):
            row_overlap[r] = seg_overlap[f, row_panel[r]]
        best_length, best_from, best_to = _longest_part_of_zone(
            zx, zy, k, zones_of_floe[f] > 1, part_from[f], part_to[f], n_parts[f], waterline_xy,
            node_distance, limit,
        )
        if best_length > 0.0:
            centre[z, 0], centre[z, 1], centre_panel[z] = _waterline_point(
                0.5 * (best_from + best_to), waterline_xy, node_distance
            )
            centre_found[z] = True
    return (
        ok, row_zone[:n_rows], row_panel[:n_rows], row_a_h[:n_rows], row_overlap[:n_rows], centre,
        centre_panel, centre_found,
    )


FORCE_SIGNS = ("consistent", "thesis_alg3", "thesis_eq9_10")  # codes 0, 1, 2 of `force_signs` below
NEAR_VERTICAL = ("vertical_face", "cap", "none")  # codes 0, 1, 2 of `near_vertical` below


@numba.njit(cache=True, nogil=True)
def _vertical_horizontal(f_c, sin_psi, cos_psi, mu, force_signs):
    """(F_v before clamping, F_h) for crushing force F_c on a panel at ψ from the vertical (Eqs. 8–10)."""
    if force_signs == 0:  # consistent (physics-notes §2.3)
        return f_c * (sin_psi - mu * cos_psi), f_c * (cos_psi + mu * sin_psi)
    if force_signs == 1:  # thesis Alg. 3: friction sign of F_h (erratum 9)
        return f_c * (sin_psi - mu * cos_psi), f_c * (cos_psi - mu * sin_psi)
    return f_c * (cos_psi - mu * sin_psi), f_c * (sin_psi + mu * cos_psi)  # Eqs. 9/10 literally (erratum 10)


@numba.njit(cache=True, nogil=True)
def panel_forces(contact_area, sin_psi, cos_psi, crushing_pa, mu, force_signs):
    """F_c = k_c σ_c A_c (Eq. 7; `crushing_pa` = k_c σ_c), F_v (clamped at 0) and F_h per row."""
    n = contact_area.shape[0]
    f_c, f_v, f_h = np.empty(n), np.empty(n), np.empty(n)
    for r in range(n):
        f_c[r] = crushing_pa * contact_area[r]
        vertical, f_h[r] = _vertical_horizontal(f_c[r], sin_psi[r], cos_psi[r], mu, force_signs)
        f_v[r] = max(vertical, 0.0)
    return f_c, f_v, f_h


@numba.njit(cache=True, nogil=True)
def zone_forces(
    row_zone, row_panel, row_a_h, overlap, thickness, a_u, centre_panel, single_psi, panel_sin, panel_cos,
    panel_normals, crushing_pa, mu, sin_psi_min, near_vertical, force_signs,
):
    """A_l, contact areas and forces of every zone and row (thesis Eqs. 6–10, Alg. 3).

    Input rows (zone × panel, sorted by zone) carry A_h,i; A_l = max(A_u − Σ A_h,i, 0). `single_psi`: thesis
    Eq. 6 literally — one row per zone at its centre panel with A_h = A_u − A_l. A_c = A_h / sin ψ with the
    near-vertical guard of physics-notes §2.2 for sin ψ < sin ψ_min: `near_vertical` 0 = thickness × length
    of the panel inside the floe (`overlap`, per input row, or per zone for `single_psi`), 1 = 1/sin ψ capped
    at 1/sin ψ_min, 2 = no guard. `thickness` per zone.

    Returns (A_l per zone, rows' zone, panel, A_h, A_c, F_c, F_v, F_h, the zone force xy on the ice, the
    first row of each zone and the end).
    """
    n_zones = a_u.shape[0]
    a_l = a_u.copy()
    sums = np.zeros(n_zones)
    for r in range(row_a_h.shape[0]):
        sums[row_zone[r]] += row_a_h[r]
    for z in range(n_zones):
        a_l[z] = max(a_u[z] - sums[z], 0.0)  # Σ A_h,i = A_u − A_l
    if single_psi:
        row_zone = np.arange(n_zones)
        row_panel = centre_panel
        row_a_h = a_u - a_l
    n = row_a_h.shape[0]
    a_c = np.empty(n)
    sin_psi, cos_psi = np.empty(n), np.empty(n)
    for r in range(n):
        s = panel_sin[row_panel[r]]
        sin_psi[r], cos_psi[r] = s, panel_cos[row_panel[r]]
        a_c[r] = row_a_h[r] / max(s, 1e-12) if row_a_h[r] > 0.0 else 0.0
        if s < sin_psi_min:
            if near_vertical == 1:
                a_c[r] = row_a_h[r] / sin_psi_min
            elif near_vertical == 0:
                a_c[r] = thickness[row_zone[r]] * overlap[r]
    f_c, f_v, f_h = panel_forces(a_c, sin_psi, cos_psi, crushing_pa, mu, force_signs)
    zone_xy = np.zeros((n_zones, 2))
    zone_start = np.zeros(n_zones + 1, dtype=np.int64)
    for r in range(n):
        zone_xy[row_zone[r], 0] += f_h[r] * panel_normals[row_panel[r], 0]
        zone_xy[row_zone[r], 1] += f_h[r] * panel_normals[row_panel[r], 1]
        zone_start[row_zone[r] + 1] = r + 1
    for z in range(n_zones):  # zones without rows start where the previous one ended
        zone_start[z + 1] = max(zone_start[z + 1], zone_start[z])
    return a_l, row_zone, row_panel, row_a_h, a_c, f_c, f_v, f_h, zone_xy, zone_start


def ccw_ring(coords: np.ndarray) -> np.ndarray:
    """Open ring (closing vertex dropped) in counter-clockwise order."""
    ring = np.asarray(coords, dtype=float)
    if len(ring) > 1 and np.array_equal(ring[0], ring[-1]):
        ring = ring[:-1]
    x, y = ring[:, 0], ring[:, 1]
    signed = 0.5 * math.fsum(x * np.roll(y, -1) - np.roll(x, -1) * y)  # exact sum, not BLAS' dot
    return ring if signed > 0.0 else ring[::-1].copy()


def is_convex_ring(ring: np.ndarray) -> bool:
    """True if the CCW open ring turns left (or runs straight) at every vertex."""
    ring = np.ascontiguousarray(ring, dtype=float)
    return bool(_is_convex(ring[:, 0].copy(), ring[:, 1].copy(), len(ring), 1.0))


def compile_now() -> None:
    """Compile (or load from numba's on-disk cache) the kernel on a tiny input; see `compile_kernels`."""
    square_x, square_y = np.array([0.0, 1.0, 1.0, 0.0]), np.array([0.0, 0.0, 1.0, 1.0])
    ring = np.stack([np.append(square_x, 0.0), np.append(square_y, 0.0)], axis=1)
    quad_x, quad_y = square_x[None, :] - 0.5, square_y[None, :] - 0.5
    waterline = np.array([[-0.5, -0.5], [0.5, -0.5]])
    contact_batch(
        ring, np.zeros(5, dtype=np.int64), 1, square_x - 0.5, square_y - 0.5, quad_x, quad_y,
        np.array([[-0.5, -0.5, 0.5, 0.5]]), waterline, np.array([0.0, 1.0]), np.array([[0.0, -1.0]]), 1e-12,
    )
    _is_convex(square_x, square_y, 4, 1.0)
    one, index = np.ones(1), np.zeros(1, dtype=np.int64)
    for single_psi in (False, True):
        zone_forces(
            index, index, one, one, one, one, index, single_psi, one, one, np.array([[0.0, -1.0]]), 1.0, 0.1,
            0.1, 0, 0,
        )
