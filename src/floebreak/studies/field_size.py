"""The thesis' field length, inferred from its affected ice area (issue 16 §2; docs/validation.md).

The thesis gives no field size. It does give, per field (means over its four fields, §5.3.3), the area of
all floes the bow affected at h = 1.0 m, A_aff = A_cusp^tot + A_flip^tot = 3446.38 m², the observation
(Table 1, 2019-12-18 20:20: 44 % cover; 20/40/40 % of the floes with d = 2.5/7.5/15 m) and the beam of the
Agulhas II (§3.1: 21.7 m). A floe is touched when its centre lies within B/2 + d/2 of the track, and a
touched floe is affected whole: it is flipped beside the bow or cracked until its pieces are cusps (§5.2,
Figs. 15–16). Per metre of transit the bow therefore affects, for diameter class d, the ice of a strip
B + d wide; weighting the classes by their share of the ice *area* (∝ p_d d²),

    A_aff = c_eff · L · (B + d_A),      d_A = Σ p_d d³ / Σ p_d d²   (area-weighted mean diameter),

so L = A_aff / (c_eff (B + d_A)). The cover the thesis' fields really had is c_eff = c · (π/4)/(π/2) = c/2:
its floe count uses the mean floe area π d²/2 (erratum 1) while the floes drawn are circles of diameter d.

With the thesis' numbers: d_A = 1521.875 / 113.75 = 13.38 m, c_eff = 0.22, L = 3446.38 / (0.22 · 35.08)
≈ 447 m. The assumption that touched floes are affected whole makes this a lower bound of the length
(were only the swept strip B affected, L = 722 m); with the nominal 44 % cover L would be half.
"""

from __future__ import annotations

from collections.abc import Sequence

from floebreak.errors import InputError

THESIS_AFFECTED_AREA_M2 = 3446.38  # thesis §5.3.3, h = 1.0 m, mean over its four fields
THESIS_BEAM_M = 21.7  # thesis §3.1, PSRV S.A. Agulhas II
THESIS_FLOE_AREA_FACTOR = 0.5  # thesis §2.1: A = π d²/2 = factor · π d² (erratum 1)
CIRCLE_AREA_FACTOR = 0.25  # a circle of diameter d: π d²/4


def area_weighted_diameter_m(diameters_m: Sequence[float], percentages: Sequence[float]) -> float:
    """d_A = Σ p d³ / Σ p d²: the mean diameter of the floes weighted by their area [m]."""
    if len(diameters_m) != len(percentages) or not diameters_m:
        raise InputError(
            "percentages", "needs one share per diameter class", allowed="equal, non-empty lists"
        )
    second = sum(p * d * d for d, p in zip(diameters_m, percentages, strict=True))
    third = sum(p * d**3 for d, p in zip(diameters_m, percentages, strict=True))
    if second <= 0.0:
        raise InputError("percentages", "no floe area", allowed="positive shares and diameters")
    return third / second


def infer_field_length_m(
    affected_area_m2: float,
    concentration: float,
    beam_m: float,
    diameters_m: Sequence[float],
    percentages: Sequence[float],
    floe_area_factor: float = THESIS_FLOE_AREA_FACTOR,
    straddle_fraction: float = 1.0,
) -> float:
    """Field length L [m] that gives `affected_area_m2` of affected floes in one transit.

    L = A_aff / (c_eff · (B + κ d_A)) with c_eff = c · 0.25 / floe_area_factor (the cover of fields whose
    floe count used the mean area floe_area_factor · π d², erratum 1), d_A the area-weighted mean diameter
    and κ = `straddle_fraction` the share of a touched floe that is affected (1: whole floes, 0: only the
    swept strip of width B). Module docstring: the reasoning.
    """
    for name, value in (("affected_area_m2", affected_area_m2), ("beam_m", beam_m)):
        if not value > 0.0:
            raise InputError(name, f"{value} is not positive", value=value, allowed="> 0")
    if not 0.0 < concentration <= 1.0:
        raise InputError("concentration", f"{concentration}", value=concentration, allowed="(0, 1]")
    if not floe_area_factor > 0.0:
        raise InputError("floe_area_factor", f"{floe_area_factor}", value=floe_area_factor, allowed="> 0")
    if not 0.0 <= straddle_fraction <= 1.0:
        raise InputError(
            "straddle_fraction", f"{straddle_fraction}", value=straddle_fraction, allowed="[0, 1]"
        )
    effective_cover = concentration * CIRCLE_AREA_FACTOR / floe_area_factor
    width_m = beam_m + straddle_fraction * area_weighted_diameter_m(diameters_m, percentages)
    return affected_area_m2 / (effective_cover * width_m)


def thesis_field_length_m() -> float:
    """The inferred length of the thesis' §5.3 fields (observation 2019-12-18T20:20), rounded to 1 m."""
    from floebreak.ice.observations import get_observation

    observation = get_observation("2019-12-18T20:20")
    length = infer_field_length_m(
        THESIS_AFFECTED_AREA_M2,
        observation.concentration,
        THESIS_BEAM_M,
        observation.diameter_classes_m,
        observation.percentages,
    )
    return float(round(length))
