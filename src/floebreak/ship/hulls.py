"""Built-in hulls: the parametric ice-waterline bow of physics-notes §6.3 and the two ships of the thesis.

No lines plans of S.A. Agulhas II or Polarstern are public (physics-notes §6.1), so both bows are parametric:
beam B, half entrance angle α_0, stem angle φ_s (from the horizontal) and an *assumed* shoulder flare β_sh.
Every assumed angle is a keyword with a documented default and is recorded in `Bow.parameters`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, Final

import numpy as np

from floebreak.constants import BOW_TIP_ANGLE_DEG
from floebreak.errors import Bounds, InputError, require_range
from floebreak.ship.agulhas_ii import BEAM_M, HALF_ENTRANCE_DEG, THESIS_STEM_ANGLE_DEG
from floebreak.ship.bow import FRAME_ANGLE_DEG, Bow, ice_waterline_heights, mirror_lines

# --- defaults (physics-notes §6.1–6.3); the "thesis" column of docs/_fragments/bow.md ---------------------
SHOULDERFRAME_ANGLE_DEG: Final = 20.0  # β_sh, flare at the shoulder from the vertical; ASSUMPTION (§6.3)
SHAPE_EXPONENT: Final = 2.0  # p of y(s) = (B/2)[1 − (1 − s/L_b)^p] (§6.3)
FLARE_EXPONENT: Final = 1.0  # q of β(s) = β_0 + (β_sh − β_0)(s/L_b)^q (§6.3)
N_PANELS_PER_SIDE: Final = 30  # bow panels stem → shoulder per side (thesis: "non-equally distributed", §3.1)
MIDBODY_LENGTH_M: Final = 10.0  # modelled parallel midbody aft of the shoulder (closes H_u, H_l; §6.3)
STEM_ANGLE_INTERPRETATIONS: Final = ("buttock", "panel_psi")  # physics-notes §6.2 (a) and (b)

AGULHAS_II_BEAM_M: Final = BEAM_M
AGULHAS_II_HALF_ENTRANCE_DEG: Final = HALF_ENTRANCE_DEG
AGULHAS_II_THESIS_STEM_ANGLE_DEG: Final = THESIS_STEM_ANGLE_DEG
POLARSTERN_BEAM_M: Final = 25.0  # thesis / physics-notes §6.1
POLARSTERN_HALF_ENTRANCE_DEG: Final = BOW_TIP_ANGLE_DEG / 2.0  # ASSUMED equal to Agulhas II (§6.3 table)
POLARSTERN_THESIS_STEM_ANGLE_DEG: Final = 45.0  # ψ_PS from the vertical, thesis

# The ranges of the parametric hull's parameters (`parametric_bow`, `stem_angle_from_thesis`), in this one
# place (range checks, `fuzz`). The bounds are physical: a beam of 1 m (a boat) to 100 m and a
# midbody ≤ 500 m (the largest ships are ≈ 70 m wide and ≈ 460 m long), an ice thickness ≤ 10 m
# (`floebreak.config.scenario.THICKNESS_M`), exponents ≤ 10 (p = 10 already makes the bow ten times as long
# as a
# straight wedge of the same entrance angle), ≤ 1000 panels a side (finer than any step of the bow); a half
# entrance angle and a stem angle of at least 5° (as `cracking.tip_angle_deg` ≥ 10°; ice-going bows have
# 15–45° and stems 17–30° from the horizontal): a needle bow of 1e-300° is 1e300 m long (its nodes overflow)
# and a flat stem's lower tip lies Δz / tan φ_s aft, at infinity for φ_s → 0 (fuzz campaign).
HULL_PARAMETER_BOUNDS: Final[dict[str, Bounds]] = {
    "beam_m": Bounds(1.0, 100.0, unit="m"),
    "waterline_entrance_half_angle_deg": Bounds(5.0, 90.0, high_inclusive=False, unit="deg"),
    "stem_angle_deg": Bounds(5.0, 90.0, unit="deg"),
    "shoulder_frame_angle_deg": FRAME_ANGLE_DEG,
    "shape_exponent": Bounds(1.0, 10.0),
    "flare_exponent": Bounds(0.0, 10.0, low_inclusive=False),
    "ice_thickness_m": Bounds(0.0, 10.0, low_inclusive=False, unit="m"),
    "midbody_length_m": Bounds(0.0, 500.0, unit="m"),
    "midbody_frame_angle_deg": FRAME_ANGLE_DEG,
    "thesis_stem_angle_deg": Bounds(0.0, 85.0, unit="deg"),  # from the vertical: 90° − stem angle (buttock)
}
N_PANELS_PER_SIDE_RANGE: Final = (2, 1000)


def hull_parameter_ranges() -> str:
    """The ranges of the hull parameters a scenario may override, as text (``floebreak schema``)."""

    def interval(b: Bounds) -> str:
        left, right = "[" if b.low_inclusive else "(", "]" if b.high_inclusive else ")"
        return f"{left}{b.low:g}, {b.high:g}{right}" + (f" {b.unit}" if b.unit else "")

    flare = " (< arctan(beam_m / (2 · ice thickness)) unless the whole lower waterline collapses)"
    ranges = [
        f"{key} {interval(b)}" + (flare if key.endswith("frame_angle_deg") else "")
        for key, b in HULL_PARAMETER_BOUNDS.items()
        if key != "ice_thickness_m"
    ]
    low, high = N_PANELS_PER_SIDE_RANGE
    return ", ".join([*ranges, f"n_panels_per_side {low} to {high}"])


def stem_angle_from_thesis(
    thesis_stem_angle_deg: float, half_entrance_deg: float, interpretation: str = "buttock"
) -> float:
    """Stem angle φ_s from the horizontal for a thesis "stem angle" ψ measured from the vertical (§6.2).

    "buttock" (default, interpretation (a)): ψ is the centreline stem inclination, φ_s = 90° − ψ.
    "panel_psi" (interpretation (b)): ψ is the panel angle ψ_v at the stem, tan ψ_v = sin α_0 / tan φ_s
    (physics-notes §2.1), so φ_s = arctan(sin α_0 / tan ψ).
    """
    psi = HULL_PARAMETER_BOUNDS["thesis_stem_angle_deg"].check("thesis_stem_angle_deg", thesis_stem_angle_deg)
    alpha0 = require_range("waterline_entrance_half_angle_deg", half_entrance_deg, low=0.0, high=90.0)
    if interpretation == "buttock":
        return 90.0 - psi
    if interpretation == "panel_psi":
        tan_psi = math.tan(math.radians(psi))
        if tan_psi == 0.0:  # a vertical stem panel (ψ = 0): a vertical stem, the limit φ_s → 90°
            return 90.0
        return math.degrees(math.atan(math.sin(math.radians(alpha0)) / tan_psi))
    raise InputError(
        "stem_angle_interpretation",
        f"unknown interpretation {interpretation!r}",
        value=interpretation,
        allowed=", ".join(STEM_ANGLE_INTERPRETATIONS),
    )


def parametric_bow(
    name: str,
    beam_m: float,
    waterline_entrance_half_angle_deg: float,
    stem_angle_deg: float,
    *,
    shoulder_frame_angle_deg: float = SHOULDERFRAME_ANGLE_DEG,
    shape_exponent: float = SHAPE_EXPONENT,
    flare_exponent: float = FLARE_EXPONENT,
    ice_thickness_m: float = 1.0,
    n_panels_per_side: int = N_PANELS_PER_SIDE,
    midbody_length_m: float = MIDBODY_LENGTH_M,
    midbody_frame_angle_deg: float | None = None,
) -> Bow:
    """The parametric two-waterline bow of physics-notes §6.3.

    With s the distance aft of the stem (x = −s), port half:

    * L_b = p (B/2) / tan α_0 (stem → shoulder), y(s) = (B/2)[1 − (1 − s/L_b)^p];
    * α(s) = arctan(tan α_0 (1 − s/L_b)^(p−1)) (waterline angle);
    * β_0 = arctan(tan α_0 / tan φ_s), β(s) = β_0 + (β_sh − β_0)(s/L_b)^q (frame angle from the vertical);
    * ψ_v(s) = arctan(tan β(s) cos α(s)) (panel angle from the vertical, physics-notes §2.1);
    * lower line: upper offset inward along (−sin α, −cos α) by Δz tan ψ_v; offsets crossing the centreline
      collapse onto the lower stem tip at x = −Δz / tan φ_s (consistent with the stem angle);
    * nodes s_k = L_b (1 − cos(π k / 2N)), k = 0 … N (dense at the stem), plus the aft end of a parallel
      midbody of length `midbody_length_m` (flare `midbody_frame_angle_deg`, default β_sh) when > 0.

    Δz = `ice_thickness_m` (z_u = (1 − ρ_i/ρ_w) h, z_l = −(ρ_i/ρ_w) h). `stem_angle_deg` is φ_s from the
    HORIZONTAL; see `stem_angle_from_thesis` for the thesis's angles from the vertical.
    """
    v = _checked_bow_parameters(
        beam_m,
        waterline_entrance_half_angle_deg,
        stem_angle_deg,
        shoulder_frame_angle_deg,
        shape_exponent,
        flare_exponent,
        ice_thickness_m,
        n_panels_per_side,
        midbody_length_m,
        midbody_frame_angle_deg,
    )
    z_upper, z_lower = ice_waterline_heights(v["ice_thickness_m"])
    dz = z_upper - z_lower
    alpha0, phi = math.radians(v["waterline_entrance_half_angle_deg"]), math.radians(v["stem_angle_deg"])
    length_bow = v["shape_exponent"] * (v["beam_m"] / 2.0) / math.tan(alpha0)
    beta0 = math.atan(math.tan(alpha0) / math.tan(phi))
    s, y, alpha, beta = _stations(v, alpha0, beta0, length_bow)
    psi = np.arctan(np.tan(beta) * np.cos(alpha))
    tip_x = -dz / math.tan(phi)
    upper, lower = mirror_lines(np.column_stack([-s, y]), alpha, psi, dz, tip_x)
    parameters: dict[str, Any] = {
        "model": "parametric_bow (physics-notes §6.3)",
        **v,
        "length_bow_m": length_bow,
        "frame_angle_stem_deg": math.degrees(beta0),
        "psi_stem_deg": math.degrees(math.atan(math.tan(beta0) * math.cos(alpha0))),
        "psi_shoulder_deg": v["shoulder_frame_angle_deg"],
        "lower_tip_x_m": tip_x,
    }
    return _bow_naming_parameters(name, upper, lower, (z_upper, z_lower), parameters)


def _bow_naming_parameters(name, upper, lower, heights_m, parameters: dict[str, Any]) -> Bow:
    """The `Bow`; an InputError of its waterline checks (made on the node arrays) also names the hull
    parameters that made them."""
    try:
        return Bow(name, upper, lower, *heights_m, parameters)
    except InputError as error:  # a waterline check on the node arrays: say which parameters make them
        dz_m = heights_m[0] - heights_m[1]
        for key in ("shoulder_frame_angle_deg", "midbody_frame_angle_deg"):  # the usual cause, named
            _check_flare_within_beam(key, parameters[key], parameters["beam_m"], dz_m)
        made_by = ", ".join(
            f"{key} = {parameters[key]:g}"
            for key in (
                "beam_m",
                "shoulder_frame_angle_deg",
                "flare_exponent",
                "shape_exponent",
                "ice_thickness_m",
            )
        )
        raise InputError(
            error.field,
            f"{str(error).removeprefix(f'{error.field}: ')}, in the waterlines these hull parameters make "
            f"({made_by})",
            value=error.value,
            allowed="less flare (shoulder_frame_angle_deg, midbody_frame_angle_deg, flare_exponent) or a "
            "wider beam_m",
        ) from None


def _check_flare_within_beam(key: str, frame_angle_deg: float, beam_m: float, dz_m: float) -> None:
    """InputError if the hull side at the shoulder (or along the midbody), flared by `frame_angle_deg` from
    the vertical, moves inward by the half beam or more across the ice thickness Δz: the lower ice waterline
    lies Δz·tan β inside the upper one there (α = 0, ψ_v = β, `mirror_lines`), so at β ≥ arctan(B / 2Δz)
    its aft nodes collapse onto the lower stem tip while nodes further forward do not, and the line folds
    across itself. (When every lower node collapses, the bow is valid: a lower waterline of one point.)"""
    limit_deg = math.degrees(math.atan(beam_m / (2.0 * dz_m)))
    if frame_angle_deg < limit_deg:
        return
    inward_m = dz_m * math.tan(math.radians(frame_angle_deg))
    raise InputError(
        key,
        f"{frame_angle_deg:g}° flares the hull side so much that across the ice thickness "
        f"(Δz = {dz_m:g} m) it moves inward by Δz·tan β = {inward_m:.4g} m, not less than the half beam "
        f"{beam_m / 2.0:g} m: the lower ice waterline reaches the centreline there and folds across itself",
        value=frame_angle_deg,
        allowed=f"[0, {limit_deg:.4g})° for beam_m = {beam_m:g} m and ice thickness {dz_m:g} m "
        "(below arctan(beam / (2 · thickness)))",
    )


def _stations(v: dict[str, Any], alpha0: float, beta0: float, length_bow: float):
    """Upper-waterline stations (physics-notes §6.3): distance aft s, half breadth y, waterline angle α and
    frame angle β per node; nodes dense at the stem, plus the midbody's aft end."""
    n, p, q = v["n_panels_per_side"], v["shape_exponent"], v["flare_exponent"]
    half_beam = v["beam_m"] / 2.0
    beta_sh = math.radians(v["shoulder_frame_angle_deg"])
    s = length_bow * (1.0 - np.cos(np.pi * np.arange(n + 1) / (2 * n)))
    s[-1] = length_bow
    u = s / length_bow
    y = half_beam * (1.0 - (1.0 - u) ** p)
    alpha = np.arctan(math.tan(alpha0) * (1.0 - u) ** (p - 1.0))
    beta = beta0 + (beta_sh - beta0) * u**q
    if v["midbody_length_m"] > 0.0:
        s = np.append(s, length_bow + v["midbody_length_m"])
        y = np.append(y, half_beam)
        alpha = np.append(alpha, 0.0)
        beta = np.append(beta, math.radians(v["midbody_frame_angle_deg"]))
    return s, y, alpha, beta


def _checked_bow_parameters(
    beam_m,
    alpha0_deg,
    stem_angle_deg,
    shoulder_frame_angle_deg,
    shape_exponent,
    flare_exponent,
    ice_thickness_m,
    n_panels_per_side,
    midbody_length_m,
    midbody_frame_angle_deg,
) -> dict[str, Any]:
    """The parameters of `parametric_bow`, range-checked against `HULL_PARAMETER_BOUNDS` and
    `N_PANELS_PER_SIDE_RANGE`, by name (InputError names the parameter)."""
    given = {
        "beam_m": beam_m,
        "waterline_entrance_half_angle_deg": alpha0_deg,
        "stem_angle_deg": stem_angle_deg,
        "shoulder_frame_angle_deg": shoulder_frame_angle_deg,
        "shape_exponent": shape_exponent,
        "flare_exponent": flare_exponent,
        "ice_thickness_m": ice_thickness_m,
    }
    values = {key: HULL_PARAMETER_BOUNDS[key].check(key, value) for key, value in given.items()}
    low, high = N_PANELS_PER_SIDE_RANGE
    if (
        isinstance(n_panels_per_side, bool)
        or not isinstance(n_panels_per_side, int | np.integer)
        or not low <= n_panels_per_side <= high
    ):
        raise InputError(
            "n_panels_per_side",
            f"must be an integer in [{low}, {high}], got {n_panels_per_side!r}",
            value=n_panels_per_side,
            allowed=f"[{low}, {high}]",
        )
    values["n_panels_per_side"] = int(n_panels_per_side)
    values["midbody_length_m"] = HULL_PARAMETER_BOUNDS["midbody_length_m"].check(
        "midbody_length_m", midbody_length_m
    )
    values["midbody_frame_angle_deg"] = (
        values["shoulder_frame_angle_deg"]
        if midbody_frame_angle_deg is None
        else HULL_PARAMETER_BOUNDS["midbody_frame_angle_deg"].check(
            "midbody_frame_angle_deg", midbody_frame_angle_deg
        )
    )
    return values


def _ship(
    name: str,
    beam_m: float,
    half_entrance_deg: float,
    thesis_stem_angle_deg: float,
    ice_thickness_m: float,
    overrides: dict[str, Any],
) -> Bow:
    allowed = set(_PARAMETRIC_KEYWORDS) | {"thesis_stem_angle_deg", "stem_angle_interpretation"}
    unknown = sorted(set(overrides) - allowed)
    if unknown:
        raise InputError(
            f"{name}.{unknown[0]}",
            "unknown hull parameter",
            value=unknown[0],
            allowed=", ".join(sorted(allowed)),
        )
    kw: dict[str, Any] = {
        "name": name,
        "beam_m": beam_m,
        "waterline_entrance_half_angle_deg": half_entrance_deg,
        "ice_thickness_m": ice_thickness_m,
    }
    thesis_angle = overrides.pop("thesis_stem_angle_deg", thesis_stem_angle_deg)
    interpretation = overrides.pop("stem_angle_interpretation", "buttock")
    kw.update(overrides)
    provenance: dict[str, Any] = {}
    if "stem_angle_deg" not in overrides:
        kw["stem_angle_deg"] = stem_angle_from_thesis(
            thesis_angle, kw["waterline_entrance_half_angle_deg"], interpretation
        )
        provenance = {"thesis_stem_angle_deg": thesis_angle, "stem_angle_interpretation": interpretation}
    bow = parametric_bow(**kw)
    if not provenance:
        return bow
    return Bow(
        bow.name,
        bow.upper_xy_m,
        bow.lower_xy_m,
        bow.z_upper_m,
        bow.z_lower_m,
        {**bow.parameters, **provenance},
    )


_PARAMETRIC_KEYWORDS: Final = (
    "name",
    "beam_m",
    "waterline_entrance_half_angle_deg",
    "stem_angle_deg",
    "shoulder_frame_angle_deg",
    "shape_exponent",
    "flare_exponent",
    "n_panels_per_side",
    "midbody_length_m",
    "midbody_frame_angle_deg",
)


def agulhas_ii(ice_thickness_m: float = 1.0, **overrides: Any) -> Bow:
    """S.A. Agulhas II (physics-notes §6.1, §6.3): B = 21.7 m, α_0 = 64.54°/2 = 32.27° (thesis Alg. 7),
    thesis stem angle 63° from the vertical → φ_s = 27° (interpretation "buttock", §6.2), β_sh = 20°
    (assumed).

    Gives L_b = 34.4 m, β_0 = 51.1°, ψ_v 46.3° at the stem → 20° at the shoulder, lower tip 1.96 m aft
    (Δz = 1 m).
    `overrides`: any `parametric_bow` keyword, `thesis_stem_angle_deg`, `stem_angle_interpretation`.
    """
    return _ship(
        "agulhas_ii",
        AGULHAS_II_BEAM_M,
        AGULHAS_II_HALF_ENTRANCE_DEG,
        AGULHAS_II_THESIS_STEM_ANGLE_DEG,
        ice_thickness_m,
        dict(overrides),
    )


def polarstern(ice_thickness_m: float = 1.0, **overrides: Any) -> Bow:
    """RV Polarstern (physics-notes §6.1, §6.3): B = 25 m, α_0 = 32.27° (ASSUMED, as Agulhas II), thesis stem
    angle 45° → φ_s = 45°, β_sh = 20° (assumed).

    Gives L_b = 39.6 m, β_0 = 32.3°, ψ_v 28.1° at the stem → 20° at the shoulder, lower tip 1.00 m aft
    (Δz = 1 m).
    """
    return _ship(
        "polarstern",
        POLARSTERN_BEAM_M,
        POLARSTERN_HALF_ENTRANCE_DEG,
        POLARSTERN_THESIS_STEM_ANGLE_DEG,
        ice_thickness_m,
        dict(overrides),
    )


HULLS: Final[dict[str, Callable[..., Bow]]] = {"agulhas_ii": agulhas_ii, "polarstern": polarstern}


def get_hull(name: str, /, **kw: Any) -> Bow:
    """Build the built-in hull `name` (a key of `HULLS`) with keyword overrides (``name`` among them renames
    the bow: `name` is positional only)."""
    if name not in HULLS:
        raise InputError("hull", f"unknown hull {name!r}", value=name, allowed=", ".join(sorted(HULLS)))
    return HULLS[name](**kw)
