"""Fracture mechanics for global cracking (thesis §4.2, Eqs. 12–19, Alg. 7; physics-notes §3.3, §4).

Errata 14–20 of physics-notes §5 are corrected here; each has a thesis-compatible switch.

Pure functions, SI units in and out (Pa, Pa·√m, N, m). The consumer is `floebreak.failure.cracking`.

- Tensile strength from total porosity, corrected thesis Eq. 13 (erratum 14, physics-notes §4.2).
- Tensile capacity P_t = σ_t h l (thesis §4.2.1, Eq. 14; erratum 20).
- Wedge splitting fraction κ = F_cr / F_h of the bow stem (physics-notes §3.3; thesis Alg. 7 uses μ = 0).
- Line-load stress-intensity factor K_I = 0.878 (κ F_h / h) √(π/a) (physics-notes §4.3; erratum 17 adds 1/h).
- Size-effect laws BZ, BZ1, BZ2 for the nominal tensile strength σ_n^t(L) (thesis Eqs. 15–17, Table 3;
  physics-notes §4.1; erratum 15 corrects BZ2).
- Tada edge-crack geometry factors for tension and in-plane bending (thesis Eq. 19; physics-notes §4.3;
  erratum 16 – the thesis swaps them).
- The stress criteria of Alg. 7 (physics-notes §4.4; erratum 19 – load-independent in the thesis) with
  the notes' load-consistent alternatives.

Every check returns a `CrackCheck` whose ``driving`` and ``resistance`` share the unit named in ``quantity``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Final, Literal

import numpy as np

from floebreak.errors import Bounds, InputError, require_range

SizeEffectLaw = Literal["BZ", "BZ1", "BZ2"]
BZ2Mode = Literal["generalised", "thesis"]
# "thesis": swapped labels and the exponent 4 printed in the thesis text (Eq. 19 variant for flexure);
# "thesis_alg7": swapped labels with the exponent 3 of thesis Alg. 7 (the code as run).
TadaLabels = Literal["correct", "thesis", "thesis_alg7"]
Loading = Literal["tension", "bending"]
# "thesis": K_I(σ_n^t) ≥ K_Ic, load-independent (Alg. 7, erratum 19);
# "strength": σ_app = F_h / (h b) ≥ σ_n^t(L) (physics-notes §4.4 `stress_mode_consistent`);
# "sif": K_I(σ_app) ≥ K_Ic with σ_app = F_h / (h b) (physics-notes §4.4, last alternative).
StressMode = Literal["thesis", "strength", "sif"]

SIZE_EFFECT_LAWS: Final = ("BZ", "BZ1", "BZ2")
BZ2_MODES: Final = ("generalised", "thesis")
TADA_LABELS: Final = ("correct", "thesis", "thesis_alg7")
LOADINGS: Final = ("tension", "bending")
STRESS_MODES: Final = ("thesis", "strength", "sif")

MPA_TO_PA: Final = 1.0e6

# --- Eq. 13 (corrected, erratum 14): σ_t = 4.278 ν_t^(−0.6455) MPa, ν_t in ppt (physics-notes §4.2) -------
POROSITY_STRENGTH_COEFFICIENT_MPA: Final = 4.278
POROSITY_STRENGTH_EXPONENT: Final = -0.6455

# --- Line load on the crack faces (physics-notes §4.3): K_I = 0.439 p √(πa), p = 2 F_cr / (h a) -----------
LINEAR_PRESSURE_SIF_COEFFICIENT: Final = 0.439  # = 1.1215 − 0.683 (uniform minus linearly increasing)
LINE_LOAD_SIF_COEFFICIENT: Final = 2.0 * LINEAR_PRESSURE_SIF_COEFFICIENT  # 0.878, thesis Alg. 7

# --- Size-effect constants, thesis Table 3 / Dempsey et al. (1999), 0.5–80 m range (physics-notes §4.1) ---
SIZE_EFFECT_SIGMA_MPA: Final = {"BZ": 0.68, "BZ1": 2.4, "BZ2": 0.38}  # Σ [MPa]
SIZE_EFFECT_B_M: Final = {"BZ": 0.26, "BZ1": 0.02, "BZ2": 0.71}  # B [m]
BZ1_C_M: Final = 5.85  # C [m]
BZ2_F_DEMPSEY: Final = 466.0  # F of Dempsey et al. (generalised SEL)
BZ2_F_THESIS: Final = 4.66  # F as changed by the thesis (Table 3)
SIZE_EFFECT_RANGE_M: Final = (0.5, 80.0)  # fitted range of L; clamp to it (physics-notes §4.1)

# --- Tada, Paris & Irwin edge crack in a strip (physics-notes §4.3) ---------------------------------------
TADA_EDGE_CRACK_LIMIT: Final = 1.122  # both factors → 0.752 + 0.37 = 0.923 + 0.199 = 1.122 as a/b → 0


@dataclass(frozen=True)
class CrackCheck:
    """Result of a crack criterion: ``fails`` when ``driving`` reaches ``resistance`` (unit: ``quantity``)."""

    fails: bool
    driving: float
    resistance: float
    quantity: str


# ----------------------------------------------------------------------------------------------------------
# Tensile capacity (thesis §4.2.1)
# ----------------------------------------------------------------------------------------------------------


def porosity_tensile_strength_pa(total_porosity_ppt: float) -> float:
    """Tensile strength σ_t [Pa] from the total porosity ν_t [ppt, ‰].

    Corrected thesis Eq. 13 (erratum 14, physics-notes §4.2; Richter-Menge & Jones 1993):
    σ_t = 4.278 · ν_t^(−0.6455) MPa. ν_t = 50 ppt gives 0.342 MPa.
    """
    nu = require_range("ice.total_porosity_ppt", total_porosity_ppt, low=0.0, high=1000.0, unit="ppt")
    return POROSITY_STRENGTH_COEFFICIENT_MPA * nu**POROSITY_STRENGTH_EXPONENT * MPA_TO_PA


def tensile_capacity_n(thickness_m: float, length_m: float, tensile_strength_pa: float) -> float:
    """Tensile capacity P_t = σ_t h l [N] of a floe of thickness h, length l (thesis §4.2.1, erratum 20)."""
    h = require_range("thickness_m", thickness_m, low=0.0, unit="m")
    length = require_range("length_m", length_m, low=0.0, unit="m")
    sigma = require_range("tensile_strength_pa", tensile_strength_pa, low=0.0, unit="Pa")
    return sigma * h * length


def check_point_load(horizontal_force_n: float, capacity_n: float) -> CrackCheck:
    """Point-load criterion: fails when F_h > P (thesis Alg. 7 `fracture_criterion_simple`, Eq. 14).

    ``capacity_n`` is either the bending capacity P (thesis code) or P_t = σ_t h l (thesis text), erratum 20.
    """
    f_h = require_range("horizontal_force_n", horizontal_force_n, low=0.0, low_inclusive=True, unit="N")
    capacity = require_range("capacity_n", capacity_n, low=0.0, low_inclusive=True, unit="N")
    return CrackCheck(fails=f_h > capacity, driving=f_h, resistance=capacity, quantity="F_h [N]")


# ----------------------------------------------------------------------------------------------------------
# Line load (wedge splitting)
# ----------------------------------------------------------------------------------------------------------


# the full waterline entrance angle of a bow (ice-going bows ≈ 40–90°); κ grows without bound as α → 0
TIP_ANGLE_DEG: Final = Bounds(10.0, 170.0, unit="deg")


def wedge_splitting_fraction(tip_angle_deg: float, friction: float = 0.0) -> float:
    """κ = F_cr / F_h: force on each crack face per unit horizontal bow force (physics-notes §3.3).

    κ = (1 − μ tan(α/2)) / (2 (tan(α/2) + μ)), α the full waterline angle at the stem. With μ = 0 this is the
    thesis' 1/(2 tan(α/2)) (Alg. 7). α = 64.54° gives κ = 0.792 (μ = 0) or 0.579 (μ = 0.15).
    """
    alpha = TIP_ANGLE_DEG.check("failure.cracking.tip_angle_deg", tip_angle_deg)
    mu = require_range("failure.cracking.wedge_friction", friction, low=0.0, low_inclusive=True)
    tan_half = math.tan(math.radians(alpha) / 2.0)
    if mu * tan_half >= 1.0:
        raise InputError(
            "failure.cracking.wedge_friction",
            f"μ = {mu:g} with α = {alpha:g}° makes the wedge self-locking (μ tan(α/2) ≥ 1)",
            value=mu,
            allowed=f"< {1.0 / tan_half:g}",
        )
    return (1.0 - mu * tan_half) / (2.0 * (tan_half + mu))


def line_load_sif_pa_sqrt_m(
    crack_face_force_n: float, thickness_m: float, crack_length_m: float, *, divide_by_thickness: bool = True
) -> float:
    """K_I [Pa√m] of an edge crack loaded by a triangular crack-face pressure of total force F_cr per face.

    K_I = 0.878 (F_cr / h) √(π/a) (physics-notes §4.3; thesis Alg. 7 line load). With
    ``divide_by_thickness=False`` the thesis-literal 0.878 F_cr √(π/a) (erratum 17; equal only at h = 1 m).
    """
    f_cr = require_range("crack_face_force_n", crack_face_force_n, low=0.0, low_inclusive=True, unit="N")
    h = require_range("thickness_m", thickness_m, low=0.0, unit="m")
    a = require_range("crack_length_m", crack_length_m, low=0.0, unit="m")
    per_thickness = f_cr / h if divide_by_thickness else f_cr
    return LINE_LOAD_SIF_COEFFICIENT * per_thickness * math.sqrt(math.pi / a)


def check_line_load(
    horizontal_force_n: float,
    thickness_m: float,
    crack_length_m: float,
    toughness_pa_sqrt_m: float,
    kappa: float,
    *,
    divide_by_thickness: bool = True,
) -> CrackCheck:
    """Line-load criterion K_I = 0.878 (κ F_h / h) √(π/a) ≥ K_Ic (thesis Alg. 7, Eq. 18; erratum 17)."""
    f_h = require_range("horizontal_force_n", horizontal_force_n, low=0.0, low_inclusive=True, unit="N")
    k = require_range("kappa", kappa, low=0.0, low_inclusive=True)
    k_ic = require_range("ice.fracture_toughness_pa_sqrt_m", toughness_pa_sqrt_m, low=0.0, unit="Pa·√m")
    k_i = line_load_sif_pa_sqrt_m(
        k * f_h, thickness_m, crack_length_m, divide_by_thickness=divide_by_thickness
    )
    return CrackCheck(fails=k_i >= k_ic, driving=k_i, resistance=k_ic, quantity="K_I [Pa√m]")


# ----------------------------------------------------------------------------------------------------------
# Size-effect laws (thesis Eqs. 15–17, Table 3)
# ----------------------------------------------------------------------------------------------------------


def _check_choice(field: str, value: str, allowed: tuple[str, ...]) -> str:
    if value not in allowed:
        raise InputError(field, f"unknown value {value!r}", value=value, allowed=", ".join(allowed))
    return value


def _positive_array(field: str, value, unit: str) -> np.ndarray:
    array = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(array)) or np.any(array <= 0.0):
        raise InputError(
            field,
            f"{value!r} must be finite and > 0 {unit}".rstrip(),
            value=value,
            allowed=f"(0, inf) {unit}".rstrip(),
        )
    return array


def _as_output(array: np.ndarray, like) -> float | np.ndarray:
    return float(array) if np.ndim(like) == 0 else array


def bz2_generalised_mpa(size_m, *, sigma_mpa: float, transition_m: float, exponent_f: float):
    """Bažant's generalised size-effect law σ = Σ [1 + (L/B)^F]^(−1/(2F)) [MPa], in log space (§4.1).

    σ = Σ · exp(−logaddexp(0, F ln(L/B)) / (2F)); no overflow for F = 466.
    """
    length = np.asarray(size_m, dtype=float)
    log_ratio = exponent_f * np.log(length / transition_m)
    return sigma_mpa * np.exp(-np.logaddexp(0.0, log_ratio) / (2.0 * exponent_f))


def bz2_thesis_literal_mpa(size_m, *, sigma_mpa: float, transition_m: float, exponent_f: float):
    """Thesis-literal Eq. 17 σ = Σ [1 + (L/B)^F]^(−1/2) [MPa] (1/F missing, erratum 15), in log space."""
    length = np.asarray(size_m, dtype=float)
    log_ratio = exponent_f * np.log(length / transition_m)
    return sigma_mpa * np.exp(-0.5 * np.logaddexp(0.0, log_ratio))


def size_effect_strength_pa(
    size_m, law: SizeEffectLaw, *, bz2_mode: BZ2Mode = "generalised", clamp: bool = True
) -> float | np.ndarray:
    """Nominal tensile strength σ_n^t(L) [Pa] of a structure of size L [m] (thesis Eqs. 15–17, Table 3).

    physics-notes §4.1 (Σ in MPa, B and C in m, L the floe length in the crack direction):
    - BZ  (Eq. 15): σ = Σ (1 + L/B)^(−1/2),                Σ = 0.68, B = 0.26;
    - BZ1 (Eq. 16): σ = Σ (1 + L/B + C/L)^(−1/2),          Σ = 2.4,  B = 0.02, C = 5.85;
    - BZ2 (Eq. 17): ``bz2_mode="generalised"`` (default, erratum 15): σ = Σ [1 + (L/B)^F]^(−1/(2F)), F = 466
      (Dempsey); ``"thesis"``: thesis-literal σ = Σ [1 + (L/B)^F]^(−1/2) with the thesis' F = 4.66.
    With ``clamp`` (default) L is clamped to the fitted range [0.5, 80] m (BZ1 → 0 as L → 0 is unphysical).
    Accepts scalars or arrays; returns the same shape.
    """
    _check_choice("failure.size_effect_law", law, SIZE_EFFECT_LAWS)
    _check_choice("failure.bz2_mode", bz2_mode, BZ2_MODES)
    length = _positive_array("size_m", size_m, "m")
    if clamp:
        length = np.clip(length, *SIZE_EFFECT_RANGE_M)
    return _as_output(_size_effect_strength_mpa(length, law, bz2_mode) * MPA_TO_PA, size_m)


def _size_effect_strength_mpa(length, law: SizeEffectLaw, bz2_mode: BZ2Mode):
    """σ_n^t(L) [MPa] of Eqs. 15–17 for validated (and clamped) L, a float or an array."""
    sigma = SIZE_EFFECT_SIGMA_MPA[law]
    transition = SIZE_EFFECT_B_M[law]
    if law == "BZ":
        return sigma / np.sqrt(1.0 + length / transition)
    if law == "BZ1":
        return sigma / np.sqrt(1.0 + length / transition + BZ1_C_M / length)
    if bz2_mode == "generalised":
        return bz2_generalised_mpa(length, sigma_mpa=sigma, transition_m=transition, exponent_f=BZ2_F_DEMPSEY)
    return bz2_thesis_literal_mpa(length, sigma_mpa=sigma, transition_m=transition, exponent_f=BZ2_F_THESIS)


# ----------------------------------------------------------------------------------------------------------
# Tada stress-intensity factors (thesis Eq. 19, physics-notes §4.3)
# ----------------------------------------------------------------------------------------------------------


def _tan_ratio_sqrt(t):
    """√(tan t / t), = 1 at t = 0 (a float or an array)."""
    if np.ndim(t) == 0:
        return np.sqrt(np.tan(t) / t) if t > 0.0 else 1.0
    safe = np.where(t > 0.0, t, 1.0)
    return np.where(t > 0.0, np.sqrt(np.tan(safe) / safe), 1.0)


def tada_tension_g(relative_crack_length, *, exponent: int = 3):
    """Tada G_T(ε) = [0.752 + 2.02 ε + 0.37 (1 − sin t)^3] / cos t, t = πε/2 (edge crack, remote tension).

    ``exponent=4`` reproduces the thesis text's misprint (erratum 16).
    """
    eps = np.asarray(relative_crack_length, dtype=float)
    t = 0.5 * np.pi * eps
    return (0.752 + 2.02 * eps + 0.37 * (1.0 - np.sin(t)) ** exponent) / np.cos(t)


def tada_bending_g(relative_crack_length):
    """Tada G_B(ε) = [0.923 + 0.199 (1 − sin t)^4] / cos t, t = πε/2 (edge crack, in-plane bending)."""
    eps = np.asarray(relative_crack_length, dtype=float)
    t = 0.5 * np.pi * eps
    return (0.923 + 0.199 * (1.0 - np.sin(t)) ** 4) / np.cos(t)


def tada_geometry_factor(relative_crack_length, loading: Loading, *, labels: TadaLabels = "correct"):
    """F(ε) = √(tan t / t) · G(ε) with K_I = σ √(πa) F(a/b), ε = a/b ∈ [0, 1) (thesis Eq. 19, §4.3).

    ``labels="correct"``: tension → G_T, bending → G_B (Tada handbook). ``"thesis"``: swapped as in the
    thesis text (tension → G_B; "flexural" → the 0.752 polynomial with the printed exponent 4);
    ``"thesis_alg7"``: swapped, exponent 3 as in Alg. 7 (erratum 16). F → 1.122 as ε → 0 for every choice.
    Accepts scalars or arrays.
    """
    _check_choice("loading", loading, LOADINGS)
    _check_choice("failure.tada_labels", labels, TADA_LABELS)
    eps = np.asarray(relative_crack_length, dtype=float)
    if not np.all(np.isfinite(eps)) or np.any(eps < 0.0) or np.any(eps >= 1.0):
        raise InputError(
            "a/b",
            f"{relative_crack_length!r} must lie in [0, 1)",
            value=relative_crack_length,
            allowed="[0, 1)",
        )
    return _as_output(_tada_factor(eps, loading, labels), relative_crack_length)


def _tada_factor(eps, loading: Loading, labels: TadaLabels):
    """F(ε) of `tada_geometry_factor` for validated ε ∈ [0, 1), a float or an array."""
    use_tension_polynomial = (loading == "tension") == (labels == "correct")
    if use_tension_polynomial:
        g = tada_tension_g(eps, exponent=4 if labels == "thesis" else 3)
    else:
        g = tada_bending_g(eps)
    return _tan_ratio_sqrt(0.5 * np.pi * eps) * g


def _crack_geometry(crack_length_m: float, strip_width_m: float) -> tuple[float, float]:
    a = require_range("crack_length_m", crack_length_m, low=0.0, unit="m")
    b = require_range("strip_width_m", strip_width_m, low=0.0, unit="m")
    if a >= b:
        raise InputError(
            "crack_length_m",
            f"a = {a:g} m must be shorter than the strip width b = {b:g} m",
            value=a,
            allowed=f"(0, {b:g}) m",
        )
    return a, b


def check_stress_sif(
    *,
    crack_length_m: float,
    strip_width_m: float,
    size_m: float,
    toughness_pa_sqrt_m: float,
    law: SizeEffectLaw,
    loading: Loading,
    labels: TadaLabels = "correct",
    bz2_mode: BZ2Mode = "generalised",
    stress_mode: StressMode = "thesis",
    horizontal_force_n: float | None = None,
    thickness_m: float | None = None,
) -> CrackCheck:
    """Stress criteria ``tensile_stress`` / ``flexural_stress`` of Alg. 7 (physics-notes §4.4, erratum 19).

    σ_n^t = σ_n^t(L = ``size_m``) from the size-effect law; F(a/b) the Tada factor for ``loading``/``labels``.

    - ``stress_mode="thesis"`` (default, as the thesis): driving = K_I = σ_n^t √(πa) F(a/b) [Pa√m],
      resistance = K_Ic [Pa√m]. **Load-independent**: the strength σ_n^t is used as the applied stress, so
      failure depends only on a, b and L (BZ, b = L = 10 m: a ≥ 0.44 m correct, 0.50 m thesis labels).
    - ``"strength"`` (notes' `stress_mode_consistent`): driving = σ_app = F_h / (h b) [Pa],
      resistance = σ_n^t(L) [Pa]; the size-effect law is the strength criterion, no K_Ic needed.
    - ``"sif"``: driving = K_I = σ_app √(πa) F(a/b) [Pa√m], resistance = K_Ic [Pa√m].
    The load-consistent modes need ``horizontal_force_n`` and ``thickness_m``.
    Fails when driving ≥ resistance.
    """
    _check_choice("failure.stress_mode", stress_mode, STRESS_MODES)
    _check_choice("failure.size_effect_law", law, SIZE_EFFECT_LAWS)
    _check_choice("failure.bz2_mode", bz2_mode, BZ2_MODES)
    _check_choice("loading", loading, LOADINGS)
    _check_choice("failure.tada_labels", labels, TADA_LABELS)
    a, b = _crack_geometry(crack_length_m, strip_width_m)
    k_ic = require_range("ice.fracture_toughness_pa_sqrt_m", toughness_pa_sqrt_m, low=0.0, unit="Pa·√m")
    size = require_range("size_m", size_m, low=0.0, high=math.inf, high_inclusive=False, unit="m")
    # the scalar forms of size_effect_strength_pa and tada_geometry_factor (called at every contact):
    # the inputs are checked above, a/b ∈ (0, 1) by _crack_geometry
    size = min(max(size, SIZE_EFFECT_RANGE_M[0]), SIZE_EFFECT_RANGE_M[1])
    strength = float(_size_effect_strength_mpa(size, law, bz2_mode) * MPA_TO_PA)
    factor = float(_tada_factor(a / b, loading, labels))
    if stress_mode == "thesis":
        k_i = strength * math.sqrt(math.pi * a) * factor
        return CrackCheck(fails=k_i >= k_ic, driving=k_i, resistance=k_ic, quantity="K_I [Pa√m]")
    if horizontal_force_n is None or thickness_m is None:
        raise InputError(
            "failure.stress_mode",
            f"{stress_mode!r} needs horizontal_force_n and thickness_m",
            value=stress_mode,
            allowed="thesis (load-independent)",
        )
    f_h = require_range("horizontal_force_n", horizontal_force_n, low=0.0, low_inclusive=True, unit="N")
    h = require_range("thickness_m", thickness_m, low=0.0, unit="m")
    applied = f_h / (h * b)
    if stress_mode == "strength":
        return CrackCheck(fails=applied >= strength, driving=applied, resistance=strength, quantity="σ [Pa]")
    k_i = applied * math.sqrt(math.pi * a) * factor
    return CrackCheck(fails=k_i >= k_ic, driving=k_i, resistance=k_ic, quantity="K_I [Pa√m]")
