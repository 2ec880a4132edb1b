"""Global failure by cracking (thesis §4.2, Alg. 5 and 7; physics-notes §3.3, §4; errata 14–21).

The crack line runs through the zone centre O ("midBow"), orthogonal to the bow panel (along the
outward normal n̂, thesis Eq. 20) and, once started, through the whole floe (thesis §3.1: "cracking
started once will lead to a full crack"). A piece whose ancestry has cracked before gets its crack
rotated by α_nextcrack = 30° (thesis §4.2.3, Fig. 11), to the side that passes closer to the piece's
centroid (the thesis does not say which side; this gives the more even split).

Criteria (`criterion`):
- ``point_load``: F_h > P_t = σ_t h b, the tensile capacity of the section along the crack (thesis §4.2.1,
  Eq. 14), or P the Nevel bending capacity at the contact (thesis §3.2, Alg. 7 `fracture_criterion_simple`;
  `point_load_capacity = "bending_P"`);
- ``line_load``: K_I = 0.878 (κ F_h / h) √(π/a) ≥ K_Ic (Alg. 7 line load, /h added: erratum 17);
- ``tensile_stress`` / ``flexural_stress``: K_I = σ_n^t(L) √(πa) · Tada factor ≥ K_Ic (Alg. 7, Eq. 19),
  load-independent (physics-notes §4.4), size-effect law BZ/BZ1/BZ2 for σ_n^t.
Crack length a: the indentation depth along the crack line (default) or ℓ/5 (the crack-line start offset of
Alg. 5). Floe length b: the floe's extent along the crack direction. Size L: b by default.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Annotated, ClassVar, Literal

import numpy as np
import shapely

from floebreak import constants as c
from floebreak.errors import Bounds, InputError, check_bounds, require_range
from floebreak.failure.base import (
    FailureContext,
    FailureInput,
    Fate,
    NewPiece,
    Outcome,
    failed,
    log_margin,
    pass_on,
    split_parts,
)
from floebreak.failure.bending import BendingSettings, bending_check
from floebreak.failure.registry import register_mode
from floebreak.ice.material import characteristic_length_scalar_m
from floebreak.mechanics import fracture, polygon_kernel

CrackCriterion = Literal["point_load", "line_load", "tensile_stress", "flexural_stress"]
PointLoadCapacity = Literal["bending_P", "tensile_Pt"]
CrackLengthDefinition = Literal["indentation", "ell_over_5"]
LineLoadCrackLength = Literal["strip_critical", "indentation"]
SizeSource = Literal["b", "equiv_diameter", "thickness"]

MAX_RELATIVE_CRACK_LENGTH = 0.95  # a/b cap for the Tada factors (they diverge as a → b)
MIN_CRACK_LENGTH_M = 1e-3  # a → 0 makes K_I singular (line load) or zero (stress); keep it finite
# a/b at which K_I of an edge crack in a strip of width b, loaded by splitting forces at its mouth, is
# smallest (physics-notes §3.3: Tada, min K_I h √b / P = 6.55 at a/b ≈ 0.13): a full crack (thesis §3.1)
# needs K_I ≥ K_Ic there too, so the line-load criterion is evaluated at a ≥ 0.13 b
STRIP_CRITICAL_RELATIVE_CRACK_LENGTH = 0.13


@dataclass(frozen=True)
class CrackingSettings:
    """Parameters of global cracking (SI; angles in degrees); scenario table ``[failure.cracking]``."""

    criterion: CrackCriterion = "tensile_stress"
    """crack criterion (thesis §4.2, Alg. 7; docs/model.md §7)"""
    fracture_toughness_pa_sqrt_m: float = c.FRACTURE_TOUGHNESS_PA_SQRT_M
    """K_Ic [Pa·√m] (from [ice])"""
    size_effect_law: fracture.SizeEffectLaw = "BZ"
    """size-effect law of the fracture toughness (thesis §4.2.1)"""
    bz2_mode: fracture.BZ2Mode = "generalised"
    """BZ2 law: generalised, or the thesis' F = 4.66 without exponent (erratum 15)"""
    size_source: SizeSource = "b"
    """size L of the size-effect law: floe length b along the crack, equivalent diameter, or thickness"""
    tada_labels: fracture.TadaLabels = "correct"
    """Tada factors: correct, or tension/bending swapped as run in the thesis (erratum 16)"""
    crack_length: CrackLengthDefinition = "indentation"
    """crack length a: indentation depth along the crack line, or ℓ/5 (Alg. 5)"""
    point_load_capacity: PointLoadCapacity = "tensile_Pt"
    """capacity of the point-load criterion: the tensile capacity of the floe's section along the crack,
    P_t = σ_t h b (thesis §4.2.1, Eq. 14), or the Nevel bending capacity P (thesis §3.2 and Alg. 7: an
    out-of-plane capacity for an in-plane force; erratum 20, docs/model.md §11)"""
    total_porosity_ppt: Annotated[float, Bounds(0.0, 1000.0, low_inclusive=False, unit="‰")] = (
        c.TOTAL_POROSITY_PPT
    )
    """total porosity ν_t for σ_t of P_t [‰] (thesis §4.2.1: 50 ‰), in (0, 1000]: a volume fraction; σ_t ∝
    ν_t^−0.6455 (physics-notes §4.2) has no finite value at 0"""
    tip_angle_deg: Annotated[float, fracture.TIP_ANGLE_DEG] = c.BOW_TIP_ANGLE_DEG
    """bow tip angle α of the wedge-splitting fraction κ [deg] (thesis Alg. 7: 64.54°), in [10, 170]: the full
    waterline entrance angle of a bow (ice-going bows ≈ 40–90°); κ = 1/(2 tan(α/2)) grows without bound as
    α → 0 (κ = 5.7 at 10°)"""
    wedge_friction: Annotated[float, Bounds(0.0, 2.0)] = 0.0
    """friction μ of the wedge-splitting fraction; κ with μ = 0 is the thesis' 1/(2 tan(α/2)) [-], in [0, 2]:
    the range of ice.friction_coefficient, a friction coefficient well above any measured for ice"""
    line_load_divide_by_thickness: bool = True
    """line load F_h/h in K_I (erratum 17; the thesis omits /h)"""
    line_load_crack_length: LineLoadCrackLength = "strip_critical"
    """crack length of the line load: max(indentation, 0.13 b), where a mouth-loaded edge crack in a strip
    is hardest to drive (physics-notes §3.3), or the indentation depth from 1 mm (thesis; singular at first
    touch)"""
    stress_mode: fracture.StressMode = "sif"
    """stress criteria form: K_I from the load, F_h/(h b) √(πa) F(a/b) (sif), the size-effect strength as the
    stress (strength), or the thesis' load-independent K_I(σ_n^t) (thesis; erratum 19, physics-notes §4.4)"""
    next_crack_angle_deg: Annotated[float, Bounds(0.0, 90.0, unit="deg")] = c.NEXT_CRACK_ANGLE_DEG
    """α_nextcrack [deg]: rotation of a later crack in a cracked floe's piece (thesis §4.2.3: 30°), in
    [0, 90]: beyond 90° the crack would turn back towards the bow"""

    def __post_init__(self) -> None:
        require_range(
            "ice.fracture_toughness_pa_sqrt_m", self.fracture_toughness_pa_sqrt_m, low=0.0, unit="Pa·√m"
        )
        check_bounds(self, "failure.cracking")
        allowed = ("point_load", "line_load", "tensile_stress", "flexural_stress")
        if self.criterion not in allowed:
            raise InputError("failure.crack_criterion", repr(self.criterion), allowed=", ".join(allowed))
        if self.criterion == "line_load":  # a self-locking wedge (μ tan(α/2) ≥ 1): refused here, not mid-run
            fracture.wedge_splitting_fraction(self.tip_angle_deg, self.wedge_friction)


def crack_direction(inp: FailureInput, next_crack_angle_rad: float) -> np.ndarray:
    """Unit direction of the crack: the bow normal, rotated by ±α_nextcrack after an earlier crack, to the
    side whose line passes closer to the piece's centroid. A tie (the two distances within
    `TIE_DISTANCE_M`: the centroid on the normal, as for a symmetric piece on the stem) is a genuine one —
    no single crack keeps the symmetry — and goes to +α_nextcrack (counter-clockwise: to port for a crack
    pointing ahead), by this rule and not by the rounding of the two distances."""
    normal = np.asarray(inp.zone.centre_normal, dtype=float)
    if inp.crack_count == 0 or next_crack_angle_rad == 0.0:
        return normal
    centroid = np.array(shapely.get_coordinates(shapely.centroid(inp.polygon))[0])
    to_centroid = centroid - inp.zone.centre_xy_m
    rotated = {}
    for sign in (1.0, -1.0):
        c, s = np.cos(sign * next_crack_angle_rad), np.sin(sign * next_crack_angle_rad)
        direction = np.array([c * normal[0] - s * normal[1], s * normal[0] + c * normal[1]])
        rotated[sign] = (abs(direction[0] * to_centroid[1] - direction[1] * to_centroid[0]), direction)
    (ccw_offset, ccw), (cw_offset, cw) = rotated[1.0], rotated[-1.0]
    return cw if cw_offset < ccw_offset - TIE_DISTANCE_M else ccw


TIE_DISTANCE_M = 1e-9  # two crack lines this close [m] to the centroid are equally close (rounding)


def split_by_line(
    polygon, point_xy_m: np.ndarray, direction: np.ndarray, thickness_m: float = 0.0
) -> tuple[list, list]:
    """Split `polygon` by the infinite line through `point_xy_m` along `direction` (two half-planes).

    Half-plane intersections conserve area up to float rounding, whatever the polygon's shape.
    """
    x0, y0, x1, y1 = shapely.bounds(polygon)
    reach = 4.0 * (np.hypot(x1 - x0, y1 - y0) + np.hypot(*(point_xy_m - [x0, y0])))
    d = direction / np.hypot(*direction)
    left_normal = np.array([-d[1], d[0]])
    a, b = point_xy_m - reach * d, point_xy_m + reach * d
    halves = shapely.polygons(
        [
            [a, b, b + reach * left_normal, a + reach * left_normal],
            [a, a - reach * left_normal, b - reach * left_normal, b],
        ]
    )
    left, right = shapely.intersection(polygon, halves)
    return split_parts(left, right, thickness_m=thickness_m)


def indentation_depth_m(polygon, origin_xy_m: np.ndarray, direction: np.ndarray) -> float:
    """How deep the bow has pushed into the floe along the crack line: the length of the crack line behind O
    (towards −direction) that still lies inside the floe (the part connected to O; compiled:
    `polygon_kernel.inside_length_from`)."""
    x0, y0, x1, y1 = shapely.bounds(polygon).tolist()
    reach = 2.0 * math.hypot(x1 - x0, y1 - y0) + 1.0
    return polygon_kernel.inside_length_from(
        *polygon_kernel.ring_arrays(polygon),
        float(origin_xy_m[0]),
        float(origin_xy_m[1]),
        -reach * float(direction[0]),
        -reach * float(direction[1]),
        _CONNECTED_M,
    )


_CONNECTED_M = 1e-6  # a line part within this distance of O starts at O


def extent_along_m(polygon, direction: np.ndarray) -> float:
    unit = direction / np.hypot(*direction)
    xy = shapely.get_coordinates(polygon)
    along = xy[:, 0] * unit[0] + xy[:, 1] * unit[1]  # element-wise, not `@`: BLAS kernels round per CPU
    return float(along.max() - along.min())


@dataclass(frozen=True)
class Cracking:
    name: ClassVar[str] = "cracking"
    settings: CrackingSettings = CrackingSettings()
    bending: BendingSettings = BendingSettings()  # ℓ's material and the point-load capacity P

    def criterion_check(self, inp: FailureInput, ctx: FailureContext, direction: np.ndarray):
        """The crack criterion at this contact (a `fracture.CrackCheck`)."""
        s = self.settings
        h = inp.thickness_m
        b = extent_along_m(inp.polygon, direction)
        bending = self.bending
        ell = characteristic_length_scalar_m(
            h, "eq1", bending.youngs_modulus_pa, bending.poisson_ratio, bending.foundation_modulus_n_m3
        )
        if s.crack_length == "indentation":
            a = indentation_depth_m(inp.polygon, inp.zone.centre_xy_m, direction)
        else:
            a = ell / 5.0
        a = max(a, MIN_CRACK_LENGTH_M)
        f_h = inp.zone.horizontal_force_n
        if s.criterion == "point_load":
            if s.point_load_capacity == "tensile_Pt":
                sigma_t = fracture.porosity_tensile_strength_pa(s.total_porosity_ppt)
                capacity = fracture.tensile_capacity_n(h, b, sigma_t)
            else:
                capacity = bending_check(inp, ctx, bending).capacity_n
            return fracture.check_point_load(f_h, capacity)
        if s.criterion == "line_load":
            if s.line_load_crack_length == "strip_critical":
                a = max(a, STRIP_CRITICAL_RELATIVE_CRACK_LENGTH * b)
            kappa = fracture.wedge_splitting_fraction(s.tip_angle_deg, s.wedge_friction)
            return fracture.check_line_load(
                f_h,
                h,
                a,
                s.fracture_toughness_pa_sqrt_m,
                kappa,
                divide_by_thickness=s.line_load_divide_by_thickness,
            )
        size = {"b": b, "thickness": h, "equiv_diameter": float(np.sqrt(4.0 * inp.polygon.area / np.pi))}[
            s.size_source
        ]
        loading = "tension" if s.criterion == "tensile_stress" else "bending"
        a = min(a, MAX_RELATIVE_CRACK_LENGTH * b)  # a deep indentation: the crack has nearly crossed the floe
        return fracture.check_stress_sif(
            crack_length_m=a,
            strip_width_m=b,
            size_m=size,
            toughness_pa_sqrt_m=s.fracture_toughness_pa_sqrt_m,
            law=s.size_effect_law,
            loading=loading,
            labels=s.tada_labels,
            bz2_mode=s.bz2_mode,
            stress_mode=s.stress_mode,
            horizontal_force_n=f_h,
            thickness_m=h,
        )

    def evaluate(self, inp: FailureInput, ctx: FailureContext) -> Outcome:
        direction = crack_direction(inp, np.radians(self.settings.next_crack_angle_deg))
        # no crack starts (driving < resistance, or the crack line does not split the floe): passed on — at
        # the shoulder the default policy then rotates the floe by its position (thesis §4.4)
        check = self.criterion_check(inp, ctx, direction)
        margin = log_margin(check.driving, check.resistance)
        if not check.fails:
            return pass_on(self.name, margin)
        left, right = split_by_line(inp.polygon, inp.zone.centre_xy_m, direction, inp.thickness_m)
        if not left or not right:
            return pass_on(self.name, margin)
        pieces = (NewPiece(p, Fate.FLOE, inp.crack_count + 1) for p in [*left, *right])
        return failed(self.name, pieces, margin)


# thesis-literal switches (physics-notes §5); bending's settings give ℓ's material and P
register_mode(
    Cracking,
    settings=CrackingSettings,
    material=("fracture_toughness_pa_sqrt_m",),
    thesis={
        "line_load_divide_by_thickness": False,  # erratum 17
        "line_load_crack_length": "indentation",  # erratum 19: a = the indentation depth, from 1 mm
        # not "stress_mode": "thesis" (erratum 19, Alg. 7's load-independent K_I): §3.2 makes K_I a threshold
        # of the horizontal force, §5.3.1 needs a "higher initial contact force", and Table 5's K_Ic
        # effects rule the literal form out (docs/model.md §11)
        # not "bz2_mode": "thesis" (erratum 15): Table 8 shows BZ2 ≈ BZ, which the literal law rules out
        # not "tada_labels": "thesis_alg7" (erratum 16, Alg. 7's swap): Table 6's flexural-vs-tensile
        # direction needs the correct labels (docs/model.md §11)
    },
    create=lambda settings: Cracking(settings["cracking"], settings["bending"]),
)
