"""Ship–ice contact: crushed areas and contact forces per floe and bow panel (thesis §4.1.1, Alg. 3).

Everything here works in the **bow frame** (the bow at its start position, stem tip of the upper ice
waterline at the origin); the stepping engine translates floes into it. Pure functions on shapely
geometries and numpy arrays.

Default model (physics-notes §2.2, §2.3):
- zones: connected parts of F ∩ H_u (thesis §3.2: n_int = 2N intersection points bound N zones);
- per panel i: A_h,i = area(Z ∩ Q_i) with Q_i the footprint between the two waterlines, so that
  Σ A_h,i = A_u − A_l; A_c,i = A_h,i / sin ψ_i (Eq. 6 per panel), with a near-vertical guard;
- F_c = k_c σ_c A_c (Eq. 7), F_f = μ F_c (Eq. 8), ψ from the vertical:
  F_v = F_c (sin ψ − μ cos ψ) (clamped at 0), F_h = F_c (cos ψ + μ sin ψ), F_h along the panel's
  outward horizontal normal; zone totals are vector sums over panels.
Thesis-literal options: one ψ for the whole zone (Eq. 6 with ψ at the zone centre), Alg. 3 signs, or
Eqs. 9/10 taken literally (errata 9, 10).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, Literal

import numpy as np
import shapely

from floebreak import constants as c
from floebreak.errors import require_range
from floebreak.mechanics import contact_kernel, polygon_kernel

# Overlaps of at most a square micrometre are rounding, not contact: GEOS and the compiled kernel round
# differently (the kernel's clipped outline of a non-convex floe leaves ~1e-15 m² on zero-width bridges).
MIN_OVERLAP_M2 = 1e-12

AreaModel = Literal["per_panel", "single_psi"]
ForceSigns = Literal["consistent", "thesis_alg3", "thesis_eq9_10"]
NearVerticalGuard = Literal["vertical_face", "cap", "none"]


@dataclass(frozen=True)
class ContactParams:
    """Contact-model parameters (SI). Validated on construction; errors name the field and range."""

    crushing_strength_pa: float = c.CRUSHING_STRENGTH_PA
    contact_coefficient: float = c.CONTACT_COEFFICIENT
    friction_coefficient: float = c.FRICTION_COEFFICIENT
    psi_min_deg: float = c.PSI_MIN_DEG
    area_model: AreaModel = "per_panel"
    force_signs: ForceSigns = "consistent"
    near_vertical: NearVerticalGuard = "vertical_face"

    def __post_init__(self) -> None:
        require_range("contact.crushing_strength_pa", self.crushing_strength_pa, low=0.0, unit="Pa")
        require_range("contact.contact_coefficient", self.contact_coefficient, low=0.0)
        require_range("contact.friction_coefficient", self.friction_coefficient, low=0.0, low_inclusive=True)
        require_range(
            "contact.psi_min_deg", self.psi_min_deg, low=0.0, high=45.0, high_inclusive=False, unit="deg"
        )

    # the compiled kernels' inputs derived from the settings, once per parameter set rather than per batch
    @cached_property
    def near_vertical_code(self) -> int:
        return _code("contact.near_vertical", self.near_vertical, contact_kernel.NEAR_VERTICAL)

    @cached_property
    def force_signs_code(self) -> int:
        return _code("contact.force_signs", self.force_signs, contact_kernel.FORCE_SIGNS)

    @cached_property
    def sin_psi_min(self) -> float:
        return math.sin(math.radians(self.psi_min_deg))


def panel_forces(
    contact_area_m2: np.ndarray, psi_rad: np.ndarray, params: ContactParams
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Crushing, vertical and horizontal force [N] for contact areas A_c on panels of angle ψ (from vertical).

    Thesis Eqs. 7–10 / Alg. 3; sign convention per ``params.force_signs`` (physics-notes §2.3, erratum 9).
    The vertical force on the ice is downward-positive and clamped at 0 (a panel with tan ψ ≤ μ cannot
    push the ice down). Compiled: `contact_kernel.panel_forces`, which the contact evaluation uses too.
    """
    area, psi = np.broadcast_arrays(
        np.asarray(contact_area_m2, dtype=float), np.asarray(psi_rad, dtype=float)
    )
    f_c, f_v, f_h = contact_kernel.panel_forces(
        np.ascontiguousarray(area.ravel()),
        np.sin(psi.ravel()),
        np.cos(psi.ravel()),
        params.contact_coefficient * params.crushing_strength_pa,
        params.friction_coefficient,
        params.force_signs_code,
    )
    return f_c.reshape(area.shape), f_v.reshape(area.shape), f_h.reshape(area.shape)


def _code(key: str, value: str, choices: tuple[str, ...]) -> int:
    if value not in choices:
        raise ValueError(f"unknown {key} {value!r} (allowed: {', '.join(choices)})")
    return choices.index(value)


# crushing forces of two zones this close (relative) are equal: a mirror pair differs by ≈ 1e-14
DOMINANT_TIE_RELATIVE = 1e-9


@dataclass(frozen=True, eq=False)
class ContactZone:
    """One contact zone of a floe with the bow (bow frame), with per-panel results.

    Arrays indexed like ``panels``. Areas in m², forces in N; ``force_on_ice_xy_n`` is the summed
    horizontal force vector acting on the ice (the bow feels the opposite).
    """

    zone: int
    overlap: shapely.Geometry | _LazyOverlap  # Z = F ∩ H_u for this zone (see `overlap_upper`)
    centre_xy_m: np.ndarray  # "midBow": middle of the upper waterline inside the floe (thesis Alg. 5)
    centre_panel: int
    # outward unit normal of the centre panel (thesis Eq. 20); on a node between two panels (the stem of a
    # floe centred on it) the bisector of both (`contact_kernel.centre_normal`)
    centre_normal: np.ndarray
    a_u_m2: float
    a_l_m2: float
    panels: np.ndarray
    a_h_m2: np.ndarray
    a_c_m2: np.ndarray
    psi_rad: np.ndarray
    f_c_n: np.ndarray
    f_v_n: np.ndarray
    f_h_n: np.ndarray
    force_on_ice_xy_n: np.ndarray
    # the floe's extent along centre_normal and along the panel (thesis Alg. 2 box) if the kernel measured it
    floe_extent_m: tuple[float, float] | None = None

    @property
    def overlap_upper(self) -> shapely.Geometry:
        """Z = F ∩ H_u of this zone; where the compiled kernel found the zone, GEOS builds it on first use."""
        return self.overlap.geometry if isinstance(self.overlap, _LazyOverlap) else self.overlap

    @property
    def a_h_total_m2(self) -> float:
        return float(self.a_h_m2.sum())

    @property
    def crushing_force_n(self) -> float:
        return float(self.f_c_n.sum())

    @property
    def vertical_force_n(self) -> float:
        return float(self.f_v_n.sum())

    @property
    def horizontal_force_n(self) -> float:
        """Magnitude of the summed horizontal force vector on the ice [N]."""
        return float(np.hypot(*self.force_on_ice_xy_n))


@dataclass(frozen=True, eq=False)
class Contact:
    """All contact zones of one floe at one bow position. Empty ``zones`` means no contact."""

    zones: tuple[ContactZone, ...] = field(default_factory=tuple)
    floe_area_m2: float | None = None  # the floe's area where the kernel measured it on the way

    @property
    def in_contact(self) -> bool:
        return bool(self.zones)

    @property
    def dominant(self) -> ContactZone:
        """The zone with the largest crushing force; failure is evaluated there. Forces within
        `DOMINANT_TIE_RELATIVE` of the largest tie (a symmetric floe touching both shoulders: equal up to
        rounding), and the tie goes to the port zone (largest centre y): a documented rule, not the
        rounding of the forces nor the order in which GEOS returned the zones (which follows the ring's
        vertex order). The other zone is judged next, at the same bow position, on the piece the first
        break left (docs/model.md, "Breaking sequence")."""
        if len(self.zones) == 1:
            return self.zones[0]
        top = max(z.crushing_force_n for z in self.zones)
        tied = [z for z in self.zones if z.crushing_force_n >= top * (1.0 - DOMINANT_TIE_RELATIVE)]
        return max(tied, key=lambda z: float(z.centre_xy_m[1]))

    @property
    def force_on_ice_xyz_n(self) -> np.ndarray:
        """Total force on the ice (x, y horizontal; z = −F_v, i.e. downward is negative z) [N]."""
        horizontal = sum((z.force_on_ice_xy_n for z in self.zones), start=np.zeros(2))
        vertical = sum(z.vertical_force_n for z in self.zones)
        return np.array([horizontal[0], horizontal[1], -vertical])

    @property
    def force_on_bow_xyz_n(self) -> np.ndarray:
        return -self.force_on_ice_xyz_n


def evaluate_contact(
    floe_bow_frame: shapely.Geometry, thickness_m: float, geometry: BowContactGeometry, params: ContactParams
) -> Contact:
    """Contact zones, areas and forces of one floe (already translated into the bow frame).

    `geometry` is the bow's prepared contact geometry, `BowContactGeometry.from_bow(bow)`, built once per run.
    """
    return evaluate_contacts(np.array([floe_bow_frame], dtype=object), [thickness_m], geometry, params)[0]


def evaluate_contacts(
    floes_bow_frame: np.ndarray, thickness_m, geometry: BowContactGeometry, params: ContactParams
) -> list[Contact]:
    """`evaluate_contact` for many floes at once (one `Contact` per floe, in input order).

    The GEOS overlays of all floes (floe ∩ H_u, zone ∩ footprints, waterline ∩ floe) run as one vectorised
    shapely call each, and the per-panel areas and forces of all zones as one array computation.
    """
    floes = np.asarray(floes_bow_frame, dtype=object).reshape(-1)
    thickness = np.asarray(thickness_m, dtype=float).reshape(-1)
    contacts = [Contact()] * len(floes)
    if len(floes) == 0:
        return contacts
    if geometry.kernel is None:
        tables = [_zone_table_shapely(floes, np.arange(len(floes)), geometry)]
    else:
        table, fallback = _zone_table_kernel(floes, geometry.kernel)
        tables = [table, _zone_table_zones_by_geos(floes, fallback, geometry) if fallback.size else None]
    for table in tables:
        if table is not None:
            _add_contacts(contacts, table, floes, thickness, geometry, params)
    return contacts


def _add_contacts(contacts, table: _ZoneTable, floes, thickness, geometry, params: ContactParams) -> None:
    """Areas and forces of the table's zones (one compiled call), set as the contacts of their floes."""
    single_psi = params.area_model == "single_psi"
    near_vertical, sin_psi_min = params.near_vertical_code, params.sin_psi_min
    # the length of a near-vertical row's panel inside its floe, where the kernel has not measured it
    if single_psi:  # one row per zone, at the centre panel
        overlap, panels, floe_of_row = np.full(len(table.zones), np.nan), table.centre_panel, table.owner
    else:
        overlap, panels, floe_of_row = table.row_overlap_m, table.row_panel, table.owner[table.row_zone]
    if near_vertical == 0 and (single_psi or not table.rows_measured):
        missing = np.isnan(overlap) & (geometry.panel_sin[panels] < sin_psi_min)
        if missing.any():
            rows = np.flatnonzero(missing)
            overlap = overlap.copy()
            overlap[rows] = shapely.length(
                shapely.intersection(geometry.panel_segments[panels[rows]], floes[floe_of_row[rows]])
            )
    a_l, _, row_panel, row_a_h, row_a_c, row_f_c, row_f_v, row_f_h, zone_force_xy, start = (
        contact_kernel.zone_forces(
            table.row_zone,
            table.row_panel,
            table.row_a_h_m2,
            overlap,
            thickness[table.owner],
            table.a_u_m2,
            table.centre_panel,
            single_psi,
            geometry.panel_sin,
            geometry.panel_cos,
            geometry.panel_normals,
            params.contact_coefficient * params.crushing_strength_pa,
            params.friction_coefficient,
            sin_psi_min,
            near_vertical,
            params.force_signs_code,
        )
    )
    row_psi = geometry.panel_psi_rad[row_panel]
    parts, hull, lazy = table.zones, geometry.hull_upper, table.overlap_is_floe_and_hull
    start, a_u, a_l = start.tolist(), table.a_u_m2.tolist(), a_l.tolist()
    centres, centre_panels = table.centre_xy_m, table.centre_panel.tolist()
    normals = contact_kernel.centre_normals(
        np.asarray(centres, dtype=float),
        np.asarray(table.centre_panel, dtype=np.int64),
        geometry.waterline_xy_m,
        geometry.panel_normals,
    )
    if single_psi:  # the zone's one row acts along the centre's normal (on the stem: the centreline)
        zone_force_xy = row_f_h[:, None] * normals
    floe_areas, extents = table.floe_area_m2.tolist(), table.floe_extent_m.tolist()
    zones_of_floe: dict[int, list[ContactZone]] = {}
    for k, floe_index in enumerate(table.owner.tolist()):
        zones = zones_of_floe.setdefault(floe_index, [])
        rows = slice(start[k], start[k + 1])
        extent, area = extents[k], floe_areas[k]
        zones.append(
            ContactZone(
                zone=len(zones),
                overlap=_LazyOverlap(parts[k], hull) if lazy else parts[k],
                centre_xy_m=centres[k],
                centre_panel=centre_panels[k],
                centre_normal=normals[k],
                a_u_m2=a_u[k],
                a_l_m2=a_l[k],
                panels=row_panel[rows],
                a_h_m2=row_a_h[rows],
                a_c_m2=row_a_c[rows],
                psi_rad=row_psi[rows],
                f_c_n=row_f_c[rows],
                f_v_n=row_f_v[rows],
                f_h_n=row_f_h[rows],
                force_on_ice_xy_n=zone_force_xy[k],
                floe_extent_m=None if extent[0] != extent[0] else (extent[0], extent[1]),  # NaN: not measured
            )
        )
        contacts[floe_index] = Contact(tuple(zones), None if area != area else area)


# --- internals --------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class BowContactGeometry:
    """Prepared, indexed bow geometry for fast contact queries (built once per bow)."""

    hull_upper: shapely.Polygon
    waterline: shapely.LineString  # the upper ice waterline polyline (without the aft closure)
    waterline_xy_m: np.ndarray  # its nodes (n_panels + 1, 2)
    node_distance_m: np.ndarray  # cumulative length along the waterline at each node
    footprints: np.ndarray
    footprint_tree: shapely.STRtree
    panel_segments: np.ndarray  # upper panel segments as LineStrings
    panel_normals: np.ndarray
    panel_psi_rad: np.ndarray
    panel_sin: np.ndarray  # sin ψ_i, cos ψ_i per panel, for the force kernel
    panel_cos: np.ndarray
    kernel: _ConvexBow | None = None  # arrays for the compiled kernel; None: a non-convex bow, shapely only
    hull_rings: tuple | None = None  # `polygon_kernel.ring_arrays(hull_upper)` for the failure modes' probes

    @classmethod
    def from_bow(cls, bow) -> BowContactGeometry:
        """Prepare a `floebreak.ship.bow.Bow` for contact queries (prepared hull, STRtree of footprints)."""
        upper = np.asarray(bow.upper_xy_m, dtype=float)
        hull_upper = shapely.Polygon(bow.hull_upper.exterior.coords)
        shapely.prepare(hull_upper)
        steps = np.hypot(*np.diff(upper, axis=0).T)
        node_distance = np.concatenate([[0.0], np.cumsum(steps)])
        footprints = np.asarray(bow.panel_footprints, dtype=object)
        return cls(
            hull_upper=hull_upper,
            waterline=shapely.LineString(upper),
            waterline_xy_m=np.array(upper),  # a writable copy: one compiled signature
            node_distance_m=node_distance,
            footprints=footprints,
            footprint_tree=shapely.STRtree(footprints),
            panel_segments=shapely.linestrings(np.stack([upper[:-1], upper[1:]], axis=1)),
            panel_normals=np.array(bow.panel_normals, dtype=float),  # writable: one compiled signature
            panel_psi_rad=np.asarray(bow.panel_psi_rad, dtype=float),
            panel_sin=np.sin(np.asarray(bow.panel_psi_rad, dtype=float)),
            panel_cos=np.cos(np.asarray(bow.panel_psi_rad, dtype=float)),
            kernel=_ConvexBow.from_bow(hull_upper, footprints, upper, node_distance, bow.panel_normals),
            hull_rings=polygon_kernel.ring_arrays(hull_upper),
        )


@dataclass(frozen=True, eq=False)
class _ConvexBow:
    """The bow as plain arrays for `contact_kernel.contact_batch` (only built when H_u and every footprint
    are convex single polygons: the kernel's clipping needs convex clip polygons)."""

    hull_x: np.ndarray
    hull_y: np.ndarray
    quad_x: np.ndarray
    quad_y: np.ndarray
    quad_bounds: np.ndarray
    waterline_xy: np.ndarray
    node_distance_m: np.ndarray
    panel_normals: np.ndarray

    @classmethod
    def from_bow(cls, hull_upper, footprints, upper_xy, node_distance_m, panel_normals) -> _ConvexBow | None:
        single = (shapely.get_type_id(footprints) == 3) & ~shapely.is_empty(footprints)
        if not single.all():  # a blunt bow's footprint can be a bow-tie's two triangles (or nothing)
            return None
        hull = contact_kernel.ccw_ring(shapely.get_coordinates(hull_upper.exterior))
        quads = [contact_kernel.ccw_ring(shapely.get_coordinates(q.exterior)) for q in footprints]
        if any(len(q) != 4 for q in quads) or not all(map(contact_kernel.is_convex_ring, [hull, *quads])):
            return None
        quads = np.stack(quads)
        return cls(
            hull_x=np.ascontiguousarray(hull[:, 0]),
            hull_y=np.ascontiguousarray(hull[:, 1]),
            quad_x=np.ascontiguousarray(quads[:, :, 0]),
            quad_y=np.ascontiguousarray(quads[:, :, 1]),
            quad_bounds=np.ascontiguousarray(shapely.bounds(footprints)),
            waterline_xy=np.array(upper_xy, dtype=float),  # a writable copy: one compiled signature
            node_distance_m=node_distance_m,
            panel_normals=np.array(panel_normals, dtype=float),  # writable copy: one compiled signature
        )


class _LazyOverlap:
    """F ∩ H_u of a floe with exactly one zone, computed once when first asked for (only the `max_distance`
    loading-radius model needs the polygon; everything else comes from the kernel's numbers)."""

    __slots__ = ("_floe", "_geometry", "_hull")

    def __init__(self, floe: shapely.Geometry, hull: shapely.Geometry):
        self._floe, self._hull, self._geometry = floe, hull, None

    @property
    def geometry(self) -> shapely.Geometry:
        if self._geometry is None:
            self._geometry = shapely.intersection(self._floe, self._hull)
        return self._geometry


@dataclass(frozen=True, eq=False)
class _ZoneTable:
    """Zones of a batch (one row per zone, grouped by floe) and their panel rows (sorted by zone, panel)."""

    zones: np.ndarray  # Z = F ∩ H_u per zone (shapely polygons), or F where `overlap_is_floe_and_hull`
    overlap_is_floe_and_hull: bool  # True: each zone is all of F ∩ H_u, computed only when asked for
    owner: np.ndarray  # index of each zone's floe in the batch
    a_u_m2: np.ndarray
    centre_xy_m: np.ndarray
    centre_panel: np.ndarray
    row_zone: np.ndarray
    row_panel: np.ndarray
    row_a_h_m2: np.ndarray
    row_overlap_m: np.ndarray  # length of the row's upper panel segment inside the floe; NaN: not computed
    floe_area_m2: np.ndarray  # area of each zone's floe; NaN: not computed
    floe_extent_m: np.ndarray  # (n, 2) floe extent along the centre normal and along the panel; NaN: idem
    rows_measured: bool = False  # every row's `row_overlap_m` is measured (no NaN): the kernel's tables


def _zone_table_kernel(floes, bow: _ConvexBow) -> tuple[_ZoneTable | None, np.ndarray]:
    """`contact_kernel.contact_batch` on the floes that are polygons without holes: the table, and the floes
    left to shapely (the others, and those the kernel hands over), in batch order."""
    simple = (shapely.get_type_id(floes) == 3) & (shapely.get_num_interior_rings(floes) == 0)
    all_simple = bool(simple.all())
    if all_simple:
        coords, which = shapely.get_coordinates(floes, return_index=True)
    else:
        fast = np.flatnonzero(simple)
        coords, which = shapely.get_coordinates(floes[fast], return_index=True)
        which = fast[which]
    status, owner, a_u, centre, centre_panel, floe_area, extent, row_zone, row_panel, row_a_h, row_overlap = (
        contact_kernel.contact_batch(
            coords,
            which,
            len(floes),
            bow.hull_x,
            bow.hull_y,
            bow.quad_x,
            bow.quad_y,
            bow.quad_bounds,
            bow.waterline_xy,
            bow.node_distance_m,
            bow.panel_normals,
            MIN_OVERLAP_M2,
        )
    )
    handed_over = status == contact_kernel.FALLBACK
    fallback = np.flatnonzero(handed_over if all_simple else handed_over | ~simple)
    if owner.size == 0:
        return None, fallback
    table = _ZoneTable(
        zones=floes[owner],  # one zone per floe: Z = F ∩ H_u, built by GEOS only if asked for
        overlap_is_floe_and_hull=True,
        owner=owner,
        a_u_m2=a_u,
        centre_xy_m=centre,
        centre_panel=centre_panel,
        row_zone=row_zone,
        row_panel=row_panel,
        row_a_h_m2=row_a_h,
        row_overlap_m=row_overlap,
        floe_area_m2=floe_area,
        floe_extent_m=extent,
        rows_measured=True,
    )
    return table, fallback


def _geos_zones(floes, index, geometry: BowContactGeometry):
    """(zones, their floe, A_u): the connected parts of F ∩ H_u of floes[index] with area, by GEOS."""
    if len(index) == 0:
        return None
    index = index[shapely.intersects(geometry.hull_upper, floes[index])]
    if index.size == 0:
        return None
    overlaps = shapely.intersection(floes[index], geometry.hull_upper)
    parts, owner = shapely.get_parts(overlaps, return_index=True)
    if parts.size:
        is_polygon = shapely.get_type_id(parts) == 3
        areas = shapely.area(parts)
        keep = is_polygon & (areas > MIN_OVERLAP_M2)
        parts, owner, areas = parts[keep], index[owner[keep]], areas[keep]
    if parts.size == 0:
        return None
    return parts, owner, areas


def _zone_table_shapely(floes, index, geometry: BowContactGeometry) -> _ZoneTable | None:
    """GEOS overlays for floes[index] (any polygon, any bow): connected parts of F ∩ H_u are the zones."""
    zones = _geos_zones(floes, index, geometry)
    if zones is None:
        return None
    parts, owner, areas = zones
    return _table_of_zones(parts, owner, areas, *_geos_rows_and_centres(parts, owner, floes, geometry))


def _geos_rows_and_centres(parts, owner, floes, geometry: BowContactGeometry):
    """(centres, centre panels, row zone, row panel, row A_h) of GEOS zones, all by GEOS overlays."""
    row_zone, row_panel, row_a_h = _panel_areas(parts, geometry)
    centres, centre_panels = _zone_centres(parts, owner, floes, geometry)
    return centres, centre_panels, row_zone, row_panel, row_a_h


def _table_of_zones(
    parts, owner, areas, centres, centre_panels, row_zone, row_panel, row_a_h, row_overlap=None
) -> _ZoneTable:
    """A table of zones found by GEOS (the floe's area and box are not measured on this path)."""
    return _ZoneTable(
        zones=parts,
        overlap_is_floe_and_hull=False,
        owner=owner,
        a_u_m2=areas,
        centre_xy_m=centres,
        centre_panel=centre_panels,
        row_zone=row_zone,
        row_panel=row_panel,
        row_a_h_m2=row_a_h,
        row_overlap_m=np.full(len(row_zone), np.nan) if row_overlap is None else row_overlap,
        floe_area_m2=np.full(len(parts), np.nan),
        floe_extent_m=np.full((len(parts), 2), np.nan),
        rows_measured=row_overlap is not None,  # `zone_rows` measures every row
    )


def _zone_table_zones_by_geos(floes, index, geometry: BowContactGeometry) -> _ZoneTable | None:
    """The floes the kernel hands over (several zones each, against a convex bow): the zones F ∩ H_u by GEOS,
    their panel rows and centres by `contact_kernel.zone_rows` (same definitions as `_zone_table_shapely`,
    which takes over for floes or zones with holes and for degenerate cases)."""
    zones = _geos_zones(floes, index, geometry)
    if zones is None:
        return None
    parts, owner, areas = zones
    floe_ids, zone_floe = np.unique(owner, return_inverse=True)
    own_floes = floes[floe_ids]
    simple = (
        (shapely.get_num_interior_rings(parts) == 0).all()
        and (shapely.get_type_id(own_floes) == 3).all()
        and (shapely.get_num_interior_rings(own_floes) == 0).all()
    )
    if simple:
        zone_coords, zone_index = shapely.get_coordinates(parts, return_index=True)
        floe_coords, floe_index = shapely.get_coordinates(own_floes, return_index=True)
        bow = geometry.kernel
        result = contact_kernel.zone_rows(
            zone_coords,
            zone_index,
            len(parts),
            zone_floe.reshape(-1),
            floe_coords,
            floe_index,
            len(floe_ids),
            bow.quad_x,
            bow.quad_y,
            bow.quad_bounds,
            bow.waterline_xy,
            bow.node_distance_m,
            MIN_OVERLAP_M2,
            _ON_BOUNDARY_M,
        )
        ok, row_zone, row_panel, row_a_h, row_overlap, centres, centre_panels, found = result
        if ok:
            if not found.all():  # a zone clear of the waterline: the nearest waterline point (GEOS)
                missing = np.flatnonzero(~found)
                centres[missing], centre_panels[missing] = _nearest_waterline_points(parts[missing], geometry)
            return _table_of_zones(
                parts, owner, areas, centres, centre_panels, row_zone, row_panel, row_a_h, row_overlap
            )
    return _table_of_zones(parts, owner, areas, *_geos_rows_and_centres(parts, owner, floes, geometry))


def _panel_areas(
    zones: np.ndarray, geometry: BowContactGeometry
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rows (zone, panel, A_h,i > 0) of every zone × footprint overlap, sorted by zone then panel — one
    STRtree query and one vectorised intersection for all zones."""
    zone_index, panel = geometry.footprint_tree.query(zones, predicate="intersects")
    order = np.lexsort((panel, zone_index))
    zone_index, panel = zone_index[order], panel[order]
    a_h = shapely.area(shapely.intersection(zones[zone_index], geometry.footprints[panel]))
    keep = a_h > MIN_OVERLAP_M2
    return zone_index[keep], panel[keep], a_h[keep]


def _zone_centres(
    zones: np.ndarray, zone_owner: np.ndarray, floes: np.ndarray, geometry: BowContactGeometry
) -> tuple[np.ndarray, np.ndarray]:
    """Middle of the upper waterline inside each zone's floe, and the panel it lies on (thesis "midBow").

    The waterline is intersected with the *floe* (whose outline crosses it transversally), not with the zone
    Z = F ∩ H_u, whose edge is the waterline itself: that overlay of collinear segments is numerically fragile
    and made mirrored floes differ port/starboard. Of the parts of waterline ∩ F, those on the zone's boundary
    count; the middle of the longest is the centre (of tied longest parts, the middle of their span:
    `_middles_of_longest`). A zone that does not reach the waterline (a piece already
    inside the hull) takes the nearest waterline point.
    """
    zones_of_floe: dict[int, list[int]] = {}
    for k, floe_index in enumerate(zone_owner.tolist()):
        zones_of_floe.setdefault(floe_index, []).append(k)
    owners = list(zones_of_floe)
    # parts meeting at a vertex of F on the waterline are one line (`contact_kernel._merge_touching`)
    inside = shapely.line_merge(shapely.intersection(geometry.waterline, floes[owners]))
    lines, line_floe = shapely.get_parts(inside, return_index=True)
    found: list[list[tuple[float, Any]]] = [[] for _ in range(len(zones))]
    if lines.size:
        lengths = shapely.length(lines)
        usable = (shapely.get_type_id(lines) == 1) & (lengths > 0.0)
        for line, j, length, ok in zip(lines, line_floe.tolist(), lengths.tolist(), usable, strict=True):
            if not ok:
                continue
            candidates = zones_of_floe[owners[j]]
            if len(candidates) > 1:  # a floe with several zones: the line belongs to the zones it bounds
                candidates = [k for k in candidates if shapely.dwithin(line, zones[k], _ON_BOUNDARY_M)]
            for k in candidates:
                found[k].append((length, line))
    centres = _middles_of_longest(found, geometry)
    has_line = centres != None  # noqa: E711 (element-wise on an object array)
    if (~has_line).any():
        nearest = shapely.shortest_line(zones[~has_line], geometry.waterline)
        centres[~has_line] = shapely.get_point(nearest, 1)
    return shapely.get_coordinates(centres), _panel_at(centres, geometry)


def _middles_of_longest(found: list[list[tuple[float, Any]]], geometry: BowContactGeometry) -> np.ndarray:
    """Per zone, from its waterline parts [(length, line)]: the middle of the longest part, or, where parts
    tie as the longest (within `contact_kernel.ON_NODE_M`: a symmetric floe straddling the stem), the
    waterline point halfway between the first tied part's start and the last one's end — mirror-equivariant,
    where taking the first (port) part was not (as `contact_kernel._longest_span`); None for a zone
    without parts."""
    tolerance = contact_kernel.ON_NODE_M
    longest = np.full(len(found), None, dtype=object)
    centres = np.full(len(found), None, dtype=object)
    for k, parts in enumerate(found):
        if parts:
            top = max(length for length, _ in parts)
            tied = [line for length, line in parts if length >= top - tolerance]
            if len(tied) == 1:
                longest[k] = tied[0]
            else:
                ends = shapely.points(shapely.get_coordinates(tied))
                at = shapely.line_locate_point(geometry.waterline, ends)
                centres[k] = shapely.line_interpolate_point(geometry.waterline, 0.5 * (at.min() + at.max()))
    single = longest != None  # noqa: E711
    if single.any():
        centres[single] = shapely.line_interpolate_point(longest[single], 0.5, normalized=True)
    return centres


def _nearest_waterline_points(zones, geometry: BowContactGeometry) -> tuple[np.ndarray, np.ndarray]:
    """The waterline point nearest to each zone (a zone clear of the waterline) and its panel."""
    points = shapely.get_point(shapely.shortest_line(zones, geometry.waterline), 1)
    return shapely.get_coordinates(points), _panel_at(points, geometry)


def _panel_at(points, geometry: BowContactGeometry) -> np.ndarray:
    """The panel of each waterline point (by its arc length along the waterline)."""
    distance = shapely.line_locate_point(geometry.waterline, points)
    return np.clip(np.searchsorted(geometry.node_distance_m, distance) - 1, 0, len(geometry.footprints) - 1)


_ON_BOUNDARY_M = 1e-6  # a waterline part of F lies on the boundary of its zone up to rounding
