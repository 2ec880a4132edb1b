"""Cusp transport under the hull: which cusp reaches which propeller, when, and where it enters the disc.

A kinematic model (docs/model.md, "Cusp transport under the hull"). Frames: the field frame of the run
(x forward, y to port, the bow's upper stem tip at x = 0 at the start; docs/architecture.md "Frames"); depths
z are positive downwards from the still waterline. Per cusp:

1. **Region** (where it was made): the cusp's centroid relative to the bow when it was made,
   x_b = centroid_x − bow_x, gives the region by the dispatch rule (`failure.dispatch.bow_region`):
   "shoulder" when −x_b / L_b ≥ `shoulder_region_start`, else "stem".
2. **Shoulder** cusps are pushed down along the near-vertical shoulder flare and rise beside the hull
   (`shoulder_cusps_submerge = False`, default); they reach no propeller.
3. **Lateral path**: a stem cusp slides down the bow and aft along the flat bottom at its entry offset
   y (buttock flow; with `lateral_spread_m` > 0 and a `numpy.random.Generator`, a normal scatter of that
   standard deviation is added). A cusp whose centroid lies beyond the flat bottom's half-width
   B/2 − r_bilge lies on the bilge, where buoyancy drives it up and out along the hull: it surfaces beside
   the hull.
4. **Vertical path**: on the flat bottom the cusp's top face is at the draught T. Over the stern run
   (length L_run, rising from T to the hull above the discs, z_h = z_shaft − R − c_tip) it rises at its
   terminal buoyant speed w = √(2 g h (ρ_w − ρ_i) / (ρ_w C_D)) for the time L_run / v_rel, but not above the
   hull: z_top = max(z_h, T − w L_run / v_rel).
5. **Contact**: the cusp's cross-section at the propeller plane, lateral [y − a, y + a] with
   a = √A / 2 (orientation unknown: half the side of the square of equal area) and depth
   [z_top, z_top + h], reaches a propeller when it intersects the disc (centre (y_s, z_s), radius R). Of
   several discs the one whose axis is nearest to the cross-section wins (ties: the lower index).
6. **Entry point**: the point of the cross-section nearest to the shaft axis (the deepest the blades cut):
   radius fraction r / R and angle θ from top dead centre, positive towards port, seen from aft
   (θ = atan2(Δy, −Δz)). A cross-section covering the axis gives r = 0, θ = 0.
7. **Arrival time**: made at t_0 = bow_x / v; travels the distance L_p + x_b from its centroid to the
   propeller plane (L_p aft of the stem) at v_rel = s v (slip factor s; s = 1: ice at rest in the earth
   frame): t = t_0 + (L_p + x_b) / (s v).

Only cusps are candidates: flipped pieces are pushed aside (thesis §4.4) and are not passed here.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Annotated, Any, Final

import numpy as np

from floebreak import constants as c
from floebreak.errors import Bounds, InputError, check_bounds, require_range
from floebreak.ship.agulhas_ii import (
    BEAM_M,
    BILGE_RADIUS_M,
    BOW_LENGTH_M,
    DISC_BOTTOM_ABOVE_BASE_M,
    DRAUGHT_M,
    PROPELLER_DIAMETER_M,
    PROPELLER_PLANE_AFT_OF_STEM_M,
    RUN_LENGTH_M,
    SHAFT_DEPTH_M,
    SHAFT_SPREAD_M,
    TIP_CLEARANCE_M,
)

NO_PROPELLER: Final = -1
# why a cusp reaches no propeller (`CuspTransport.path`); "surfaced" and "stalled" come from the flow
# transport (`floebreak.propeller.flow_transport`)
PATHS: Final = ("propeller", "shoulder", "bilge", "missed", "surfaced", "stalled")
PATH_PROPELLER, PATH_SHOULDER, PATH_BILGE, PATH_MISSED = range(4)


@dataclass(frozen=True)
class HullUnderwater:
    """The underwater hull as the transport sees it. Defaults: S.A. Agulhas II (docs/model.md, "Cusp
    transport under the hull", gives each value's source; ASSUMED values are marked there)."""

    beam_m: Annotated[float, Bounds(1.0, 100.0, unit="m")] = BEAM_M
    """waterline beam B [m] (thesis §3)"""
    draught_m: Annotated[float, Bounds(0.5, 30.0, unit="m")] = DRAUGHT_M
    """draught T [m], depth of the flat bottom (thesis §3)"""
    bilge_radius_m: Annotated[float, Bounds(0.0, 50.0, unit="m")] = BILGE_RADIUS_M
    """bilge radius r_bilge [m]; flat-bottom half-width B/2 − r_bilge (ASSUMED)"""
    bow_length_m: Annotated[float, Bounds(0.0, 500.0, low_inclusive=False, unit="m")] = BOW_LENGTH_M
    """stem-to-shoulder length L_b [m] (the parametric Agulhas II bow, `ship.hulls.agulhas_ii`)"""
    propeller_plane_aft_of_stem_m: Annotated[float, Bounds(1.0, 1000.0, unit="m")] = (
        PROPELLER_PLANE_AFT_OF_STEM_M
    )
    """L_p, distance from the stem tip (ice waterline) aft to the propeller plane [m] (ASSUMED from
    L_pp ≈ 121.8 m)"""
    run_length_m: Annotated[float, Bounds(0.0, 200.0, low_inclusive=False, unit="m")] = RUN_LENGTH_M
    """L_run, length of the stern run over which the hull rises from the flat bottom to above the discs
    [m] (ASSUMED)"""

    def __post_init__(self) -> None:
        check_bounds(self, "transport.hull")
        if self.bilge_radius_m > 0.5 * self.beam_m:
            raise InputError(
                "transport.hull.bilge_radius_m",
                f"{self.bilge_radius_m:g} m exceeds half the beam ({0.5 * self.beam_m:g} m)",
                value=self.bilge_radius_m,
                allowed=f"[0, {0.5 * self.beam_m:g}] m",
            )

    @property
    def flat_half_width_m(self) -> float:
        """Half-width of the flat bottom, B/2 − r_bilge [m]."""
        return 0.5 * self.beam_m - self.bilge_radius_m


@dataclass(frozen=True)
class Propeller:
    """One open propeller: lateral offset of its shaft line (y to port), diameter and shaft depth."""

    offset_y_m: Annotated[float, Bounds(-50.0, 50.0, unit="m")]
    """y_s, lateral offset of the shaft line [m], positive to port"""
    diameter_m: Annotated[float, Bounds(0.0, 20.0, low_inclusive=False, unit="m")] = PROPELLER_DIAMETER_M
    """D [m] (thesis Table 9: r = 2.15 m)"""
    shaft_depth_m: Annotated[float, Bounds(0.0, 30.0, low_inclusive=False, unit="m")] = SHAFT_DEPTH_M
    """z_s, immersion of the shaft axis below the waterline [m] (ASSUMED: disc bottom 0.25 m above the
    base line, T − R − 0.25 m)"""

    def __post_init__(self) -> None:
        check_bounds(self, "transport.propeller")

    @property
    def radius_m(self) -> float:
        return 0.5 * self.diameter_m


@dataclass(frozen=True)
class PropellerArrangement:
    """The propellers and the hull's clearance above their discs. Default: two shafts at ±5.5 m (ASSUMED)."""

    propellers: tuple[Propeller, ...] = (
        Propeller(SHAFT_SPREAD_M),
        Propeller(-SHAFT_SPREAD_M),
    )
    tip_clearance_m: Annotated[float, Bounds(0.0, 10.0, unit="m")] = TIP_CLEARANCE_M
    """c_tip, vertical gap between the hull and the disc's top [m] (ASSUMED 0.2 D)"""

    def __post_init__(self) -> None:
        check_bounds(self, "transport.arrangement")
        if not 1 <= len(self.propellers) <= 8:
            raise InputError(
                "transport.arrangement.propellers",
                f"{len(self.propellers)} propellers",
                value=len(self.propellers),
                allowed="1 to 8",
            )
        for k, prop in enumerate(self.propellers):
            if prop.shaft_depth_m - prop.radius_m - self.tip_clearance_m < 0.0:
                raise InputError(
                    f"transport.arrangement.propellers[{k}].shaft_depth_m",
                    f"{prop.shaft_depth_m:g} m puts the hull above the disc out of the water (needs "
                    f"≥ R + tip_clearance_m = {prop.radius_m + self.tip_clearance_m:g} m)",
                    value=prop.shaft_depth_m,
                    allowed=f"≥ {prop.radius_m + self.tip_clearance_m:g} m",
                )


@dataclass(frozen=True)
class TransportParameters:
    """Parameters of the transport (docs/model.md, "Cusp transport under the hull")."""

    slip_factor: Annotated[float, Bounds(0.0, 1.0, low_inclusive=False)] = 1.0
    """s, ice speed relative to the hull / ship speed [-], in (0, 1]: 1 = ice at rest in the earth frame"""
    drag_coefficient: Annotated[float, Bounds(0.3, 3.0)] = 1.17
    """C_D of a cusp rising flat-face first [-] (square plate normal to the flow, Hoerner 1965)"""
    lateral_spread_m: Annotated[float, Bounds(0.0, 10.0, unit="m")] = 0.0
    """standard deviation of the lateral scatter between entry and propeller plane [m] (needs `rng`)"""
    shoulder_region_start: Annotated[float, Bounds(0.0, 1.0)] = 0.5
    """fraction of L_b where the shoulder region begins (`failure.shoulder_region_start`)"""
    shoulder_cusps_submerge: bool = False
    """True: shoulder cusps go under the hull like stem cusps; False: they rise beside the hull"""

    def __post_init__(self) -> None:
        check_bounds(self, "transport")


@dataclass(frozen=True)
class FlowParameters:
    """The flow transport's own parameters (docs/explanation/cusp-flow.md gives each source)."""

    drag_coefficient_range: tuple[float, float] = (0.5, 1.5)
    """C_D of a cusp, sampled uniformly per cusp [-] (bluff plates and blocks, Hoerner 1965)"""
    friction_range: tuple[float, float] = (0.05, 0.15)
    """μ of ice on the hull, sampled uniformly per cusp [-] (Tatinclaux & Murdey 1985; ATTC 1995)"""
    stem_angle_deg: Annotated[float, Bounds(5.0, 90.0, unit="deg")] = 27.0
    """φ_s, stem angle from the horizontal [deg] (physics-notes §6.2, interpretation a)"""
    time_step_s: Annotated[float, Bounds(0.001, 1.0, unit="s")] = 0.1
    """shortest integration step [s]; each cusp steps 0.25 m (docs/explanation/cusp-flow.md, "Integration")"""

    def __post_init__(self) -> None:
        check_bounds(self, "transport.flow")
        for key, (low, high), allowed in (
            ("drag_coefficient_range", self.drag_coefficient_range, (0.1, 3.0)),
            ("friction_range", self.friction_range, (0.0, 1.0)),
        ):
            if not allowed[0] <= low <= high <= allowed[1]:
                raise InputError(
                    f"transport.flow.{key}",
                    f"({low:g}, {high:g}) is not an ordered range within [{allowed[0]:g}, {allowed[1]:g}]",
                    value=[low, high],
                    allowed=f"low ≤ high within [{allowed[0]:g}, {allowed[1]:g}]",
                )


@dataclass(frozen=True)
class CuspTransport:
    """Per cusp (input order): propeller index (−1 = none), arrival time [s], entry point in the disc
    (radius fraction r/R and angle from top dead centre [deg], NaN without a propeller), region
    ("stem"/"shoulder") and path (index into `PATHS`). `cross_section_m`: the cross-section of step 5
    relative to the reached propeller's shaft centre, (y_lo, y_hi, z_lo, z_hi) [m] (y to port, z depth
    positive down), NaN without a propeller (None when not computed); `propeller.engagement` turns it into
    the blade's engaged interval."""

    propeller_index: np.ndarray
    arrival_time_s: np.ndarray
    entry_radius_fraction: np.ndarray
    entry_angle_deg: np.ndarray
    region: np.ndarray
    path: np.ndarray
    n_propellers: int = field(default=2)
    cross_section_m: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None = None

    @property
    def n_cusps(self) -> int:
        return int(self.propeller_index.size)

    def counts(self) -> np.ndarray:
        """Cusps reaching each propeller."""
        reached = self.propeller_index[self.propeller_index >= 0]
        return np.bincount(reached, minlength=self.n_propellers)

    def fractions(self) -> np.ndarray:
        """Fraction of the cusps reaching each propeller."""
        return self.counts() / self.n_cusps if self.n_cusps else np.zeros(self.n_propellers)

    def path_counts(self) -> dict[str, int]:
        return {name: int(np.sum(self.path == k)) for k, name in enumerate(PATHS)}


def terminal_rise_speed_m_s(thickness_m: np.ndarray, drag_coefficient: float) -> np.ndarray:
    """Terminal buoyant rise speed of a flat cusp [m/s]: net buoyancy (ρ_w − ρ_i) g A h balances the drag
    ½ ρ_w C_D A w², so w = √(2 g h (ρ_w − ρ_i) / (ρ_w C_D))."""
    rho_w, rho_i = c.SEAWATER_DENSITY_KG_M3, c.ICE_DENSITY_KG_M3
    h = np.asarray(thickness_m, dtype=float)
    return np.sqrt(2.0 * c.GRAVITY_M_S2 * h * (rho_w - rho_i) / (rho_w * drag_coefficient))


def cusp_regions(
    bow_x_m: np.ndarray, centroid_x_m: np.ndarray, bow_length_m: float, shoulder_region_start: float
) -> np.ndarray:
    """ "stem"/"shoulder" per cusp by the dispatch rule (`failure.dispatch.bow_region`) on the centroid's
    position aft of the stem when the cusp was made."""
    fraction = -(np.asarray(centroid_x_m, dtype=float) - np.asarray(bow_x_m, dtype=float)) / bow_length_m
    return np.where(fraction >= shoulder_region_start, "shoulder", "stem")


def _nearest_point(y_lo, y_hi, z_lo, z_hi, y_s: float, z_s: float):
    """Point of each rectangle [y_lo, y_hi] × [z_lo, z_hi] nearest to (y_s, z_s)."""
    return np.clip(y_s, y_lo, y_hi), np.clip(z_s, z_lo, z_hi)


def _checked_columns(columns: Mapping[str, Any]) -> dict[str, np.ndarray]:
    arrays = {key: np.asarray(value, dtype=float).ravel() for key, value in columns.items()}
    n = {a.size for a in arrays.values()}
    if len(n) > 1:
        sizes = ", ".join(f"{k} {a.size}" for k, a in arrays.items())
        raise InputError("transport.cusps", f"columns differ in length ({sizes})")
    for key, a in arrays.items():
        if not np.all(np.isfinite(a)):
            raise InputError(f"transport.cusps.{key}", "has non-finite values", allowed="finite numbers")
    for key in ("area_m2", "thickness_m"):
        if np.any(arrays[key] <= 0.0):
            raise InputError(f"transport.cusps.{key}", "has values ≤ 0", allowed="> 0")
    return arrays


def transport_cusps(
    bow_x_m,
    centroid_x_m,
    centroid_y_m,
    area_m2,
    thickness_m,
    *,
    speed_m_s: float = c.SHIP_SPEED_IN_ICE_M_S,
    hull: HullUnderwater = HullUnderwater(),
    arrangement: PropellerArrangement = PropellerArrangement(),
    params: TransportParameters = TransportParameters(),
    rng: np.random.Generator | None = None,
) -> CuspTransport:
    """Which propeller each cusp reaches, when, and where it enters the disc (module docstring, steps 1–7).

    Inputs per cusp (field frame, metres): the bow position when it was made, its centroid, area and
    thickness. `rng` is needed only for `params.lateral_spread_m` > 0.
    """
    v = require_range(
        "ship.speed_m_s", speed_m_s, low=c.SHIP_SPEED_RANGE_M_S[0], high=c.SHIP_SPEED_RANGE_M_S[1], unit="m/s"
    )
    cols = _checked_columns(
        {
            "bow_x_m": bow_x_m,
            "centroid_x_m": centroid_x_m,
            "centroid_y_m": centroid_y_m,
            "area_m2": area_m2,
            "thickness_m": thickness_m,
        }
    )
    for k, prop in enumerate(arrangement.propellers):
        if abs(prop.offset_y_m) > 0.5 * hull.beam_m:
            raise InputError(
                f"transport.arrangement.propellers[{k}].offset_y_m",
                f"{prop.offset_y_m:g} m lies outside the beam",
                value=prop.offset_y_m,
                allowed=f"[{-0.5 * hull.beam_m:g}, {0.5 * hull.beam_m:g}] m",
            )
    if params.lateral_spread_m > 0.0 and rng is None:
        raise InputError(
            "transport.lateral_spread_m",
            f"{params.lateral_spread_m:g} m > 0 needs a numpy.random.Generator (rng=)",
            value=params.lateral_spread_m,
        )
    y = cols["centroid_y_m"]
    if params.lateral_spread_m > 0.0:
        y = y + rng.normal(0.0, params.lateral_spread_m, size=y.size)
    region = cusp_regions(
        cols["bow_x_m"], cols["centroid_x_m"], hull.bow_length_m, params.shoulder_region_start
    )
    path = np.full(y.size, PATH_MISSED, dtype=np.int8)
    if not params.shoulder_cusps_submerge:
        path[region == "shoulder"] = PATH_SHOULDER
    path[(path == PATH_MISSED) & (np.abs(cols["centroid_y_m"]) > hull.flat_half_width_m)] = PATH_BILGE
    index, radius, angle, section = _contact(y, cols, v, hull, arrangement, params, path == PATH_MISSED)
    path[index >= 0] = PATH_PROPELLER
    x_aft = cols["centroid_x_m"] - cols["bow_x_m"]
    travel_s = (hull.propeller_plane_aft_of_stem_m + x_aft) / (params.slip_factor * v)
    arrival = np.where(index >= 0, cols["bow_x_m"] / v + travel_s, np.nan)
    return CuspTransport(index, arrival, radius, angle, region, path, len(arrangement.propellers), section)


def _contact(y, cols, v, hull, arrangement, params, candidate):
    """Steps 4–6: the nearest disc each candidate's cross-section meets, with the entry point and the
    cross-section relative to that disc's shaft centre (y_lo, y_hi, z_lo, z_hi; NaN without a disc)."""
    h = cols["thickness_m"]
    half_width = 0.5 * np.sqrt(cols["area_m2"])
    rise_m = (
        terminal_rise_speed_m_s(h, params.drag_coefficient) * hull.run_length_m / (params.slip_factor * v)
    )
    n = y.size
    best = np.full(n, np.inf)
    index = np.full(n, NO_PROPELLER, dtype=np.int64)
    radius = np.full(n, np.nan)
    angle = np.full(n, np.nan)
    section = tuple(np.full(n, np.nan) for _ in range(4))
    for k, prop in enumerate(arrangement.propellers):
        r_disc = prop.radius_m
        z_hull = prop.shaft_depth_m - r_disc - arrangement.tip_clearance_m
        z_top = np.maximum(z_hull, hull.draught_m - rise_m)
        py, pz = _nearest_point(
            y - half_width, y + half_width, z_top, z_top + h, prop.offset_y_m, prop.shaft_depth_m
        )
        dy, dz_up = py - prop.offset_y_m, prop.shaft_depth_m - pz
        dist = np.hypot(dy, dz_up)
        wins = candidate & (dist < r_disc) & (dist < best)  # strict: ties keep the lower index
        best[wins] = dist[wins]
        index[wins] = k
        radius[wins] = dist[wins] / r_disc
        angle[wins] = np.degrees(np.arctan2(dy[wins], dz_up[wins]))
        bounds = (y - half_width - prop.offset_y_m, y + half_width - prop.offset_y_m, z_top, z_top + h)
        centres = (0.0, 0.0, prop.shaft_depth_m, prop.shaft_depth_m)
        for out, value, centre in zip(section, bounds, centres, strict=True):
            out[wins] = value[wins] - centre
    return index, radius, angle, section


def transport_cusp_table(columns: Mapping[str, Any], **kw: Any) -> CuspTransport:
    """`transport_cusps` on the columns of a ``cusps.parquet`` table (``bow_x_m``, ``centroid_x_m``,
    ``centroid_y_m``, ``area_m2``, ``thickness_m``)."""
    needed = ("bow_x_m", "centroid_x_m", "centroid_y_m", "area_m2", "thickness_m")
    missing = [key for key in needed if key not in columns]
    if missing:
        raise InputError("transport.cusps", f"missing columns {missing}", allowed=", ".join(needed))
    return transport_cusps(*(columns[key] for key in needed), **kw)


def loads_per_hour(n_loads: np.ndarray | float, transit_m: float, speed_m_s: float) -> np.ndarray:
    """Loads per hour in ice for `n_loads` over a transit of `transit_m` at `speed_m_s`."""
    hours = transit_m / speed_m_s / 3600.0
    return np.asarray(n_loads, dtype=float) / hours


@dataclass(frozen=True)
class TransportSettings:
    """The user-settable transport inputs: the hull, the parameters and the hull's clearance above the discs
    (the propellers' count comes from the runs, their radius from the propeller spec: `arrangement`)."""

    hull: HullUnderwater = HullUnderwater()
    params: TransportParameters = TransportParameters()
    tip_clearance_m: float = TIP_CLEARANCE_M
    flow: FlowParameters = FlowParameters()

    def __post_init__(self) -> None:
        PropellerArrangement(tip_clearance_m=self.tip_clearance_m)  # its bounds and the disc check

    def arrangement(self, n_propellers: int, radius_m: float) -> PropellerArrangement:
        """`n_propellers` discs of the propeller spec's radius under this hull, with this clearance: shafts at
        ±SHAFT_SPREAD_M for two (else spread evenly; one on the centreline), each disc's bottom
        DISC_BOTTOM_ABOVE_BASE_M above the base line (shaft depth T − R − 0.25 m: 5.25 m for the defaults,
        T = 7.65 m and R = 2.15 m). A radius that leaves no room for the clearance between the hull and the
        disc's top is refused as `propeller.radius_m`."""
        depth = self.hull.draught_m - radius_m - DISC_BOTTOM_ABOVE_BASE_M
        largest = 0.5 * (self.hull.draught_m - DISC_BOTTOM_ABOVE_BASE_M - self.tip_clearance_m)
        if not 0.0 < radius_m <= largest:
            raise InputError(
                "propeller.radius_m",
                f"{radius_m:g} m: the disc (bottom {DISC_BOTTOM_ABOVE_BASE_M:g} m above the base line) and "
                f"the hull's clearance above it ({self.tip_clearance_m:g} m) must fit in the draught "
                f"({self.hull.draught_m:g} m)",
                value=radius_m,
                allowed=f"(0, {largest:g}] m",
            )
        offsets = np.linspace(SHAFT_SPREAD_M, -SHAFT_SPREAD_M, n_propellers) if n_propellers > 1 else [0.0]
        propellers = tuple(Propeller(float(y), 2.0 * radius_m, depth) for y in offsets)
        return PropellerArrangement(propellers, self.tip_clearance_m)

    def as_dict(self) -> dict[str, Any]:
        """The settings as `TRANSPORT_KEYS` → value."""
        return {key: _get(self, key) for key in TRANSPORT_KEYS}


# the flow transport's keys (`FlowParameters`): each range's ends, and the stem angle
FLOW_KEYS: Final = (
    "flow.drag_coefficient_min",
    "flow.drag_coefficient_max",
    "flow.friction_min",
    "flow.friction_max",
    "flow.stem_angle_deg",
)
_FLOW_RANGE_ENDS: Final = {"min": 0, "max": 1}


# the keys of `transport_settings` (`--transport-parameter KEY=VALUE`); error messages name "transport.KEY".
# lateral_spread_m is left out: it needs a numpy.random.Generator, which a key cannot give
TRANSPORT_KEYS: Final = (
    "slip_factor",
    "drag_coefficient",
    "shoulder_region_start",
    "shoulder_cusps_submerge",
    *(f"hull.{name}" for name in HullUnderwater.__dataclass_fields__),
    "arrangement.tip_clearance_m",
    *FLOW_KEYS,
)


def _get(settings: TransportSettings, key: str) -> Any:
    section, _, name = key.rpartition(".")
    if section == "arrangement":
        return settings.tip_clearance_m
    if section == "flow":
        quantity, _, end = name.rpartition("_")
        if end in _FLOW_RANGE_ENDS:
            return getattr(settings.flow, f"{quantity}_range")[_FLOW_RANGE_ENDS[end]]
        return getattr(settings.flow, name)
    return getattr(settings.hull if section == "hull" else settings.params, name)


def _value(key: str, value: Any) -> float | bool:
    """A setting's value as given (number or bool) or as text ("0.5", "true")."""
    if key == "shoulder_cusps_submerge":
        text = str(value).strip().lower()
        if isinstance(value, bool) or text in ("true", "false"):
            return value if isinstance(value, bool) else text == "true"
        raise InputError(
            f"transport.{key}", f"{value!r} is not true or false", value=value, allowed="true, false"
        )
    try:
        if isinstance(value, bool):
            raise ValueError
        return float(value)
    except (TypeError, ValueError):
        raise InputError(f"transport.{key}", f"{value!r} is not a number", value=value) from None


def transport_settings(values: Mapping[str, Any] | None = None) -> TransportSettings:
    """`TransportSettings` from `TRANSPORT_KEYS` → value (numbers, bools or their text); keys not given keep
    their defaults. Unknown keys and values out of range raise InputError naming "transport.KEY", the value
    and the allowed range."""
    values = dict(values or {})
    unknown = [key for key in values if key not in TRANSPORT_KEYS]
    if unknown:
        why = " (needs a random generator; not settable)" if "lateral_spread_m" in unknown else ""
        raise InputError(
            f"transport.{unknown[0]}",
            f"unknown key{why}",
            value=unknown[0],
            allowed=", ".join(TRANSPORT_KEYS),
        )
    parsed = {key: _value(key, value) for key, value in values.items()}
    hull = {k.partition(".")[2]: v for k, v in parsed.items() if k.startswith("hull.")}
    params = {k: v for k, v in parsed.items() if "." not in k}
    clearance = parsed.get("arrangement.tip_clearance_m", PropellerArrangement().tip_clearance_m)
    return TransportSettings(
        HullUnderwater(**hull), TransportParameters(**params), float(clearance), _flow_parameters(parsed)
    )


def _flow_parameters(parsed: Mapping[str, Any]) -> FlowParameters:
    """`FlowParameters` from the parsed "flow.*" keys; a range's end not given keeps its default."""
    default, values = FlowParameters(), {}
    for quantity in ("drag_coefficient", "friction"):
        ends = list(getattr(default, f"{quantity}_range"))
        for end, k in _FLOW_RANGE_ENDS.items():
            ends[k] = parsed.get(f"flow.{quantity}_{end}", ends[k])
        values[f"{quantity}_range"] = (float(ends[0]), float(ends[1]))
    if "flow.stem_angle_deg" in parsed:
        values["stem_angle_deg"] = float(parsed["flow.stem_angle_deg"])
    return FlowParameters(**values)
