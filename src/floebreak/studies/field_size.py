"""The thesis' field length, inferred from its affected ice area (docs/validation.md).

The thesis gives no field size. It does give, per field (means over its four fields, §5.3.3), the area of
all floes the bow affected at h = 1.0 m, A_aff = A_cusp^tot + A_flip^tot = 3446.38 m², the observation
(Table 1, 2019-12-18 20:20: 44 % cover; 20/40/40 % of the floes with d = 2.5/7.5/15 m) and the beam of the
Agulhas II (§3.1: 21.7 m). A floe is touched when its centre lies within B/2 + d/2 of the track, and a
touched floe is affected whole: it is flipped beside the bow or cracked until its pieces are cusps (§5.2,
Figs. 15–16). The floes lie wholly inside a field of width W (thesis §2.1: "the floes stay inside the
boundaries of the floe field"), so the centres of class d spread over W − d, not W: the floes of a class
are denser by W/(W − d) than the field's cover, and a share min(1, (B + d)/(W − d)) of them is touched.
Per metre of transit the bow therefore affects, for class d, the ice of a strip

    w_d = min(W, (B + d) · W/(W − d))      (→ B + d for a wide field)

and, weighting the classes by their share of the ice *area* (∝ p_d d²),

    A_aff = c_eff · L · Σ p_d d² w_d / Σ p_d d²,     L = A_aff / (c_eff · w̄).

The cover the thesis' fields really had is c_eff = c · (π/4)/(π/2) = c/2: its floe count uses the mean
floe area π d²/2 (erratum 1) while the floes drawn are circles of diameter d.

With the thesis' numbers and a wide field: w̄ = B + d_A = 21.7 + 1521.875/113.75 = 35.08 m (d_A the
area-weighted mean diameter), L = 3446.38 / (0.22 · 35.08) ≈ 447 m. At the study's W = 100 m
(`THESIS_FIELD_WIDTH_M`): w̄ = 40.68 m, L ≈ 385 m. The assumption that touched floes are affected whole
makes L a lower bound (were only the swept strip B affected, L = 722 m in a wide field); with the nominal
44 % cover L would be half.
"""

from __future__ import annotations

import tomllib
from collections.abc import Sequence
from typing import Any

from floebreak.config.scenario import REFERENCE_TOML, apply_overrides
from floebreak.errors import InputError

THESIS_AFFECTED_AREA_M2 = 3446.38  # thesis §5.3.3, h = 1.0 m, mean over its four fields
THESIS_BEAM_M = 21.7  # thesis §3.1, PSRV S.A. Agulhas II
THESIS_FLOE_AREA_FACTOR = 0.5  # thesis §2.1: A = π d²/2 = factor · π d² (erratum 1)
CIRCLE_AREA_FACTOR = 0.25  # a circle of diameter d: π d²/4
# The thesis gives no width. At W ≥ B + 2 d_max (51.7 m) every class the bow can touch has floes beside the
# touched band too, so the band holds a random sample of each class' lateral positions; 100 m keeps the
# classes' density excess W/(W − d) ≤ 18 % (docs/validation.md, "The thesis' field size").
THESIS_FIELD_WIDTH_M = 100.0


def affected_strip_width_m(
    beam_m: float,
    diameters_m: Sequence[float],
    percentages: Sequence[float],
    field_width_m: float | None = None,
    straddle_fraction: float = 1.0,
) -> float:
    """w̄ = Σ p d² w_d / Σ p d²: the width of field whose ice the bow affects per metre of transit [m].

    w_d = B + κ d in a field of unbounded width (`field_width_m` None), else min(W, (B + κ d) W/(W − d)):
    floes lie wholly inside the field, so the centres of class d spread over W − d (module docstring).
    κ = `straddle_fraction`: the share of a touched floe that is affected (1: whole floes, 0: the swept
    strip).
    """
    if len(diameters_m) != len(percentages) or not diameters_m:
        raise InputError(
            "percentages", "needs one share per diameter class", allowed="equal, non-empty lists"
        )
    if field_width_m is not None and not field_width_m > max(diameters_m):
        raise InputError(
            "field_width_m",
            f"{field_width_m} m does not hold the largest floe ({max(diameters_m)} m)",
            value=field_width_m,
            allowed=f"> {max(diameters_m)} m",
        )
    weights = [p * d * d for d, p in zip(diameters_m, percentages, strict=True)]
    if sum(weights) <= 0.0:
        raise InputError("percentages", "no floe area", allowed="positive shares and diameters")
    strips = []
    for d in diameters_m:
        strip = beam_m + straddle_fraction * d
        if field_width_m is not None:
            strip = min(field_width_m, strip * field_width_m / (field_width_m - d))
        strips.append(strip)
    return sum(w * s for w, s in zip(weights, strips, strict=True)) / sum(weights)


def infer_field_length_m(
    affected_area_m2: float,
    concentration: float,
    beam_m: float,
    diameters_m: Sequence[float],
    percentages: Sequence[float],
    floe_area_factor: float = THESIS_FLOE_AREA_FACTOR,
    straddle_fraction: float = 1.0,
    field_width_m: float | None = None,
) -> float:
    """Field length L [m] that gives `affected_area_m2` of affected floes in one transit.

    L = A_aff / (c_eff · w̄) with c_eff = c · 0.25 / floe_area_factor (the cover of fields whose floe count
    used the mean area floe_area_factor · π d², erratum 1) and w̄ the affected strip of
    `affected_strip_width_m` (field width `field_width_m`, None: unbounded). Module docstring: the reasoning.
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
    strip_m = affected_strip_width_m(beam_m, diameters_m, percentages, field_width_m, straddle_fraction)
    return affected_area_m2 / (effective_cover * strip_m)


def thesis_field_length_m(field_width_m: float | None = THESIS_FIELD_WIDTH_M) -> float:
    """The inferred length of the thesis' §5.3 fields (observation 2019-12-18T20:20) for fields
    `field_width_m` wide (None: unbounded), rounded to 1 m."""
    from floebreak.ice.observations import get_observation

    observation = get_observation("2019-12-18T20:20")
    length = infer_field_length_m(
        THESIS_AFFECTED_AREA_M2,
        observation.concentration,
        THESIS_BEAM_M,
        observation.diameter_classes_m,
        observation.percentages,
        field_width_m=field_width_m,
    )
    return float(round(length))


def thesis_scenario(sets: Sequence[str] = (), length_m: float | None = None) -> dict[str, Any]:
    """The reference scenario of thesis §5.3 on the thesis' field: `THESIS_FIELD_WIDTH_M` wide (or the width
    an override in `sets` gives) and `length_m` long (None: the length inferred for that width), with the
    overrides `sets` (``key=value``) applied. `validate thesis` and `study thesis` both start from it."""
    base = tomllib.loads(REFERENCE_TOML)
    base["field"]["width_m"] = THESIS_FIELD_WIDTH_M
    base = apply_overrides(base, list(sets))
    width_m = float(base["field"]["width_m"])
    base["field"]["length_m"] = thesis_field_length_m(width_m) if length_m is None else float(length_m)
    return base
