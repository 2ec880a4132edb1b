"""Physical constants and model defaults, SI units throughout.

Every value names its unit in its identifier and its source in the comment beside it
(physics-notes §0 table; thesis section or equation). Nothing here is mutable state: the
values are the defaults that configuration objects copy.
"""

from __future__ import annotations

from typing import Final

# --- Ice material (physics-notes §0) -------------------------------------------------------------
YOUNGS_MODULUS_PA: Final = 2.0e9  # thesis §4.1.1 (Erceg et al.); literature range 2–6 GPa
POISSON_RATIO: Final = 0.3  # thesis §4.1.1
FLEXURAL_STRENGTH_PA: Final = 0.5e6  # not stated in the thesis; physics-notes §0 (range 0.3–0.7 MPa)
CRUSHING_STRENGTH_PA: Final = 1.28e6  # thesis Alg. 3 (1280 kPa); literature range 1–3 MPa
CONTACT_COEFFICIENT: Final = 1.0  # k_c, thesis Alg. 3
FRICTION_COEFFICIENT: Final = 0.15  # μ ice–hull, thesis Alg. 3
FRACTURE_TOUGHNESS_PA_SQRT_M: Final = 145.7e3  # K_Ic reference value, thesis Table 4 (Fischer)
FRACTURE_TOUGHNESS_ALTERNATIVES_PA_SQRT_M: Final = (120.0e3, 145.7e3, 230.0e3)  # thesis Table 4
TOTAL_POROSITY_PPT: Final = 50.0  # ν_t in Eq. 13 (thesis §4.2.1)

# --- Densities and gravity (physics-notes §0) ----------------------------------------------------
SEAWATER_DENSITY_KG_M3: Final = 1025.0
ICE_DENSITY_KG_M3: Final = 917.0  # thesis §6.3; the FEM part of the thesis uses 900
ICE_DENSITY_FEM_KG_M3: Final = 900.0  # thesis Table 9
GRAVITY_M_S2: Final = 9.81

# Winkler foundation modulus k = ρ_w g [N/m³] = 10 055 N/m³ (thesis symbol list says MN/m³: 0.010055 MN/m³)
FOUNDATION_MODULUS_N_M3: Final = SEAWATER_DENSITY_KG_M3 * GRAVITY_M_S2

# --- Thesis-literal characteristic length (errata 7, 8) ------------------------------------------
# ℓ = 13.5 h^(3/4) (Lu et al.), used by the thesis for the unbreakable-area threshold (Alg. 2, Eq. 5).
LU_CHARACTERISTIC_LENGTH_COEFFICIENT: Final = 13.5  # [m^(1/4)], i.e. ℓ[m] = 13.5 · h[m]^(3/4)

# --- Floe fields (thesis §2.1, Table 1) ----------------------------------------------------------
OBSERVATION_DIAMETER_CLASSES_M: Final = (2.5, 7.5, 15.0, 60.0, 300.0)  # thesis §2.1 d_ice
FLOE_AREA_FACTOR: Final = 0.25  # A = factor · π d²; thesis prints 0.5 (erratum 1)
CIRCLE_POLYGON_VERTICES: Final = 64  # circles become regular 64-gons inscribed in the circle

# The field of a generated scenario that gives no size: the thesis' §5.3 field, whose size the thesis does not
# state — 100 m wide (above B + 2 d_max = 51.7 m, so the bow's path holds a fair sample of every floe class)
# and 385 m long (inferred for that width from its affected area; `studies.field_size`, docs/validation.md).
# A narrower field puts every floe of the largest class in the bow's path and inflates the flipped ice (the
# 400 m × 50 m used until 2026-12-02 did; docs/validation.md, "The width"; `api.set_up_warnings`).
REFERENCE_FIELD_LENGTH_M: Final = 385.0
REFERENCE_FIELD_WIDTH_M: Final = 100.0

# --- Randomised thickness (thesis §5.3.3, erratum 6) ---------------------------------------------
THICKNESS_SUMMANDS_DEFAULT: Final = 12  # p_h: Bates(12), std = (h_max − h_min)/12
THICKNESS_SUMMANDS_THESIS: Final = 1180  # p_h implied by the thesis' σ = 0.0042 m over [0.75, 1.25] m

# --- Ship–ice interaction (thesis §3.2, §4.1) ----------------------------------------------------
DIST_BOW_MAX_M: Final = 1.0  # candidate search distance, thesis §3.2
WEDGE_ANGLE_DEG: Final = 5.0  # φ, thesis §4.1.2
NEXT_CRACK_ANGLE_DEG: Final = 30.0  # α_nextcrack, thesis §4.2.3
BOW_TIP_ANGLE_DEG: Final = 64.54  # α (full waterline entrance angle), thesis Alg. 7
PSI_MIN_DEG: Final = 10.0  # near-vertical panel guard, physics-notes §2.2

# --- Propeller loads: time base (thesis §6.1, §6.3) -----------------------------------------------
SHIP_SPEED_IN_ICE_M_S: Final = 3.0  # ship surge speed in ice, thesis §6.3 (Eq. 28: v_cusp = v_ship = 3 m/s)
# the ranges a scenario allows, shared by the propeller's own checks: 20 m/s ≈ 39 kn is above any ice-going
# ship's top speed in open water; ice-going ships have 1–4 propellers (Agulhas II 2, thesis §6.1), 8 leaves
# room
SHIP_SPEED_RANGE_M_S: Final = (0.0, 20.0)
PROPELLER_COUNT_RANGE: Final = (1, 8)
FRACTION_REACHING_PROPELLER: Final = 1.0  # every cusp reaches a propeller, as the thesis assumes (§6.2)
