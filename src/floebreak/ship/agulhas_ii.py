"""The reference ship, PSRV S.A. Agulhas II: its numbers, written once (thesis §3, §6.1, Table 9;
physics-notes §6.1, §7.1). Values marked ASSUMED are not in the thesis (docs/model.md, "Parameters and their
sources"); the modules that model a part of the ship take their defaults from here."""

from __future__ import annotations

from typing import Final

from floebreak.constants import BOW_TIP_ANGLE_DEG
from floebreak.ship.ship import Ship

# --- bow (ship.hulls.agulhas_ii) ---------------------------------------------------------------------------
BEAM_M: Final = 21.7  # thesis §3 / physics-notes §6.1
HALF_ENTRANCE_DEG: Final = BOW_TIP_ANGLE_DEG / 2.0  # 64.54°/2 = 32.27°, thesis Alg. 7 (§6.1)
THESIS_STEM_ANGLE_DEG: Final = 63.0  # ψ_AGU from the vertical, thesis ("from design drawings")

# --- underwater hull (propeller.transport.HullUnderwater) -------------------------------------------------
DRAUGHT_M: Final = 7.65  # T, depth of the flat bottom (thesis §3)
LENGTH_M: Final = 121.8  # L_pp (physics-notes §6.1)
BLOCK_COEFFICIENT: Final = 0.65  # C_B, ASSUMED: a full-bodied twin-screw polar vessel
BILGE_RADIUS_M: Final = 2.5  # ASSUMED
BOW_LENGTH_M: Final = 34.4  # stem-to-shoulder length L_b of the parametric bow
PROPELLER_PLANE_AFT_OF_STEM_M: Final = 115.0  # ASSUMED from L_pp
RUN_LENGTH_M: Final = 15.0  # ASSUMED: the stern run over which the hull rises above the discs

# --- propellers (propeller.spec.PropellerSpec, propeller.transport) ---------------------------------------
PROPELLER_COUNT: Final = 2  # two controllable-pitch propellers, thesis §6.1
PROPELLER_DIAMETER_M: Final = 4.3  # thesis Table 9: r = 2.15 m
PROPELLER_MAX_PITCH_M: Final = 5.15  # P_0.7 at 100 % pitch, thesis Table 9
PROPELLER_PITCH_PERCENT: Final = 95.8551  # mean pitch of the 18/12/2019 20:20 slot (thesis §6.1.2)
PROPELLER_RPM: Final = 140.0  # thesis §6.1.2
PROPELLER_BLADES: Final = 4  # ASSUMED (notes §7.1)
SHAFT_DEPTH_M: Final = (
    5.25  # ASSUMED: disc bottom DISC_BOTTOM_ABOVE_BASE_M above the base line, T − R − 0.25 m
)
DISC_BOTTOM_ABOVE_BASE_M: Final = 0.25  # ASSUMED
SHAFT_SPREAD_M: Final = 5.5  # ASSUMED lateral offset of the two shaft lines
TIP_CLEARANCE_M: Final = 0.86  # ASSUMED 0.2 D: vertical gap between the hull and a disc's top

# --- drive and shaft line (shaft.line.AGULHAS_II) ---------------------------------------------------------
RATED_POWER_W: Final = 4.5e6  # ≈ 2 × 4.5 MW motors: physics-notes §6.1 [recalled, medium]
MOTOR_INERTIA_KG_M2: Final = 20000.0  # ASSUMED: rotor of a ≈ 4.5 MW, 140 rpm direct-drive motor
THRUST_BEARING_INERTIA_KG_M2: Final = 1500.0  # ASSUMED: thrust collar, couplings and half of both shafts
PROPELLER_INERTIA_KG_M2: Final = 7500.0  # ASSUMED: dry CP propeller, D = 4.3 m (thesis), Z = 4 (notes §7.1)
INTERMEDIATE_SHAFT_M: Final = (0.45, 15.0)  # ASSUMED solid steel (diameter, length)
PROPELLER_SHAFT_M: Final = (0.55, 12.0)  # ASSUMED solid steel (diameter, length)

AGULHAS_II: Final = Ship(
    name="agulhas_ii",
    hull="agulhas_ii",
    shaft_line="agulhas_ii",
    propeller_count=PROPELLER_COUNT,
    propeller_diameter_m=PROPELLER_DIAMETER_M,
    shaft_depth_m=SHAFT_DEPTH_M,
    tip_clearance_m=TIP_CLEARANCE_M,
    rpm=PROPELLER_RPM,
    rated_power_w=RATED_POWER_W,
)
