"""Global failure by cracking (thesis §4.2, Alg. 5 and 7; physics-notes §3.3, §4; errata 14–21).

The crack line runs through the zone centre O ("midBow"), orthogonal to the bow panel (along the
outward normal n̂, thesis Eq. 20) and, once started, through the whole floe (thesis §3.1: "cracking
started once will lead to a full crack"). A piece whose ancestry has cracked before gets its crack
rotated by α_nextcrack = 30° (thesis §4.2.3, Fig. 11), to the side that passes closer to the piece's
centroid (the thesis does not say which side; this gives the more even split).

Criteria (`criterion`):
- ``point_load``: F_h > P with P the Nevel bending capacity at the contact (thesis Alg. 7
  `fracture_criterion_simple`) or P_t = σ_t h b (thesis §4.2.1; `point_load_capacity = "tensile_Pt"`);
- ``line_load``: K_I = 0.878 (κ F_h / h) √(π/a) ≥ K_Ic (Alg. 7 line load, /h added: erratum 17);
- ``tensile_stress`` / ``flexural_stress``: K_I = σ_n^t(L) √(πa) · Tada factor ≥ K_Ic (Alg. 7, Eq. 19),
  load-independent (physics-notes §4.4), size-effect law BZ/BZ1/BZ2 for σ_n^t.
Crack length a: the indentation depth along the crack line (default) or ℓ/5 (the crack-line start offset of
Alg. 5). Floe length b: the floe's extent along the crack direction. Size L: b by default.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar, Literal

import numpy as np
import shapely

from floebreak import constants as c
from floebreak.errors import InputError, require_range
from floebreak.failure.base import (
    FailureContext,
    FailureInput,
    Fate,
    NewPiece,
    Outcome,
    no_failure,
    split_parts,
)
from floebreak.failure.bending import BendingSettings, bending_check
from floebreak.ice.material import characteristic_length_scalar_m
from floebreak.mechanics import fracture, polygon_kernel

CrackCriterion = Literal["point_load", "line_load", "tensile_stress", "flexural_stress"]
PointLoadCapacity = Literal["bending_P", "tensile_Pt"]
CrackLengthDefinition = Literal["indentation", "ell_over_5"]
SizeSource = Literal["b", "equiv_diameter", "thickness"]

MAX_RELATIVE_CRACK_LENGTH = 0.95  # a/b cap for the Tada factors (they diverge as a → b)
MIN_CRACK_LENGTH_M = 1e-3  # a → 0 makes K_I singular (line load) or zero (stress); keep it finite


@dataclass(frozen=True)
class CrackingSettings:
    criterion: CrackCriterion = "tensile_stress"
    fracture_toughness_pa_sqrt_m: float = c.FRACTURE_TOUGHNESS_PA_SQRT_M
    size_effect_law: fracture.SizeEffectLaw = "BZ"
    bz2_mode: fracture.BZ2Mode = "generalised"
    size_source: SizeSource = "b"
    tada_labels: fracture.TadaLabels = "correct"
    crack_length: CrackLengthDefinition = "indentation"
    point_load_capacity: PointLoadCapacity = "bending_P"
    total_porosity_ppt: float = c.TOTAL_POROSITY_PPT
    tip_angle_deg: float = c.BOW_TIP_ANGLE_DEG
    wedge_friction: float = 0.0  # κ with μ = 0 is the thesis' 1/(2 tan(α/2))
    line_load_divide_by_thickness: bool = True
    stress_mode: fracture.StressMode = "thesis"  # physics-notes §4.4: thesis K_I(σ_n^t) form; or strength/sif
    next_crack_angle_deg: float = c.NEXT_CRACK_ANGLE_DEG
    bending: BendingSettings = field(default_factory=BendingSettings)

    def __post_init__(self) -> None:
        require_range(
            "ice.fracture_toughness_pa_sqrt_m", self.fracture_toughness_pa_sqrt_m, low=0.0, unit="Pa·√m"
        )
        require_range(
            "failure.next_crack_angle_deg",
            self.next_crack_angle_deg,
            low=0.0,
            high=90.0,
            low_inclusive=True,
            unit="deg",
        )
        require_range(
            "failure.tip_angle_deg", self.tip_angle_deg, low=0.0, high=180.0, high_inclusive=False, unit="deg"
        )
        allowed = ("point_load", "line_load", "tensile_stress", "flexural_stress")
        if self.criterion not in allowed:
            raise InputError("failure.crack_criterion", repr(self.criterion), allowed=", ".join(allowed))


def crack_direction(inp: FailureInput, next_crack_angle_rad: float) -> np.ndarray:
    """Unit direction of the crack: the bow normal, rotated by ±α_nextcrack after an earlier crack."""
    normal = np.asarray(inp.zone.centre_normal, dtype=float)
    if inp.crack_count == 0 or next_crack_angle_rad == 0.0:
        return normal
    centroid = np.array(shapely.get_coordinates(shapely.centroid(inp.polygon))[0])
    to_centroid = centroid - inp.zone.centre_xy_m
    best, best_offset = normal, np.inf
    for sign in (1.0, -1.0):
        angle = sign * next_crack_angle_rad
        rotated = np.array(
            [
                np.cos(angle) * normal[0] - np.sin(angle) * normal[1],
                np.sin(angle) * normal[0] + np.cos(angle) * normal[1],
            ]
        )
        offset = abs(
            rotated[0] * to_centroid[1] - rotated[1] * to_centroid[0]
        )  # distance of centroid to line
        if offset < best_offset:
            best, best_offset = rotated, offset
    return best


def split_by_line(polygon, point_xy_m: np.ndarray, direction: np.ndarray) -> tuple[list, list]:
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
    return split_parts(left, right)


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
    along = shapely.get_coordinates(polygon) @ (direction / np.hypot(*direction))
    return float(along.max() - along.min())


@dataclass(frozen=True)
class Cracking:
    name: ClassVar[str] = "cracking"
    settings: CrackingSettings = CrackingSettings()

    def criterion_check(self, inp: FailureInput, ctx: FailureContext, direction: np.ndarray):
        """The crack criterion at this contact (a `fracture.CrackCheck`)."""
        s = self.settings
        h = inp.thickness_m
        b = extent_along_m(inp.polygon, direction)
        bending = s.bending
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
        check = self.criterion_check(inp, ctx, direction)
        info = {"driving": float(check.driving), "resistance": float(check.resistance)}
        if not check.fails:
            return no_failure(self.name, f"{check.quantity}: driving < resistance", **info)
        left, right = split_by_line(inp.polygon, inp.zone.centre_xy_m, direction)
        if not left or not right:
            return no_failure(
                self.name, "no initial crack point: the crack line does not split the floe", **info
            )
        pieces = tuple(NewPiece(p, Fate.FLOE, inp.crack_count + 1) for p in [*left, *right])
        return Outcome(
            self.name, True, pieces, reason=f"{check.quantity}: driving ≥ resistance", diagnostics=info
        )
