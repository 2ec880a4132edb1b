"""The bow: upper and lower ice waterlines, bow panels, normals and panel angles ψ (thesis §3.1, Eq. 20).

Frame (physics-notes §0, thesis Fig. 2): x forward, y to port, z up; the origin is the stem tip of the upper
ice waterline. A `Bow` holds the two ice waterlines as polylines with corresponding nodes: node i of the
lower line lies on the same (planar) hull panel edge as node i of the upper line. The lines run from the port
aft end of the modelled midbody over the port shoulder, the stem and the starboard shoulder to the starboard
aft end, so y goes from +B/2 to −B/2. Panel i is the plane hull strip between upper nodes i, i+1 (at
z_upper_m) and lower nodes i+1, i (at z_lower_m); its plan-view footprint Q_i tiles H_u \\ H_l.

CSV formats (`Bow.from_csv`, `Bow.to_csv`) are described in `Bow.from_csv`.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any, Final

import numpy as np
import shapely

from floebreak.constants import ICE_DENSITY_KG_M3, SEAWATER_DENSITY_KG_M3
from floebreak.errors import Bounds, InputError, csv_where

RELATIVE_TOLERANCE: Final = 1e-9  # geometric tolerance relative to the bow's size (min 1 m)
SHOULDER_RELATIVE_TOLERANCE: Final = 1e-6  # |y| ≥ (1 − tol)·B/2 counts as "full half-breadth"
LINES_COLUMNS: Final = ("line", "x_m", "y_m")  # CSV format (a)
STATIONS_COLUMNS: Final = ("x_m", "half_breadth_m", "frame_angle_deg")  # CSV format (b)
CSV_KEYS: Final = ("name", "z_upper_m", "z_lower_m", "ice_thickness_m")  # "# key = value" header comments
Place = tuple[int, int]  # a CSV row: (data row counted from 1 after the header, line of the file)
# frame (flare) angle β from the vertical: a vertical side (0°) up to, not including, a flat one (90°)
FRAME_ANGLE_DEG: Final = Bounds(0.0, 90.0, low_inclusive=True, high_inclusive=False, unit="deg")


class _LineError(Exception):
    """Internal: a geometry check failed at node `index` of `line` ("upper"/"lower")."""

    def __init__(self, line: str, index: int, message: str):
        super().__init__(message)
        self.line = line
        self.index = index
        self.message = message


def ice_waterline_heights(ice_thickness_m: float) -> tuple[float, float]:
    """(z_upper_m, z_lower_m) of a freely floating ice sheet of thickness h (physics-notes §6.3).

    z_u = (1 − ρ_i/ρ_w) h and z_l = −(ρ_i/ρ_w) h, so Δz = z_u − z_l = h.
    """
    ratio = ICE_DENSITY_KG_M3 / SEAWATER_DENSITY_KG_M3
    return (1.0 - ratio) * ice_thickness_m, -ratio * ice_thickness_m


def _outward_normals(xy: np.ndarray) -> np.ndarray:
    """Thesis Eq. 20 at every node, with one-sided differences at the end nodes (erratum 22).

    n_i = (y_{i−1} − y_{i+1}, x_{i+1} − x_{i−1}) normalised. For the bow's node order (port aft → stem →
    starboard aft, i.e. clockwise around the hull) this vector points out of the hull.
    """
    prev = np.vstack([xy[:1], xy[:-2], xy[-2:-1]])
    nxt = np.vstack([xy[1:2], xy[2:], xy[-1:]])
    normals = np.column_stack([prev[:, 1] - nxt[:, 1], nxt[:, 0] - prev[:, 0]])
    return normals / np.linalg.norm(normals, axis=1, keepdims=True)


def _polygonal(geometry) -> shapely.Geometry:
    """The polygonal part of a geometry (Polygon or MultiPolygon, possibly empty)."""
    if shapely.get_type_id(geometry) in (3, 6):
        return geometry
    parts = [p for p in shapely.get_parts(geometry) if shapely.get_type_id(p) in (3, 6)]
    return shapely.union_all(parts) if parts else shapely.Polygon()


def _footprint(corners: np.ndarray) -> shapely.Geometry:
    """Plan-view quadrilateral U_i, U_i+1, L_i+1, L_i (triangle or empty when corners coincide)."""
    polygon = shapely.Polygon(corners)
    if polygon.is_valid:
        return polygon
    return _polygonal(shapely.make_valid(polygon))


def _first_self_intersection(xy: np.ndarray, closed: bool) -> int | None:
    """Index of the first segment of the polyline that crosses another one (None if the line is simple).

    Zero-length segments (repeated nodes) are ignored. With `closed`, the closing segment (last → first node)
    takes part. Adjacent segments may only share their common node.
    """
    keep = np.concatenate([[True], np.any(np.diff(xy, axis=0) != 0.0, axis=1)])
    index = np.flatnonzero(keep)
    pts = xy[index]
    starts = list(range(len(pts) - 1))
    segments = [shapely.LineString(pts[i : i + 2]) for i in starts]
    seg_index = [int(index[i]) for i in starts]
    if closed and np.any(pts[-1] != pts[0]):
        segments.append(shapely.LineString([pts[-1], pts[0]]))
        seg_index.append(int(index[-1]))
    m = len(segments)
    if m == 0:  # every node at one point (a lower line collapsed onto its stem tip): nothing to cross
        return None
    tree = shapely.STRtree(segments)
    a, b = tree.query(segments, predicate="intersects")
    bad = set()
    for i, j in zip(a.tolist(), b.tolist(), strict=True):
        if i >= j:
            continue
        adjacent = j == i + 1 or (closed and i == 0 and j == m - 1)
        if adjacent:
            if shapely.intersection(segments[i], segments[j]).length > 0.0:  # back-tracking overlap
                bad.add(j)
        else:
            bad.add(i)
    return seg_index[min(bad)] if bad else None


def _check_lines(upper: np.ndarray, lower: np.ndarray) -> dict[str, Any]:
    """Validate the two waterlines; raise _LineError(line, node, message). Returns derived basics."""
    for line, xy in (("upper", upper), ("lower", lower)):
        bad = np.flatnonzero(~np.isfinite(xy).all(axis=1))
        if bad.size:
            raise _LineError(line, int(bad[0]), f"non-finite coordinate {xy[bad[0]].tolist()}")
    scale = max(1.0, float(np.ptp(upper, axis=0).max()))
    tol = RELATIVE_TOLERANCE * scale
    stem = int(np.argmin(np.hypot(upper[:, 0], upper[:, 1])))
    if np.hypot(*upper[stem]) > tol:
        raise _LineError("upper", stem, "the upper stem tip must be at (0, 0) (origin of the bow frame)")
    ahead = np.flatnonzero(upper[:, 0] > tol)
    if ahead.size:
        raise _LineError("upper", int(ahead[0]), "node lies ahead of the stem tip (x > 0)")
    if not upper[0, 1] > tol or not upper[-1, 1] < -tol:
        raise _LineError(
            "upper", 0, "the line must start on the port side (y > 0) and end to starboard (y < 0)"
        )
    rising = np.flatnonzero(np.diff(upper[:, 1]) > tol)
    if rising.size:
        raise _LineError(
            "upper",
            int(rising[0]) + 1,
            "y must not increase along the line (order: port aft → stem → starboard aft)",
        )
    if lower[0, 1] < -tol or lower[-1, 1] > tol:
        raise _LineError(
            "lower", 0, "the line must start on the port side (y ≥ 0) and end to starboard (y ≤ 0)"
        )
    steps = np.hypot(*np.diff(upper, axis=0).T)
    zero = np.flatnonzero(steps <= tol)
    if zero.size:
        raise _LineError("upper", int(zero[0]) + 1, "repeats the previous node (zero-length panel)")
    for line, xy in (("upper", upper), ("lower", lower)):
        crossing = _first_self_intersection(xy, closed=True)
        if crossing is not None:
            raise _LineError(
                line,
                crossing,
                "the waterline (closed aft by the midbody end) intersects itself: the segment starting "
                "at this node crosses or overlaps another one",
            )
    hull_upper = shapely.Polygon(upper)
    hull_lower = shapely.Polygon(lower)
    for line, hull in (("upper", hull_upper), ("lower", hull_lower)):
        if hull.area > 0.0 and shapely.is_ccw(hull.exterior):
            raise _LineError(
                line, 0, "nodes run counter-clockwise; order them port aft → stem → starboard aft"
            )
    covering = shapely.buffer(hull_upper, tol)
    outside = np.flatnonzero(~shapely.covers(covering, shapely.points(lower)))
    if outside.size:
        raise _LineError("lower", int(outside[0]), "node lies outside the upper-waterline hull polygon")
    segments = shapely.linestrings(np.stack([lower[:-1], lower[1:]], axis=1))
    crossing = np.flatnonzero(~shapely.covers(covering, segments))
    if crossing.size:
        raise _LineError("lower", int(crossing[0]), "segment leaves the upper-waterline hull polygon")
    return {"stem": stem, "tol": tol, "hull_upper": hull_upper, "hull_lower": hull_lower}


def _checked_node_arrays(upper_xy_m, lower_xy_m) -> tuple[np.ndarray, np.ndarray]:
    """The two waterlines as read-only float (n_nodes ≥ 3, 2) arrays of equal shape, else InputError."""
    arrays = {}
    for line, raw in (("upper", upper_xy_m), ("lower", lower_xy_m)):
        key = f"{line}_xy_m"
        try:
            xy = np.array(raw, dtype=float)
        except (TypeError, ValueError):
            raise InputError(key, "must be a numeric (n_nodes, 2) array") from None
        if xy.ndim != 2 or xy.shape[1] != 2 or xy.shape[0] < 3:
            raise InputError(key, f"must have shape (n_nodes ≥ 3, 2), got {xy.shape}", value=xy.shape)
        xy.setflags(write=False)
        arrays[line] = xy
    upper, lower = arrays["upper"], arrays["lower"]
    if lower.shape != upper.shape:
        raise InputError(
            "lower_xy_m", f"must have as many nodes as upper_xy_m ({len(upper)}), got {len(lower)}"
        )
    return upper, lower


def _panels(
    upper: np.ndarray, lower: np.ndarray, dz: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Panel normals, panel angles ψ_v (physics-notes §2.1), upper midpoints and plan-view footprints."""
    n_panels = len(upper) - 1
    tangents = np.diff(upper, axis=0)
    panel_normals = np.column_stack([-tangents[:, 1], tangents[:, 0]])
    panel_normals /= np.linalg.norm(panel_normals, axis=1, keepdims=True)
    upper_mid = 0.5 * (upper[:-1] + upper[1:])
    lower_mid = 0.5 * (lower[:-1] + lower[1:])
    d_n = np.einsum("ij,ij->i", upper_mid - lower_mid, panel_normals)  # inward offset of the lower panel
    psi = np.arctan2(np.maximum(d_n, 0.0), dz)
    footprints = np.empty(n_panels, dtype=object)
    for i in range(n_panels):
        footprints[i] = _footprint(np.array([upper[i], upper[i + 1], lower[i + 1], lower[i]]))
    return panel_normals, psi, upper_mid, footprints


def _split_csv_text(text: str) -> tuple[dict[str, str], list[str] | None, int, list[tuple[Place, list[str]]]]:
    """(``# key = value`` metadata, header cells or None, header's line, [((data row, line), cells)]) of a
    bow CSV: data rows counted from 1 after the header, lines of the file from 1 (`errors.csv_where`)."""
    meta: dict[str, str] = {}
    header: list[str] | None = None
    header_line = 0
    rows: list[tuple[Place, list[str]]] = []
    for line_number, raw in enumerate(text.splitlines(), start=1):
        stripped = raw.strip()
        if not stripped:
            continue
        if stripped.startswith("#"):
            body = stripped.lstrip("#").strip()
            if "=" in body:
                key, value = (part.strip() for part in body.split("=", 1))
                if key in CSV_KEYS:
                    meta[key] = value
            continue
        cells = [cell.strip() for cell in next(csv.reader([raw]))]
        if header is None:
            header, header_line = cells, line_number
        else:
            rows.append(((len(rows) + 1, line_number), cells))
    return meta, header, header_line, rows


def _csv_format(
    header: list[str] | None, header_line: int, rows: list[tuple[Place, list[str]]], where: str
) -> str:
    """The CSV format from the header, "lines" (a) or "stations" (b); InputError for a bad header or row."""
    if header is None:
        raise InputError(where, "no header row found", allowed=_formats_text())
    if sorted(header) == sorted(LINES_COLUMNS):
        fmt = "lines"
    elif sorted(header) == sorted(STATIONS_COLUMNS):
        fmt = "stations"
    else:
        raise InputError(
            csv_where(where, line=header_line),
            f"unexpected columns {header}",
            value=header,
            allowed=_formats_text(),
        )
    for place, cells in rows:
        if len(cells) != len(header):
            raise InputError(
                csv_where(where, None, *place),
                f"has {len(cells)} values, the header has {len(header)} columns",
            )
    return fmt


@dataclass(frozen=True, eq=False)
class Bow:
    """Two ice waterlines of a bow with derived panels, normals and panel angles (thesis §3.1).

    Fields: `name`; `upper_xy_m`, `lower_xy_m` (n_nodes, 2) node arrays (see the module docstring for order
    and frame); `z_upper_m`, `z_lower_m` ice top/bottom heights the lines were built for (Δz = ice thickness);
    `parameters` (assumed angles etc., provenance only).

    Derived (computed once in __post_init__): `n_panels`, `node_normals` (Eq. 20), `panel_normals`,
    `panel_psi_rad` (ψ_v from the vertical, physics-notes §2.1), `panel_midpoints_m`, `panel_footprints`,
    `hull_upper`, `hull_lower`, `stem_index`, `shoulder_indices`, `length_bow_m`, `half_breadth_m`,
    `psi_stem_deg`, `psi_shoulder_deg`.
    """

    name: str
    upper_xy_m: np.ndarray
    lower_xy_m: np.ndarray
    z_upper_m: float
    z_lower_m: float
    parameters: Mapping[str, Any] = field(default_factory=dict)

    n_panels: int = field(init=False, repr=False)
    node_normals: np.ndarray = field(init=False, repr=False)
    panel_normals: np.ndarray = field(init=False, repr=False)
    panel_psi_rad: np.ndarray = field(init=False, repr=False)
    panel_midpoints_m: np.ndarray = field(init=False, repr=False)
    panel_footprints: np.ndarray = field(init=False, repr=False)
    hull_upper: shapely.Polygon = field(init=False, repr=False)
    hull_lower: shapely.Polygon = field(init=False, repr=False)
    stem_index: int = field(init=False, repr=False)
    shoulder_indices: tuple[int, int] = field(init=False, repr=False)
    length_bow_m: float = field(init=False, repr=False)
    half_breadth_m: float = field(init=False, repr=False)
    psi_stem_deg: float = field(init=False, repr=False)
    psi_shoulder_deg: float = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.strip():
            raise InputError("name", "must be a non-empty string", value=self.name)
        upper, lower = _checked_node_arrays(self.upper_xy_m, self.lower_xy_m)
        z_u, z_l = float(self.z_upper_m), float(self.z_lower_m)
        if not (math.isfinite(z_u) and math.isfinite(z_l)) or not z_u > z_l:
            raise InputError(
                "z_lower_m", f"must be finite and below z_upper_m = {z_u:g} m, got {z_l:g} m", value=z_l
            )
        dz = z_u - z_l
        try:
            basics = _check_lines(upper, lower)
        except _LineError as error:
            raise InputError(
                f"{error.line}_xy_m[{error.index}]", f"node {error.index}: {error.message}", value=error.index
            ) from None
        setattr_ = object.__setattr__
        setattr_(self, "upper_xy_m", upper)
        setattr_(self, "lower_xy_m", lower)
        setattr_(self, "z_upper_m", z_u)
        setattr_(self, "z_lower_m", z_l)
        setattr_(self, "parameters", MappingProxyType(dict(self.parameters)))

        n_panels = len(upper) - 1
        panel_normals, psi, upper_mid, footprints = _panels(upper, lower, dz)
        node_normals = _outward_normals(upper)

        stem = basics["stem"]
        y_max, y_min = float(upper[:, 1].max()), float(upper[:, 1].min())
        half_breadth = 0.5 * (y_max - y_min)
        tol_y = SHOULDER_RELATIVE_TOLERANCE * max(half_breadth, 1.0)
        port = np.flatnonzero(upper[: stem + 1, 1] >= y_max - tol_y)
        starboard = stem + np.flatnonzero(upper[stem:, 1] <= y_min + tol_y)
        shoulders = (int(port.max()), int(starboard.min()))
        length_bow = float(-upper[list(shoulders), 0].min())
        # ψ at the shoulder node: node normal (Eq. 20) and the node's own waterline offset
        node_offsets = np.einsum("ij,ij->i", upper - lower, node_normals)
        psi_shoulder = np.degrees(np.arctan2(np.maximum(node_offsets[list(shoulders)], 0.0), dz)).mean()
        stem_panels = [p for p in (stem - 1, stem) if 0 <= p < n_panels]
        psi_stem = float(np.degrees(psi[stem_panels]).mean())

        for array in (panel_normals, psi, upper_mid, node_normals):
            array.setflags(write=False)
        footprints.setflags(write=False)
        setattr_(self, "n_panels", n_panels)
        setattr_(self, "node_normals", node_normals)
        setattr_(self, "panel_normals", panel_normals)
        setattr_(self, "panel_psi_rad", psi)
        setattr_(self, "panel_midpoints_m", upper_mid)
        setattr_(self, "panel_footprints", footprints)
        setattr_(self, "hull_upper", basics["hull_upper"])
        setattr_(self, "hull_lower", basics["hull_lower"])
        setattr_(self, "stem_index", int(stem))
        setattr_(self, "shoulder_indices", shoulders)
        setattr_(self, "length_bow_m", length_bow)
        setattr_(self, "half_breadth_m", half_breadth)
        setattr_(self, "psi_stem_deg", psi_stem)
        setattr_(self, "psi_shoulder_deg", float(psi_shoulder))

    # --- derived quantities --------------------------------------------------------------------------

    @property
    def dz_m(self) -> float:
        """Vertical distance Δz = z_upper_m − z_lower_m between the ice waterlines [m]."""
        return self.z_upper_m - self.z_lower_m

    @property
    def n_nodes(self) -> int:
        return len(self.upper_xy_m)

    def panel_at(self, xy) -> int | np.ndarray:
        """Index of the upper panel nearest to the point(s) `xy` (shape (2,) → int, (n, 2) → array)."""
        points = np.asarray(xy, dtype=float)
        single = points.ndim == 1
        points = np.atleast_2d(points)
        if points.shape[1] != 2 or not np.isfinite(points).all():
            raise InputError("xy", "must be finite point(s) of shape (2,) or (n, 2)", value=points.shape)
        a = self.upper_xy_m[:-1]
        ab = np.diff(self.upper_xy_m, axis=0)
        ap = points[:, None, :] - a[None, :, :]
        t = np.clip(np.einsum("pij,ij->pi", ap, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
        nearest = a[None] + t[..., None] * ab[None]
        index = np.argmin(np.linalg.norm(points[:, None, :] - nearest, axis=2), axis=1)
        return int(index[0]) if single else index

    # --- CSV ---------------------------------------------------------------------------------------

    @classmethod
    def from_csv(cls, path: str | Path, name: str | None = None) -> Bow:
        """Read a bow from a CSV file in one of two formats (detected from the header row).

        Lines starting with ``#`` are comments; ``# key = value`` comments set ``name``, ``z_upper_m``,
        ``z_lower_m`` or ``ice_thickness_m`` (→ z_u = (1 − ρ_i/ρ_w) h, z_l = −(ρ_i/ρ_w) h). Format (a) needs
        z_upper_m and z_lower_m or ice_thickness_m; format (b) defaults to ice_thickness_m = 1.

        (a) ``line,x_m,y_m``: one row per node, ``line`` is ``upper`` or ``lower``; the rows of each line
            in node order (port aft → stem → starboard aft), lower node i matching upper node i.
        (b) ``x_m,half_breadth_m,frame_angle_deg``: stations of the upper waterline from the stem (x_m = 0,
            half_breadth_m = 0) aft (x_m decreasing), frame (flare) angle β from the vertical per station. The
            lower line is the upper one offset inward by Δz·tan ψ_v with tan ψ_v = tan β cos α (physics-notes
            §2.1), α from the station half-breadths; the line is mirrored to starboard (§6.3).

        Errors name the file, the data row (counted from 1 after the header) with its line in the file,
        and the column, as every CSV reader of floebreak does (`floebreak.errors.csv_where`).
        """
        path = Path(path)
        try:
            text = path.read_text(encoding="utf-8")
        except OSError as error:
            raise InputError(
                "bow_csv", f"cannot read {path}: {error.strerror or error}", value=str(path)
            ) from None
        meta, header, header_line, rows = _split_csv_text(text)
        where = f"{path.name}"
        fmt = _csv_format(header, header_line, rows, where)
        records = [(place, dict(zip(header, cells, strict=True))) for place, cells in rows]
        z_upper, z_lower, thickness_note = _read_heights(meta, where, fmt)
        bow_name = name or meta.get("name") or path.stem
        parameters = {"source_csv": str(path), "csv_format": fmt, **thickness_note}
        if fmt == "lines":
            upper, lower, upper_rows, lower_rows = _lines_from_records(records, where)
            rows_of = {"upper": upper_rows, "lower": lower_rows}
        else:
            upper, lower, station_rows, extra = _stations_to_lines(records, where, z_upper - z_lower)
            parameters.update(extra)
            n_st = len(station_rows)
            by_node = [station_rows[abs(i - (n_st - 1))] for i in range(2 * n_st - 1)]
            rows_of = {"upper": by_node, "lower": by_node}
        try:
            _check_lines(upper, lower)
        except _LineError as error:
            place = rows_of[error.line][error.index]
            columns = "x_m, y_m" if fmt == "lines" else "x_m, half_breadth_m, frame_angle_deg"
            raise InputError(
                csv_where(where, None, *place),
                f"{error.line} waterline (columns {columns}): {error.message}",
                value=place[0],
            ) from None
        return cls(bow_name, upper, lower, z_upper, z_lower, parameters)

    def to_csv(self, path: str | Path) -> Path:
        """Write the bow in CSV format (a) (``line,x_m,y_m``); `Bow.from_csv` reads it back exactly."""
        path = Path(path)
        lines = [
            "# floebreak bow ice waterlines (x forward, y to port, origin at the upper stem tip)",
            f"# name = {self.name}",
            f"# z_upper_m = {self.z_upper_m!r}",
            f"# z_lower_m = {self.z_lower_m!r}",
            ",".join(LINES_COLUMNS),
        ]
        for line, xy in (("upper", self.upper_xy_m), ("lower", self.lower_xy_m)):
            lines.extend(f"{line},{float(x)!r},{float(y)!r}" for x, y in xy)
        from floebreak.io.atomic import write_text_atomic

        return write_text_atomic(path, "\n".join(lines) + "\n", field="path")


# --- CSV helpers ----------------------------------------------------------------------------------------


def _formats_text() -> str:
    return f"header '{','.join(LINES_COLUMNS)}' (format a) or '{','.join(STATIONS_COLUMNS)}' (format b)"


def _number(where: str, place: Place, column: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise InputError(csv_where(where, column, *place), f"{text!r} is not a number", value=text) from None
    if not math.isfinite(value):
        raise InputError(csv_where(where, column, *place), f"{text!r} is not a finite number", value=text)
    return value


def _read_heights(meta: Mapping[str, str], where: str, fmt: str) -> tuple[float, float, dict[str, float]]:
    values = {}
    for key in CSV_KEYS[1:]:
        if key in meta:
            try:
                values[key] = float(meta[key])
            except ValueError:
                values[key] = math.nan
            if not math.isfinite(values[key]):
                raise InputError(f"{where} # {key}", f"{meta[key]!r} is not a finite number", value=meta[key])
    if "z_upper_m" in values or "z_lower_m" in values:
        missing = [k for k in ("z_upper_m", "z_lower_m") if k not in values]
        if missing:
            raise InputError(f"{where} # {missing[0]}", "z_upper_m and z_lower_m must be given together")
        z_u, z_l = values["z_upper_m"], values["z_lower_m"]
        if not z_u > z_l:
            raise InputError(f"{where} # z_lower_m", f"must be below z_upper_m = {z_u:g} m", value=z_l)
        return z_u, z_l, {}
    if "ice_thickness_m" not in values and fmt == "lines":
        raise InputError(
            f"{where} # z_upper_m",
            "format (a) needs '# z_upper_m = …' and '# z_lower_m = …' (or ice_thickness_m)",
        )
    thickness = values.get("ice_thickness_m", 1.0)
    if not thickness > 0.0:
        raise InputError(f"{where} # ice_thickness_m", f"must be > 0 m, got {thickness:g}", value=thickness)
    z_u, z_l = ice_waterline_heights(thickness)
    return z_u, z_l, {"ice_thickness_m": thickness}


def _lines_from_records(records, where: str):
    points: dict[str, list[tuple[float, float]]] = {"upper": [], "lower": []}
    rows: dict[str, list[Place]] = {"upper": [], "lower": []}
    for place, record in records:
        line = record["line"].lower()
        if line not in points:
            raise InputError(
                csv_where(where, "line", *place),
                f"{record['line']!r} is not a waterline",
                allowed="upper, lower",
            )
        points[line].append(
            (_number(where, place, "x_m", record["x_m"]), _number(where, place, "y_m", record["y_m"]))
        )
        rows[line].append(place)
    n_u, n_l = len(points["upper"]), len(points["lower"])
    if n_u < 3 or n_u != n_l:
        raise InputError(
            csv_where(where, "line"),
            f"needs ≥ 3 'upper' rows and as many 'lower' rows (node i ↔ i), got {n_u} upper, {n_l} lower",
        )
    return np.array(points["upper"]), np.array(points["lower"]), rows["upper"], rows["lower"]


def _stations_to_lines(records, where: str, dz: float):
    if len(records) < 2:
        raise InputError(f"{where}", "format (b) needs at least 2 stations (the stem and one station aft)")
    x = np.empty(len(records))
    hb = np.empty(len(records))
    beta = np.empty(len(records))
    rows = []
    for k, (place, record) in enumerate(records):
        x[k] = _number(where, place, "x_m", record["x_m"])
        hb[k] = _number(where, place, "half_breadth_m", record["half_breadth_m"])
        beta[k] = _number(where, place, "frame_angle_deg", record["frame_angle_deg"])
        rows.append(place)
        if not FRAME_ANGLE_DEG.low <= beta[k] < FRAME_ANGLE_DEG.high:
            interval = f"[{FRAME_ANGLE_DEG.low:g}, {FRAME_ANGLE_DEG.high:g})"
            raise InputError(
                csv_where(where, "frame_angle_deg", *place),
                f"{beta[k]:g} ° is outside {interval}",
                allowed=f"{interval} °",
            )
        if hb[k] < 0.0:
            raise InputError(csv_where(where, "half_breadth_m", *place), f"{hb[k]:g} m is negative")
    if x[0] != 0.0 or hb[0] != 0.0:
        raise InputError(
            csv_where(where, "x_m", *rows[0]),
            "the first station must be the stem (x_m = 0, half_breadth_m = 0)",
        )
    for k in range(1, len(x)):
        if not x[k] < x[k - 1]:
            raise InputError(
                csv_where(where, "x_m", *rows[k]), "stations must go aft (x_m strictly decreasing)"
            )
        if hb[k] < hb[k - 1]:
            raise InputError(csv_where(where, "half_breadth_m", *rows[k]), "must not decrease aft")
    port = np.column_stack([x, hb])
    # waterline angle α per station: thesis Eq. 20 differences on the port half line (one-sided at the ends)
    s = -x
    alpha = np.arctan(np.gradient(hb, s))
    alpha[0] = math.atan2(hb[1], s[1])
    psi = np.arctan(np.tan(np.radians(beta)) * np.cos(alpha))
    tip_x = -dz * math.tan(math.radians(beta[0])) / math.tan(alpha[0]) if alpha[0] > 0 else 0.0
    upper, lower = mirror_lines(port, alpha, psi, dz, tip_x)
    return upper, lower, rows, {"frame_angle_stem_deg": float(beta[0])}


def mirror_lines(
    port_xy_m: np.ndarray, alpha_rad: np.ndarray, psi_rad: np.ndarray, dz_m: float, lower_tip_x_m: float
) -> tuple[np.ndarray, np.ndarray]:
    """Full upper and lower ice waterlines from the port half of the upper one (physics-notes §6.3).

    `port_xy_m` runs from the stem (0, 0) aft; α is the waterline angle and ψ_v the panel angle from the
    vertical at each node. Each lower node is the upper node offset inward along the horizontal normal
    (−sin α, −cos α) by Δn = Δz tan ψ_v. Nodes whose offset crosses the centreline (y ≤ 0) or lies ahead of
    the lower stem tip collapse onto the tip (`lower_tip_x_m`, 0) (the stem node itself always does). The port
    half is then mirrored to starboard: order port aft → stem → starboard aft. An aft end lower node lying
    aft of the upper aft end (α ≠ 0 there) slides back along the lower line onto the aft closure x.
    """
    port_xy_m = np.asarray(port_xy_m, dtype=float)
    offset = dz_m * np.tan(psi_rad)
    lower = port_xy_m - offset[:, None] * np.column_stack([np.sin(alpha_rad), np.cos(alpha_rad)])
    collapse = (lower[:, 1] <= 0.0) | (lower[:, 0] >= lower_tip_x_m)
    collapse[0] = True
    lower[collapse] = (lower_tip_x_m, 0.0)
    x_end = port_xy_m[-1, 0]
    if lower[-1, 0] < x_end and len(lower) > 1 and lower[-2, 0] >= x_end:
        # the aft lower node must not lie aft of the hull closure: slide it along the lower line back to x_end
        t = (lower[-2, 0] - x_end) / (lower[-2, 0] - lower[-1, 0])
        lower[-1] = lower[-2] + t * (lower[-1] - lower[-2])
    mirror = np.array([1.0, -1.0])
    upper_full = np.vstack([port_xy_m[::-1], port_xy_m[1:] * mirror])
    lower_full = np.vstack([lower[::-1], lower[1:] * mirror])
    return upper_full, lower_full
