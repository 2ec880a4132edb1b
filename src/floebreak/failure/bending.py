"""Failure by bending (thesis §4.1, Eq. 11, Alg. 4; physics-notes §1, §2.5; errata 11, 13).

At the contact zone: wedge origin O (zone centre on the upper waterline), intact-ice fan Θ, loading radius
r = √(2 A_h/Θ); Nevel's narrow-wedge capacity P_f(h, r, Θ) = σ_f Θ h² / (6 S(r/ℓ)). The floe fails when
F_v > P_f. The bending line is the arc of breaking points B_k = O + ξ_σ(r/ℓ) ℓ U_k (maximum-stress distance
by default; maximum-moment distance as the thesis' wording), extended along the arc to the floe boundary:
the floe is split into the part within that radius of O and the rest. If the whole floe lies within the
radius, it cannot bend: the mode passes it on to the dispatch policy's next mode (cracking in the default
policy; rotation — flipped whole — in the thesis profile's, docs/model.md §11).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, ClassVar, Literal

import numpy as np
import shapely

from floebreak import constants as c
from floebreak.errors import Bounds, check_bounds, require_range
from floebreak.failure.base import (
    FailureContext,
    FailureInput,
    Fate,
    NewPiece,
    Outcome,
    failed,
    intact,
    log_margin,
    pass_on,
    split_parts,
)
from floebreak.failure.registry import register_mode
from floebreak.ice.material import characteristic_length_scalar_m
from floebreak.mechanics import nevel
from floebreak.mechanics.capacity_lookup import thesis_a4_capacity_n
from floebreak.mechanics.wedge_fan import LoadingRadiusModel, WedgeFan, disk_polygon, wedge_fan

CapacityModel = Literal["nevel_narrow", "kashtelyan", "thesis_per_wedge"]
CapacityLookup = Literal["direct", "thesis_a4"]
BreakingLengthMode = Literal["max_stress", "max_moment"]
WEDGE_ANGLE_MIN_DEG = 1.0  # lower bound of φ (the setting's docstring)


@dataclass(frozen=True)
class BendingSettings:
    """Parameters of the bending model (SI; angles in degrees); scenario table ``[failure.bending]``."""

    wedge_angle_deg: Annotated[float, Bounds(WEDGE_ANGLE_MIN_DEG, 60.0, unit="deg")] = c.WEDGE_ANGLE_DEG
    """bending wedge angle φ [deg] (thesis §4.1.2: 5°), in [1, 60]: Nevel's narrow-wedge solution holds
    below φ_crit = 60° (Erceg et al., thesis §4.1.2). φ is a resolution, not a crack count (radially cracked
    ice forms a few wedges, notes §1.5; Θ is the fan's opening, not φ): it sets how many rays probe the fan
    and how many vertices the bending line has, 360°/φ each. At 1° the bending line's chords deviate from
    its arc by R(1 − cos 0.5°) < 4·10⁻⁵ R, 0.04 mm at R = 1 m, far below an ice edge's roughness, so a finer
    φ resolves nothing; below it the cost grows as 1/φ without bound (0.01°: 36 000 rays, 48 s and 540 MB
    for one 10 m floe)"""
    flexural_strength_pa: float = c.FLEXURAL_STRENGTH_PA
    """σ_f [Pa] (from [ice])"""
    capacity_model: CapacityModel = "nevel_narrow"
    """P_f: Nevel's narrow wedge over the fan Θ, Kashtelyan, or the thesis' per-wedge F_v (erratum 13)"""
    capacity_lookup: CapacityLookup = "direct"
    """P_f at the contact's (h, r, Θ) ("direct"), or as the thesis' App. A.4 code looks it up ("thesis_a4":
    the mean over its table's bracketing grid points, with its thickness bracket; erratum 12, docs/model.md
    §11)"""
    kashtelyan_coefficient: Annotated[float, Bounds(0.0, 10.0, low_inclusive=False)] = 3.0
    """coefficient C_f of the Kashtelyan capacity [-], in (0, 10]: C_f ≈ 3 (physics-notes §1.5, confidence
    low–medium); the capacity is linear in C_f, and 10 is over three times that"""
    breaking_length_mode: BreakingLengthMode = "max_stress"
    """bending line distance: maximum stress (notes §1) or maximum moment (thesis wording, erratum 11)"""
    loading_radius_model: LoadingRadiusModel = "sector_area"
    """loading radius r of the wedge fan (notes §1.7)"""
    youngs_modulus_pa: float = c.YOUNGS_MODULUS_PA
    """E [Pa] (from [ice])"""
    poisson_ratio: float = c.POISSON_RATIO
    """ν [-] (from [ice])"""
    foundation_modulus_n_m3: Annotated[float, Bounds(1.0e3, 1.0e5, unit="N/m³")] = c.FOUNDATION_MODULUS_N_M3
    """k = ρ_w g of the elastic foundation [N/m³] (physics-notes §0: 10 055 N/m³), in [1e3, 1e5]: a tenth to
    ten times that of sea water (fresh water to brine lie within ±30 %)"""

    def __post_init__(self) -> None:
        check_bounds(self, "failure.bending")
        require_range("ice.flexural_strength_pa", self.flexural_strength_pa, low=0.0, unit="Pa")


@dataclass(frozen=True)
class BendingCheck:
    """The bending criterion at one contact: fan, capacity, breaking radius and the verdict."""

    fan: WedgeFan
    characteristic_length_m: float
    capacity_n: float
    vertical_force_n: float
    breaking_radius_m: float  # distance of the bending line from O

    @property
    def fails(self) -> bool:
        return self.fan.opening_rad > 0.0 and self.vertical_force_n > self.capacity_n

    @property
    def margin(self) -> float | None:
        """ln(F_v / P_f) (`Outcome.margin`)."""
        return log_margin(self.vertical_force_n, self.capacity_n)


def bending_check(inp: FailureInput, ctx: FailureContext, settings: BendingSettings) -> BendingCheck:
    """Evaluate Eq. 11 (F_v > P) at the failure zone of `inp` (shared by bending and local cracking)."""
    zone = inp.zone
    wedge = np.radians(settings.wedge_angle_deg)
    geometry = ctx.bow_geometry
    fan = wedge_fan(
        inp.polygon,
        geometry.hull_rings if geometry.hull_rings is not None else geometry.hull_upper,
        zone.centre_xy_m,
        zone.centre_normal,
        zone.a_h_total_m2,
        wedge,
        settings.loading_radius_model,
        # the crushed-zone polygon only for the one model that reads it (building it costs a GEOS overlay)
        zone.overlap_upper if settings.loading_radius_model == "max_distance" else None,
    )
    h = inp.thickness_m
    ell = characteristic_length_scalar_m(
        h, "eq1", settings.youngs_modulus_pa, settings.poisson_ratio, settings.foundation_modulus_n_m3
    )
    if fan.opening_rad > 0.0:
        capacity, radius = _capacity_and_distance(h, fan.loading_radius_m, fan.opening_rad, settings)
        if settings.capacity_lookup == "thesis_a4":  # the breaking radius stays that of the actual h
            capacity = thesis_a4_capacity_n(
                h,
                fan.loading_radius_m,
                fan.opening_rad,
                lambda h, r, opening_rad: _capacity_and_distance(h, r, opening_rad, settings)[0],
            )
    else:
        capacity, radius = float("inf"), 0.0
    return BendingCheck(fan, ell, capacity, zone.vertical_force_n, radius)


def _capacity_and_distance(
    h_m: float, r_m: float, opening_rad: float, settings: BendingSettings
) -> tuple[float, float]:
    """(P_f [N], breaking distance [m]) of the settings' models at (h, r, Θ) (Eq. 1.4, notes §1.6); also a
    grid value of App. A.4's table (Erceg's tables are not published, physics-notes §1.7)."""
    return nevel.capacity_and_breaking_distance(
        h_m,
        r_m,
        opening_rad,
        model=settings.capacity_model,
        mode=settings.breaking_length_mode,
        flexural_strength_pa=settings.flexural_strength_pa,
        kashtelyan_coefficient=settings.kashtelyan_coefficient,
        wedge_angle_rad=np.radians(settings.wedge_angle_deg),
        youngs_modulus_pa=settings.youngs_modulus_pa,
        poisson_ratio=settings.poisson_ratio,
        foundation_modulus=settings.foundation_modulus_n_m3,
    )


def split_by_radius(polygon, check: BendingCheck, thickness_m: float = 0.0) -> tuple[list, list]:
    """(parts within the bending line, parts beyond it): F ∩ disk(O, R) and F − disk(O, R)."""
    fan = check.fan
    start = fan.centre_angle_rad - fan.opening_rad / 2.0 + fan.wedge_angle_rad / 2.0  # a vertex at B_0
    vertices = round(2.0 * np.pi / fan.wedge_angle_rad)
    disk = disk_polygon(fan.origin_xy_m, check.breaking_radius_m, start, vertices)
    near, far = split_parts(
        shapely.intersection(polygon, disk), shapely.difference(polygon, disk), thickness_m=thickness_m
    )
    return near, far


def bending_gate(mode: str, check: BendingCheck) -> Outcome | None:
    """Intact when there is no intact-ice fan or F_v ≤ P_f (shared by bending and local cracking)."""
    return None if check.fails else intact(mode, check.margin)


@dataclass(frozen=True)
class Bending:
    name: ClassVar[str] = "bending"
    settings: BendingSettings = BendingSettings()

    def evaluate(self, inp: FailureInput, ctx: FailureContext) -> Outcome:
        check = bending_check(inp, ctx, self.settings)
        if (held := bending_gate(self.name, check)) is not None:
            return held
        near, far = split_by_radius(inp.polygon, check, inp.thickness_m)
        if not near:  # the bending line misses the floe
            return intact(self.name, check.margin)
        if not far:
            # no bending line crosses the floe (it lies within the breaking radius): it cannot fail in
            # bending here, and the policy's next mode (cracking) is tried
            return pass_on(self.name, check.margin)
        pieces = (NewPiece(p, Fate.FLOE, inp.crack_count) for p in [*near, *far])
        return failed(self.name, pieces, check.margin)


# thesis-literal switches (physics-notes §5)
register_mode(
    Bending,
    settings=BendingSettings,
    material=("flexural_strength_pa", "youngs_modulus_pa", "poisson_ratio"),
    thesis={
        # not the literal "capacity_model": "thesis_per_wedge" (erratum 13; §5.1's forces rule it out) nor
        # "breaking_length_mode": "max_moment" (erratum 11; floes bend in §5.2-5.3): docs/model.md §11
        "loading_radius_model": "sector_area_clipped",  # notes §1.7: r clipped to the Erceg table
        "capacity_lookup": "thesis_a4",  # App. A.4's table lookup (erratum 12): Table 7 was computed with it
    },
)
