"""Water forces on a piece, applied as external forces each step (not by the physics engine): pure functions.

Quadratic drag in translation, F = −k |u| u with k = ½ρ_w (C_d T W(û) + C_s A) (form drag on the submerged
edge, T = h ρ_i/ρ_w, W the width projected across the velocity; skin drag on the underside), and in yaw,
M = −c |ω| ω with c = ½ρ_w (C_d T K± + C_s J₃) (K± = ∫ max(±s, 0)³ dl along the edge, J₃ = ∫ r³ dA).
The force over a step Δt is the one that gives the exact solution of m_eff du/dt = −k |u| u over the step
with k frozen: u' = u / (1 + k |u| Δt / m_eff), so F = m_eff (u' − u)/Δt. This never reverses the velocity,
whatever Δt (an explicit −k|u|u does for k|u|Δt > m_eff: small fast pieces), and equals −k|u|u as Δt → 0.
Sources of the coefficients: `IceMotionSettings` and docs/model.md ("Ice motion").
"""

from __future__ import annotations

import math

import numpy as np

from floebreak.dynamics.bodies import BodyGeometry, projected_width_m
from floebreak.dynamics.settings import IceMotionSettings


def translational_drag_factor(
    geometry: BodyGeometry, thickness_m: float, direction_body: np.ndarray, settings: IceMotionSettings
) -> float:
    """k [kg/m] of F = −k|u|u for motion along the unit `direction_body` (body frame)."""
    draft = thickness_m * settings.draft_ratio
    width = projected_width_m(geometry.ring_xy_m, direction_body)
    rho = settings.water_density_kg_m3
    return (
        0.5
        * rho
        * (settings.form_drag_coefficient * draft * width + settings.skin_drag_coefficient * geometry.area_m2)
    )


def yaw_drag_factor(
    geometry: BodyGeometry, thickness_m: float, positive: bool, settings: IceMotionSettings
) -> float:
    """c [kg·m²] of M = −c|ω|ω, for ω > 0 (`positive`) or ω < 0 (the advancing edges differ)."""
    draft = thickness_m * settings.draft_ratio
    form = geometry.yaw_form_m3[0 if positive else 1]
    rho = settings.water_density_kg_m3
    return (
        0.5
        * rho
        * (
            settings.form_drag_coefficient * draft * form
            + settings.skin_drag_coefficient * geometry.yaw_skin_m5
        )
    )


def step_drag(speed: float, factor: float, effective_mass: float, dt_s: float) -> float:
    """The drag's magnitude over one step, m_eff·(|u| − |u'|)/Δt with |u'| = |u|/(1 + k|u|Δt/m_eff)."""
    decay = factor * speed * dt_s / effective_mass
    return effective_mass * speed * decay / ((1.0 + decay) * dt_s)


def water_force_and_moment(
    geometry: BodyGeometry,
    thickness_m: float,
    angle_rad: float,
    velocity_xy_m_s: tuple[float, float],
    angular_velocity_rad_s: float,
    effective_mass_kg: float,
    effective_moment_kg_m2: float,
    dt_s: float,
    settings: IceMotionSettings,
) -> tuple[float, float, float]:
    """(F_x, F_y, M_z) of the water on a piece over a step [N, N, N·m], field frame, at its centroid."""
    vx, vy = velocity_xy_m_s
    fx = fy = 0.0
    speed = math.hypot(vx, vy)
    if speed > 0.0:
        cos_a, sin_a = math.cos(angle_rad), math.sin(angle_rad)
        ux, uy = vx / speed, vy / speed
        direction_body = np.array([cos_a * ux + sin_a * uy, -sin_a * ux + cos_a * uy])
        k = translational_drag_factor(geometry, thickness_m, direction_body, settings)
        magnitude = step_drag(speed, k, effective_mass_kg, dt_s)
        fx, fy = -magnitude * ux, -magnitude * uy
    moment = 0.0
    if angular_velocity_rad_s != 0.0:
        omega = angular_velocity_rad_s
        c_yaw = yaw_drag_factor(geometry, thickness_m, omega > 0.0, settings)
        moment = -math.copysign(step_drag(abs(omega), c_yaw, effective_moment_kg_m2, dt_s), omega)
    return fx, fy, moment
