"""Shared construction for the failure-mode tests (thesis ch. 4; physics-notes §0, §1, §2).

FailureInput/FailureContext objects are built from real geometry exactly as `floebreak.engine.loop` does
(contact → dominant zone → classification → bow region). The expectations of the tests come from the
independent helpers below (physics-notes values), never from the code under test.

Geometry used most: a rectangular floe pressed against panel 0 of the Agulhas II bow, the straight 10 m
panel of the parallel midbody at y = +10.85 m (outward normal +y, ψ = 20° from the vertical). The upper
waterline is straight there, so the crushed area is the rectangle's overlap, A_h = W p (W the width along
the panel, p the penetration), as long as p < h_bow tan ψ = 0.364 m (the lower waterline).
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import pytest
import shapely

from floebreak.failure import FailureContext, FailureInput, bow_region
from floebreak.mechanics.classify import ClassificationParams, classify
from floebreak.mechanics.contact import BowContactGeometry, ContactParams, evaluate_contact
from floebreak.ship.hulls import agulhas_ii

# --- physics-notes §0 (independent constants, SI) ---------------------------------------------------------
E_PA = 2.0e9
NU = 0.3
K_N_M3 = 1025.0 * 9.81
SIGMA_F_PA = 0.5e6
SIGMA_C_PA = 1.28e6
MU = 0.15
K_IC_PA_SQRT_M = 145.7e3

# --- physics-notes §1.3 table: ρ → (S, ξ_σ, ξ_M) ------------------------------------------------------------
NEVEL_TABLE = {
    0.0: (1.0000, 0.0, 1.552),
    0.001: (0.9867, 0.114, 1.552),
    0.005: (0.9617, 0.198, 1.555),
    0.01: (0.9398, 0.253, 1.558),
    0.02: (0.9058, 0.325, 1.565),
    0.03: (0.8781, 0.377, 1.571),
    0.05: (0.8324, 0.457, 1.585),
    0.075: (0.7857, 0.536, 1.601),
    0.10: (0.7462, 0.601, 1.619),
    0.15: (0.6812, 0.711, 1.654),
    0.20: (0.6287, 0.806, 1.690),
    0.30: (0.5472, 0.970, 1.764),
    0.50: (0.4373, 1.252, 1.922),
    1.00: (0.2937, 1.857, 2.350),
}

# --- panel 0 of the Agulhas II bow (parallel midbody, port side) --------------------------------------------
PANEL0_Y_M = 10.85
PANEL0_X_CENTRE_M = -39.36583132484942  # middle of the 10 m straight panel
PANEL0_PSI_RAD = math.radians(20.0)


def ell_m(thickness_m: float) -> float:
    """ℓ = (D/k)^(1/4), D = E h³/(12(1 − ν²)) (thesis Eq. 1, physics-notes §0: 11.62 m at h = 1 m)."""
    d = E_PA * thickness_m**3 / (12.0 * (1.0 - NU**2))
    return (d / K_N_M3) ** 0.25


def nevel_capacity_n(thickness_m: float, opening_rad: float, stress_factor: float) -> float:
    """P_f = σ_f Θ h² / (6 S) (physics-notes Eq. 1.4)."""
    return SIGMA_F_PA * opening_rad * thickness_m**2 / (6.0 * stress_factor)


def capacity_bracket_n(thickness_m: float, opening_rad: float, rho: float) -> tuple[float, float]:
    """(low, high) bounds of P_f from the table rows around ρ (S decreases monotonically with ρ)."""
    rows = sorted(NEVEL_TABLE)
    below = max(r for r in rows if r <= rho)
    above = min(r for r in rows if r >= rho)
    return (
        nevel_capacity_n(thickness_m, opening_rad, NEVEL_TABLE[below][0]),
        nevel_capacity_n(thickness_m, opening_rad, NEVEL_TABLE[above][0]),
    )


def panel0_forces_per_area() -> tuple[float, float]:
    """(F_v/A_h, F_h/A_h) on panel 0: A_c = A_h / sin ψ, F_c = σ_c A_c, F_v = F_c (sin ψ − μ cos ψ),
    F_h = F_c (cos ψ + μ sin ψ) (thesis Eqs. 6–10, physics-notes §2.3, k_c = 1)."""
    s, co = math.sin(PANEL0_PSI_RAD), math.cos(PANEL0_PSI_RAD)
    return SIGMA_C_PA * (s - MU * co) / s, SIGMA_C_PA * (co + MU * s) / s


def midbody_box(width_m: float, length_m: float, penetration_m: float, x_centre_m: float = PANEL0_X_CENTRE_M):
    """A rectangle W (along the panel, x) × L (along the outward normal, +y) pressed p into panel 0."""
    y0 = PANEL0_Y_M - penetration_m
    return shapely.box(x_centre_m - width_m / 2.0, y0, x_centre_m + width_m / 2.0, y0 + length_m)


@pytest.fixture(scope="session")
def bow():
    return agulhas_ii(ice_thickness_m=1.0)


@pytest.fixture(scope="session")
def context(bow):
    return FailureContext(bow=bow, bow_geometry=BowContactGeometry.from_bow(bow))


@pytest.fixture(scope="session")
def make_input(bow, context):
    """Factory: FailureInput for a bow-frame floe polygon, built as `simulation.simulate` builds it."""

    def build(polygon, thickness_m: float = 1.0, crack_count: int = 0, shoulder_region_start: float = 0.5):
        contact = evaluate_contact(polygon, thickness_m, context.bow_geometry, ContactParams())
        assert contact.in_contact, "test geometry must touch the bow"
        zone = contact.dominant
        classification = classify(polygon, thickness_m, zone.centre_normal, ClassificationParams())
        region = bow_region(float(zone.centre_xy_m[0]), float(bow.length_bow_m), shoulder_region_start)
        return FailureInput(polygon, thickness_m, crack_count, classification, contact, zone, region)

    return build


@pytest.fixture(scope="session")
def kit():
    """The independent helpers and constants above, for the test modules."""
    return SimpleNamespace(
        ell_m=ell_m,
        nevel_capacity_n=nevel_capacity_n,
        capacity_bracket_n=capacity_bracket_n,
        panel0_forces_per_area=panel0_forces_per_area,
        midbody_box=midbody_box,
        table=NEVEL_TABLE,
        panel0_y_m=PANEL0_Y_M,
        panel0_x_centre_m=PANEL0_X_CENTRE_M,
        sigma_f_pa=SIGMA_F_PA,
        k_ic_pa_sqrt_m=K_IC_PA_SQRT_M,
    )
