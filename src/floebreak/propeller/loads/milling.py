"""Blade milling model: ice torque and axial force per blade impact, for any open propeller, without FEM.

A blade-element form of the propeller–ice milling models of Kotras et al. (1987), Veitch (1995) and Wang
(2007): each blade passage cuts a layer of the block (the advance per blade passage), every radial strip of
the blade that lies inside the block crushes the part of that layer in its path, and the crushing pressure
follows a process pressure–area relation over the blade's whole contact. Equations, parameter values with
their sources and the validity range: docs/propeller.md, section "Blade milling model".

Geometry (docs/propeller.md, "Blade milling model"): the block lies flat against the hull above the disc and
the blade tip enters it first, so the block's thickness is its radial extent in the disc (from the tip
inwards); its length lies along the shaft axis (milled through at the cut depth per passage); its width
sets the angle the blade turns through inside it. Pure functions on numpy arrays and frozen dataclasses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from floebreak.constants import (
    CRUSHING_STRENGTH_PA,
    FRICTION_COEFFICIENT,
    ICE_DENSITY_KG_M3,
    SEAWATER_DENSITY_KG_M3,
)
from floebreak.errors import InputError, require_range
from floebreak.propeller.cusps import box_dimensions, cusp_geometry
from floebreak.propeller.spec import MAX_PROPELLER_RPM, PropellerSpec
from floebreak.propeller.spectra import pitch_label

# Wageningen B-series chord: c(r) = K(r/R) · D · EAR / Z (Oosterveld & van Oossanen 1975; Kuiper 1992)
B_SERIES_RADIUS_RATIO = (0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
B_SERIES_CHORD_FACTOR = (1.662, 1.882, 2.050, 2.152, 2.187, 2.144, 1.970, 1.582, 0.0)
DEFAULT_STRIPS = 64
CHORD_DISTRIBUTIONS = ("b_series", "constant")
MAX_ADVANCE_SPEED_M_S = 20.0  # far above any ship's speed in ice; bounds the input check only
# 2-D added-mass coefficient C_A (added mass C_A ρ_w π b² per length) of a rectangle 2a along the motion by
# 2b across it, against a/b: DNV-RP-C205 (2010), Appendix A, Table A-1 (values as published, not checked
# against the text here)
HELD_IMPACTS = 1 << 40  # impacts of a block that nothing throws (no advance of the block along the path)
RECTANGLE_ASPECT = (0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0)
RECTANGLE_ADDED_MASS = (2.23, 1.98, 1.70, 1.51, 1.36, 1.21, 1.14)


def b_series_chord_factor(radius_ratio) -> np.ndarray:
    """K(r/R) of the Wageningen B-series chord c = K D EAR/Z, linear between the tabulated radii."""
    return np.interp(np.asarray(radius_ratio, dtype=float), B_SERIES_RADIUS_RATIO, B_SERIES_CHORD_FACTOR)


@dataclass(frozen=True)
class BladeGeometry:
    """An open propeller for the milling model.

    max_pitch_ratio: P_0.7/D at 100 % pitch; the operating pitch P = pitch_percent/100 · max_pitch_ratio · D
    is taken constant over the radius (the pitch distribution is seldom published). chord_07_m: the chord at
    0.7R; None takes the Wageningen B-series chord 2.144 D EAR/Z, and the chord at other radii follows the
    B-series shape scaled through it ("b_series", chord 0 at the tip), or is chord_07 at every radius
    ("constant": the wide tips of many ice-class blades). The section thickness in the ice is t_0.7 at
    every radius.
    """

    diameter_m: float
    blades: int
    hub_ratio: float
    max_pitch_ratio: float
    expanded_area_ratio: float
    thickness_07_m: float
    pitch_percent: float = 100.0
    chord_07_m: float | None = None
    chord_distribution: str = "b_series"

    def __post_init__(self) -> None:
        require_range("blade.diameter_m", self.diameter_m, low=0.0, unit="m")
        if isinstance(self.blades, bool) or int(self.blades) != self.blades or self.blades < 2:
            raise InputError("blade.blades", f"{self.blades!r} is not an integer >= 2", value=self.blades)
        require_range(
            "blade.hub_ratio", self.hub_ratio, low=0.0, high=1.0, low_inclusive=True, high_inclusive=False
        )
        require_range("blade.max_pitch_ratio", self.max_pitch_ratio, low=0.0, high=5.0)
        require_range("blade.expanded_area_ratio", self.expanded_area_ratio, low=0.0, high=1.5)
        require_range(
            "blade.thickness_07_m", self.thickness_07_m, low=0.0, high=self.diameter_m / 2, unit="m"
        )
        require_range("blade.pitch_percent", self.pitch_percent, low=0.0, high=100.0, low_inclusive=True)
        if self.chord_07_m is not None:
            require_range("blade.chord_07_m", self.chord_07_m, low=0.0, high=self.diameter_m, unit="m")
        if self.chord_distribution not in CHORD_DISTRIBUTIONS:
            raise InputError(
                "blade.chord_distribution",
                f"unknown value {self.chord_distribution!r}",
                value=self.chord_distribution,
                allowed=", ".join(CHORD_DISTRIBUTIONS),
            )

    @classmethod
    def from_spec(cls, spec: PropellerSpec, chord_07_m: float | None = None) -> BladeGeometry:
        """The geometry of a PropellerSpec (its pitch percent included)."""
        return cls(
            diameter_m=spec.diameter_m,
            blades=spec.blades,
            hub_ratio=spec.hub_ratio,
            max_pitch_ratio=spec.max_pitch_m / spec.diameter_m,
            expanded_area_ratio=spec.expanded_area_ratio,
            thickness_07_m=spec.blade_thickness_07_m,
            pitch_percent=spec.pitch_percent,
            chord_07_m=chord_07_m,
        )

    @property
    def radius_m(self) -> float:
        return 0.5 * self.diameter_m

    @property
    def hub_radius_m(self) -> float:
        return self.hub_ratio * self.radius_m

    @property
    def pitch_m(self) -> float:
        return self.pitch_percent / 100.0 * self.max_pitch_ratio * self.diameter_m

    @property
    def chord_at_07_m(self) -> float:
        if self.chord_07_m is not None:
            return float(self.chord_07_m)
        return float(b_series_chord_factor(0.7)) * self.diameter_m * self.expanded_area_ratio / self.blades

    def chord_m(self, radius_m) -> np.ndarray:
        """Chord at radius r: the B-series shape through chord_at_07_m (0 at the tip), or constant."""
        r = np.asarray(radius_m, dtype=float)
        if self.chord_distribution == "constant":
            return np.full(r.shape, self.chord_at_07_m)
        shape = b_series_chord_factor(r / self.radius_m)
        return self.chord_at_07_m * shape / float(b_series_chord_factor(0.7))


@dataclass(frozen=True)
class IceStrength:
    """Crushing pressure p = p_ref (A / A_ref)^ex over the blade's contact area A, ice–steel friction, and
    the extent of the flank contact along the chord.

    Defaults (docs/propeller.md, "Blade milling model"): p_ref = 1.28 MPa at A_ref = 1 m² (the project's
    crushing strength, thesis Alg. 3); ex = −0.1, the process pressure–area exponent of the IACS Polar
    Class ice load model (Daley 2000); μ = 0.15 (thesis Alg. 3). flank_contact_chord_fraction = 0.2: the
    flank (face or back) touches the ice at most from the leading edge to 0.2 × the local chord — the
    loaded area of the open-propeller load cases 1 (back, F_b) and 3 (face, F_f) of the ice-class rules
    (IACS UR I3 / Finnish-Swedish rules, Annex "Load cases for propeller", Table 2.1; 0.5 for a ducted
    propeller's face), in the direction of Veitch (1994, IAHR Ice Symposium: pressure-side contact limited
    by cracks from near the leading edge). In [0, 1]: 1 gives the full geometric overlap, 0 the nose
    (leading edge) alone (docs/propeller.md §10, choice 4).
    """

    crushing_pressure_pa: float = CRUSHING_STRENGTH_PA
    reference_area_m2: float = 1.0
    area_exponent: float = -0.1
    friction: float = FRICTION_COEFFICIENT
    flank_contact_chord_fraction: float = 0.2

    def __post_init__(self) -> None:
        require_range("ice.crushing_pressure_pa", self.crushing_pressure_pa, low=0.0, high=1e8, unit="Pa")
        require_range("ice.reference_area_m2", self.reference_area_m2, low=0.0, high=1e3, unit="m²")
        require_range("ice.area_exponent", self.area_exponent, low=-1.0, high=0.0, low_inclusive=True)
        require_range(
            "ice.friction", self.friction, low=0.0, high=1.0, low_inclusive=True, high_inclusive=False
        )
        require_range(
            "ice.flank_contact_chord_fraction",
            self.flank_contact_chord_fraction,
            low=0.0,
            high=1.0,
            low_inclusive=True,
        )

    def pressure_pa(self, area_m2) -> np.ndarray:
        """p(A); 0 where A = 0 (no contact)."""
        area = np.asarray(area_m2, dtype=float)
        safe = np.where(area > 0.0, area, self.reference_area_m2)
        return np.where(
            area > 0.0, self.crushing_pressure_pa * (safe / self.reference_area_m2) ** self.area_exponent, 0.0
        )


@dataclass(frozen=True)
class BlockMotion:
    """A free-floating block, thrown along the blade's path by the impacts (docs/propeller.md, "Blade
    milling model", *Block thrown out of the disc*). `added_mass=False` leaves the water's added mass out
    (the lightest block, fewest impacts)."""

    ice_density_kg_m3: float = ICE_DENSITY_KG_M3
    water_density_kg_m3: float = SEAWATER_DENSITY_KG_M3
    added_mass: bool = True

    def __post_init__(self) -> None:
        require_range(
            "block_motion.ice_density_kg_m3", self.ice_density_kg_m3, low=0.0, high=2e3, unit="kg/m³"
        )
        require_range(
            "block_motion.water_density_kg_m3", self.water_density_kg_m3, low=0.0, high=2e3, unit="kg/m³"
        )

    def effective_mass_kg(self, thickness_m, length_m, width_m) -> np.ndarray:
        """ρ_i h L W plus, sliding sideways (along its width, thickness across the motion), the 2-D added
        mass C_A(a/b) ρ_w π (h/2)² L with a/b = W/h (DNV-RP-C205 Table A-1, clipped to its range)."""
        h, length, w = (np.asarray(a, dtype=float) for a in (thickness_m, length_m, width_m))
        mass = self.ice_density_kg_m3 * h * length * w
        if not self.added_mass:
            return mass
        with np.errstate(divide="ignore", invalid="ignore"):
            aspect = np.clip(np.where(h > 0.0, w / np.where(h > 0.0, h, 1.0), 10.0), 0.1, 10.0)
        c_a = np.interp(np.log(aspect), np.log(RECTANGLE_ASPECT), RECTANGLE_ADDED_MASS)
        return mass + c_a * self.water_density_kg_m3 * math.pi * (0.5 * h) ** 2 * length


def impacts_before_thrown(
    torque_n_m, contact_radius_m, impact_angle_rad, exit_distance_m, mass_kg, rpm, blades: int
) -> np.ndarray:
    """Blade impacts a free block takes before it is thrown out of the disc (≥ 1; a large int when held).

    Each impact pushes the block along the blade's path with the impulse J = (2/π) (Q/r_c) t_c of a
    half-sine contact force of peak Q/r_c over the contact time t_c = (impact angle)/ω; the block gains
    Δv = J/m per impact and after k impacts has moved x_k = Δv Δt k(k+1)/2 (Δt = 1/(Z n) between
    impacts). It leaves the swept annulus once x_k reaches the exit distance √(R² − r_in²) (a straight
    path from the block's inner face to the disc's rim), so the impacts are the least k with x_k ≥ that.
    """
    q = np.abs(np.asarray(torque_n_m, dtype=float))
    omega = 2.0 * math.pi * np.asarray(rpm, dtype=float) / 60.0
    with np.errstate(divide="ignore", invalid="ignore"):
        contact_s = np.where(omega > 0.0, impact_angle_rad / np.where(omega > 0.0, omega, 1.0), 0.0)
        dv = 2.0 / math.pi * q / contact_radius_m * contact_s / mass_kg
        passage_s = np.where(omega > 0.0, 2.0 * math.pi / (blades * np.where(omega > 0.0, omega, 1.0)), 0.0)
        ratio = exit_distance_m / (dv * passage_s)
        k = np.ceil((np.sqrt(1.0 + 8.0 * ratio) - 1.0) / 2.0 - 1e-12)
    big = float(HELD_IMPACTS)
    return np.where(np.isfinite(k), np.clip(k, 1.0, big), big).astype(np.int64)


@dataclass(frozen=True)
class IceBlock:
    """Ice blocks (arrays of equal shape): thickness, length along the shaft axis, width across it, and
    optionally the engaged interval [inner_radius_m, outer_radius_m] of the blade in the block
    (`propeller.engagement`; docs/propeller.md §10 choice 5). NaN (the default): the block lies at the tip
    and its thickness is its radial extent in the disc (tip placement)."""

    thickness_m: np.ndarray
    length_m: np.ndarray
    width_m: np.ndarray
    inner_radius_m: np.ndarray | float = math.nan
    outer_radius_m: np.ndarray | float = math.nan

    def __post_init__(self) -> None:
        names = ("thickness_m", "length_m", "width_m", "inner_radius_m", "outer_radius_m")
        arrays = np.broadcast_arrays(*(np.asarray(getattr(self, n), dtype=float) for n in names))
        for name, values in zip(names[:3], arrays[:3], strict=True):
            bad = np.flatnonzero(~np.isfinite(values) | (values < 0.0))
            if bad.size:
                raise InputError(
                    f"block.{name}",
                    f"row {bad[0]}: {values.reshape(-1)[bad[0]]!r}",
                    allowed="finite values >= 0",
                )
        _check_interval(arrays[3], arrays[4])
        for name, values in zip(names, arrays, strict=True):
            object.__setattr__(self, name, np.atleast_1d(values).astype(float))

    @classmethod
    def from_box(cls, side_a_m, side_b_m, thickness_m, inner_radius_m=math.nan, outer_radius_m=math.nan):
        """A cusp bounding box (cusps.box_dimensions): longer side along the axis, shorter across; the
        engaged interval as given (NaN: tip placement)."""
        longer, shorter, _ = box_dimensions(side_a_m, side_b_m, thickness_m)
        return cls(np.asarray(thickness_m, dtype=float), longer, shorter, inner_radius_m, outer_radius_m)


def _check_interval(inner, outer) -> None:
    """Engaged intervals: both NaN (tip placement) or 0 ≤ inner ≤ outer, finite."""
    inner, outer = np.ravel(inner), np.ravel(outer)
    given = ~np.isnan(inner) | ~np.isnan(outer)
    for name, values in (("inner_radius_m", inner), ("outer_radius_m", outer)):
        bad = np.flatnonzero(given & (~np.isfinite(values) | (values < 0.0)))
        if bad.size:
            raise InputError(
                f"block.{name}",
                f"row {bad[0]}: {values[bad[0]]!r}",
                allowed="finite values >= 0 (NaN in both radii: tip placement)",
            )
    bad = np.flatnonzero(given & (outer < inner))
    if bad.size:
        raise InputError(
            "block.outer_radius_m",
            f"row {bad[0]}: {outer[bad[0]]!r} below inner_radius_m {inner[bad[0]]!r}",
            allowed="outer_radius_m >= inner_radius_m",
        )


@dataclass(frozen=True)
class ImpactLoads:
    """Loads of one blade impact (fully engaged) and the milling of each block; arrays, one value a block.

    torque_n_m: ice torque about the shaft, positive against the rotation. force_n: |axial blade force|;
    axial_force_aft_n: the same signed, positive aft (a backward force, contact on the blade back).
    cut_depth_m: advance per blade passage V_a/(Z n). n_impacts: blade impacts on the block, the lesser of
    n_impacts_milled = ceil(length / cut depth) (to mill it through; 0 without advance or rotation) and
    n_impacts_thrown (`impacts_before_thrown`: a free block is thrown out of the disc; HELD_IMPACTS for a
    held block, `block_motion=None`). impact_angle_deg: shaft angle the blade turns
    inside the block (width over the mean contact radius). removed_fraction: the part of the advancing
    layer the blade's frontal width removes, Σ(w_n + w_f)Δr / Σ s Δr; below 1 the rest is not cut (where
    the section is narrower than the layer, e.g. near a B-series tip or at low pitch): the block is then
    pressed onto the blades rather than milled, beyond this model.
    """

    torque_n_m: np.ndarray
    force_n: np.ndarray
    axial_force_aft_n: np.ndarray
    cut_depth_m: np.ndarray
    n_impacts: np.ndarray
    contact_area_m2: np.ndarray
    pressure_pa: np.ndarray
    radial_extent_m: np.ndarray
    impact_angle_deg: np.ndarray
    milling_time_s: np.ndarray
    removed_fraction: np.ndarray
    n_impacts_milled: np.ndarray
    n_impacts_thrown: np.ndarray


def cut_depth_m(advance_speed_m_s, rpm, blades: int) -> np.ndarray:
    """Axial advance of the ice per blade passage h = V_a / (Z n) [m]; 0 without advance, inf at n = 0."""
    v = np.asarray(advance_speed_m_s, dtype=float)
    n = np.asarray(rpm, dtype=float) / 60.0
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(v > 0.0, np.where(n > 0.0, v / (blades * np.where(n > 0.0, n, 1.0)), np.inf), 0.0)


def section_contact(
    radius_m,
    chord_m,
    thickness_m,
    pitch_m,
    rpm,
    advance_speed_m_s,
    blades: int,
    layer_fraction=1.0,
    *,
    flank_chord_fraction,
):
    """Contact widths of a blade section with the layer it mills (per unit radial length).

    Kinematics: β = atan(V_a / (ω r)) (advance angle), φ = atan(P / (2π r)) (pitch angle, thesis Eq. 22),
    α = φ − β. The layer each blade removes, measured across the section's path relative to the ice, is
    s = h cos β = 2π r V_a / (Z U) with U = √(V_a² + (ω r)²). The section's frontal width across its path
    is t|cos α| (the nose) + c|sin α| (the face if α > 0, the back if α < 0); only the part inside the layer
    is swept: nose w_n = min(t|cos α|, s), flank w_f = min(c|sin α|, s − w_n). The flank touches the ice
    along the chord over L_f = min(w_f / |sin α|, f c), f = `flank_chord_fraction` (the rest of the swept
    layer spalls off along cracks from the leading edge; IceStrength.flank_contact_chord_fraction).
    `layer_fraction` (≤ 1) scales s where the block is shorter along the axis than the cut depth (its last,
    partial layer). Returns (w_n, w_f, L_f, α, β, φ, s).
    """
    r = np.asarray(radius_m, dtype=float)
    v = np.asarray(advance_speed_m_s, dtype=float)
    tangential = 2.0 * math.pi * np.asarray(rpm, dtype=float) / 60.0 * r
    speed = np.hypot(v, tangential)
    beta = np.arctan2(v, tangential)
    phi = np.arctan2(pitch_m, 2.0 * math.pi * r)
    alpha = phi - beta
    with np.errstate(divide="ignore", invalid="ignore"):
        layer = np.where(speed > 0.0, 2.0 * math.pi * r * v / (blades * np.where(speed > 0, speed, 1.0)), 0.0)
        layer = layer * layer_fraction
        nose = np.minimum(np.asarray(thickness_m, dtype=float) * np.abs(np.cos(alpha)), layer)
        sin_a = np.abs(np.sin(alpha))
        flank = np.minimum(np.asarray(chord_m, dtype=float) * sin_a, layer - nose)
        swept_length = np.where(sin_a > 0.0, flank / np.where(sin_a > 0.0, sin_a, 1.0), 0.0)
        flank_length = np.minimum(swept_length, flank_chord_fraction * np.asarray(chord_m, dtype=float))
    return nose, flank, flank_length, alpha, beta, phi, layer


def strip_forces(pressure_pa, nose_area_m2, flank_area_m2, alpha, beta, phi, friction: float):
    """(force against the rotation, axial force aft) [N] on blade strips.

    Nose: p A_n against the section's motion relative to the ice, i.e. (aft, against rotation) =
    p A_n (sin β, cos β). Flank: normal force N = p A_f on the face (α > 0: pushes the blade forward and
    against the rotation, −N(cos φ, sin φ)) or on the back (α < 0: +N(cos φ, sin φ)); friction μN along the
    chord in the direction the ice slides, μN (sin φ, cos φ).
    """
    p = np.asarray(pressure_pa, dtype=float)
    nose = p * nose_area_m2
    normal = p * flank_area_m2
    side = np.sign(alpha)
    resisting = nose * np.cos(beta) + normal * (side * np.sin(phi) + friction * np.cos(phi))
    aft = nose * np.sin(beta) + normal * (-side * np.cos(phi) + friction * np.sin(phi))
    return resisting, aft


def _check_operation(rpm, advance_speed_m_s):
    rpm = np.asarray(rpm, dtype=float)
    speed = np.asarray(advance_speed_m_s, dtype=float)
    for key, values, high in (
        ("rpm", rpm, MAX_PROPELLER_RPM),
        ("advance_speed_m_s", speed, MAX_ADVANCE_SPEED_M_S),
    ):
        bad = np.flatnonzero(~np.isfinite(values) | (values < 0.0) | (values > high))
        if bad.size:
            value = float(values.reshape(-1)[bad[0]])
            raise InputError(
                key, f"{value:g} is outside [0, {high:g}]", value=value, allowed=f"[0, {high:g}]"
            )
    return rpm, speed


def _strips_under_block(blade: BladeGeometry, thickness_m, strips: int, inner_m=math.nan, outer_m=math.nan):
    """The radial interval a block covers and per strip of [r_hub, R] its overlap with it and the
    overlap's mid radius (a strip outside the block: overlap 0). Tip placement (NaN interval): [R − e, R]
    with e = min(h, R − r_hub); an engaged interval: [r_in, r_out] clipped to [r_hub, R], e = r_out − r_in.
    Returns (e, inner edge, overlap, mid radius)."""
    radius, hub = blade.radius_m, blade.hub_radius_m
    tip_extent = np.minimum(thickness_m, radius - hub)
    engaged = np.isfinite(inner_m) & np.isfinite(outer_m)
    low = np.where(engaged, np.clip(inner_m, hub, radius), radius - tip_extent)
    high = np.where(engaged, np.clip(outer_m, hub, radius), radius)
    extent = np.where(engaged, high - low, tip_extent)
    edges = np.linspace(hub, radius, strips + 1)
    inner = np.maximum(edges[:-1], low[..., None])
    outer = np.minimum(edges[1:], high[..., None])
    overlap = np.clip(outer - inner, 0.0, None)
    mid = np.where(overlap > 0.0, 0.5 * (inner + outer), edges[1:])
    return extent, low, overlap, mid


@dataclass(frozen=True)
class BlockStrips:
    """What `impact_loads` computes from the blocks alone (`block_strips`): each block's length along the
    axis, the radial extent e it covers and its inner edge, and per blade strip its overlap with the
    block, the overlap's mid radius and the chord there."""

    length_m: np.ndarray
    radial_extent_m: np.ndarray
    overlap_m: np.ndarray
    mid_radius_m: np.ndarray
    chord_m: np.ndarray
    inner_edge_m: np.ndarray | None = None


def block_strips(
    blade: BladeGeometry,
    thickness_m,
    length_m,
    strips: int = DEFAULT_STRIPS,
    inner_radius_m=math.nan,
    outer_radius_m=math.nan,
) -> BlockStrips:
    """The blocks' strips on `blade` (`_strips_under_block`; the engaged interval [inner, outer] where
    given, else tip placement), for `impact_loads` or, computed once per block, for `impact_torque_n_m` at
    many rpm."""
    if isinstance(strips, bool) or int(strips) != strips or not 1 <= strips <= 10_000:
        raise InputError("strips", f"{strips!r} is not an integer in [1, 10000]", value=strips)
    inner, outer = (np.asarray(a, dtype=float) for a in (inner_radius_m, outer_radius_m))
    _check_interval(inner, outer)
    extent, low, overlap, mid = _strips_under_block(blade, thickness_m, int(strips), inner, outer)
    return BlockStrips(np.asarray(length_m, dtype=float), extent, overlap, mid, blade.chord_m(mid), low)


def _strip_loads(strip: BlockStrips, blade: BladeGeometry, rpm, speed, ice: IceStrength):
    """Cut depth, (w_n, w_f, s, A, p, axial force per strip) and torque Q of one impact (`impact_loads`)."""
    cut = cut_depth_m(speed, rpm, blade.blades)
    length, overlap, mid = strip.length_m, strip.overlap_m, strip.mid_radius_m
    with np.errstate(divide="ignore", invalid="ignore"):
        fraction = np.where(cut > length, length / np.where(cut > 0.0, cut, 1.0), 1.0)
    nose, flank, flank_length, alpha, beta, phi, layer = section_contact(
        mid,
        strip.chord_m,
        blade.thickness_07_m,
        blade.pitch_m,
        rpm[..., None],
        speed[..., None],
        blade.blades,
        fraction[..., None],
        flank_chord_fraction=ice.flank_contact_chord_fraction,
    )
    nose_area, flank_area = nose * overlap, flank_length * overlap
    area = np.sum(nose_area + flank_area, axis=-1)
    pressure = ice.pressure_pa(area)
    resisting, aft = strip_forces(pressure[..., None], nose_area, flank_area, alpha, beta, phi, ice.friction)
    torque = np.sum(resisting * mid, axis=-1)
    return cut, (nose, flank, layer, area, pressure, aft), torque


def impact_torque_n_m(
    strip: BlockStrips, blade: BladeGeometry, rpm, advance_speed_m_s, ice: IceStrength | None = None
) -> np.ndarray:
    """`impact_loads(...).torque_n_m` of the blocks of `strip` (`block_strips`, computed once), to the bit:
    the same checks of rpm and speed and the same arithmetic, without the block's other quantities."""
    ice = IceStrength() if ice is None else ice
    rpm, speed = _check_operation(rpm, advance_speed_m_s)
    length, rpm, speed = np.broadcast_arrays(strip.length_m, rpm, speed)
    return _strip_loads(replace(strip, length_m=length), blade, rpm, speed, ice)[2]


def impact_loads(
    block: IceBlock,
    blade: BladeGeometry,
    rpm,
    advance_speed_m_s,
    ice: IceStrength | None = None,
    strips: int = DEFAULT_STRIPS,
    block_motion: BlockMotion | None = BlockMotion(),
) -> ImpactLoads:
    """Ice torque and axial force of one blade impact on each block, and the impacts to mill it through.

    The blade span [r_hub, R] is cut into `strips` radial strips; the block covers its engaged interval
    [r_in, r_out] (`block.inner_radius_m`, `outer_radius_m`; e = r_out − r_in) or, where that is NaN,
    [R − e, R] with e = min(thickness, R − r_hub) (tip placement), each strip counting with its overlap
    and the overlap's mid radius; the contact centre is the interval's midpoint. A zero-length interval
    (the block only touches the blade's annulus) gives no contact: zero loads and no impacts. The
    contact area A = Σ (w_n + L_f) Δr (`section_contact`; L_f the flank's contact length along the chord,
    at most `ice.flank_contact_chord_fraction` × c) sets one pressure p(A) for the blade (process
    pressure–area), and Q = Σ r · (force against rotation), F = Σ axial force (`strip_forces`).
    The layer is at most the block's length along the axis (a block shorter than the cut depth is cut
    once, by its length). `block_motion`: the block is free and thrown out of the disc after
    `impacts_before_thrown` impacts (None: held, every block milled through). rpm and advance_speed_m_s
    broadcast against the blocks, so a drive model can pass its changing rpm.
    """
    ice = IceStrength() if ice is None else ice
    rpm, speed = _check_operation(rpm, advance_speed_m_s)
    thickness, length, width, inner, outer, rpm, speed = np.broadcast_arrays(
        block.thickness_m,
        block.length_m,
        block.width_m,
        block.inner_radius_m,
        block.outer_radius_m,
        rpm,
        speed,
    )
    radius = blade.radius_m
    strip = block_strips(blade, thickness, length, strips, inner, outer)
    extent, overlap, low = strip.radial_extent_m, strip.overlap_m, strip.inner_edge_m
    cut, contact, torque = _strip_loads(strip, blade, rpm, speed, ice)
    nose, flank, layer, area, pressure, aft = contact
    axial = np.sum(aft, axis=-1)
    layer_area = np.sum(layer * overlap, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        removed = np.where(layer_area > 0.0, np.sum((nose + flank) * overlap, axis=-1) / layer_area, 1.0)
    finite = np.isfinite(cut) & (cut > 0.0)
    milled = np.where(finite, np.ceil(length / np.where(finite, cut, 1.0) - 1e-12), 0).astype(np.int64)
    engaged = np.isfinite(inner) & np.isfinite(outer)
    milled = np.where(engaged & (extent <= 0.0), 0, milled)
    centre = np.where(engaged, low + 0.5 * extent, radius - 0.5 * extent)
    angle = np.minimum(width / centre, math.pi)
    thrown = np.full(milled.shape, HELD_IMPACTS, dtype=np.int64)
    if block_motion is not None:
        exit_m = np.sqrt(np.maximum(radius**2 - low**2, 0.0))  # low = R − e under tip placement
        mass = block_motion.effective_mass_kg(thickness, length, width)
        thrown = impacts_before_thrown(torque, centre, angle, exit_m, mass, rpm, blade.blades)
    with np.errstate(divide="ignore", invalid="ignore"):
        milling_time = np.where(speed > 0.0, length / np.where(speed > 0.0, speed, 1.0), np.inf)
    return ImpactLoads(
        torque_n_m=torque,
        force_n=np.abs(axial),
        axial_force_aft_n=axial,
        cut_depth_m=cut,
        n_impacts=np.minimum(milled, thrown),
        contact_area_m2=area,
        pressure_pa=pressure,
        radial_extent_m=extent,
        impact_angle_deg=np.degrees(angle),
        milling_time_s=milling_time,
        removed_fraction=np.where(layer_area > 0.0, removed, 1.0),
        n_impacts_milled=milled,
        n_impacts_thrown=thrown,
    )


MILLING_PITCH_PERCENT = 0.0  # the milling model's pitches: 0 % and the spec's (those of the FEM tables)


def milling_pitches(spec: PropellerSpec) -> tuple[float, ...]:
    return tuple(sorted({MILLING_PITCH_PERCENT, float(spec.pitch_percent)}))


def milling_loads(
    longer_m,
    shorter_m,
    thickness_m,
    spec: PropellerSpec,
    advance_speed_m_s,
    inner_radius_m=math.nan,
    outer_radius_m=math.nan,
) -> dict[str, np.ndarray]:
    """Per pitch (`milling_pitches`): force [N] (|axial blade force| of one impact), torque [N·m] (signed
    as the FEM tables: negative about the shaft axis, thesis §6.1.2), impacts to mill the cusp, and
    `beyond_table` (all False: no table). Block = the cusp's box (`IceBlock.from_box`) on its engaged
    interval (`engaged_intervals`; NaN: tip placement), blade = the spec at that pitch, rpm = the spec's,
    advance speed = the ship speed (docs/propeller.md "Blade milling model")."""
    block = IceBlock.from_box(longer_m, shorter_m, thickness_m, inner_radius_m, outer_radius_m)
    out: dict[str, np.ndarray] = {}
    for pitch in milling_pitches(spec):
        blade = BladeGeometry.from_spec(replace(spec, pitch_percent=pitch))
        loads = impact_loads(block, blade, spec.rpm, advance_speed_m_s)
        label = pitch_label(pitch)
        out[f"force_n_{label}"] = loads.force_n
        out[f"torque_nm_{label}"] = -loads.torque_n_m
        out[f"n_impacts_{label}"] = loads.n_impacts
        out[f"beyond_table_{label}"] = np.zeros(block.thickness_m.size, dtype=bool)
    return out


class MillingLoads:
    """The blade milling model: one blade impact on each cusp's box, on the blade's engaged interval where
    the transport gives it (docs/propeller.md "Blade milling model")."""

    name = "milling"
    label = "blade milling model"
    description = (
        "blade milling model (docs/propeller.md 'Blade milling model'): one blade impact on the "
        "cusp's box at the spec's rpm and the ship speed, on the blade's engaged interval in the cusp where "
        "the transport gives it (load_model.placement)"
    )
    rpm_text = "milling at the propeller's rpm"
    needs_tables = False
    places_on_blade = True

    def pitches(self, propeller: PropellerSpec, tables) -> tuple[float, ...]:
        return milling_pitches(propeller)

    def cusp_loads(
        self, columns, tables, options, propeller, speed_m_s, engaged=None
    ) -> dict[str, np.ndarray]:
        loads = cusp_geometry(columns, options["cusp_speed_m_s"])
        n = loads["run_id"].size
        inner, outer = engaged if engaged is not None else (np.full(n, math.nan), np.full(n, math.nan))
        loads["engaged_inner_radius_m"], loads["engaged_outer_radius_m"] = inner, outer
        box = (loads["bbox_longer_m"], loads["bbox_shorter_m"], loads["thickness_m"])
        loads.update(milling_loads(*box, propeller, speed_m_s, inner, outer))
        return loads


MODEL = MillingLoads()
