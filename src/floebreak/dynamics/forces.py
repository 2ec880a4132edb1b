"""Water forces on the pieces, applied as external forces each step (not by the engine): pure functions.

Quadratic drag in translation, F = −k |u| u with k = ½ρ_w (C_d T W(û) + C_s A) (form drag on the submerged
edge, T = h ρ_i/ρ_w, W the width projected across the velocity; skin drag on the underside), and in yaw,
M = −c |ω| ω with c = ½ρ_w (C_d T K± + C_s J₃) (K± = ∫ max(±s, 0)³ dl along the edge, J₃ = ∫ r³ dA).
The force over a step Δt is the one that gives the exact solution of m_eff du/dt = −k |u| u over the step
with k frozen: u' = u / (1 + k |u| Δt / m_eff), so F = m_eff (u' − u)/Δt. This never reverses the velocity,
whatever Δt (an explicit −k|u|u does for k|u|Δt > m_eff: small fast pieces), and equals −k|u|u as Δt → 0.
What does not change with a piece's motion (C_d T, C_s A, c±) is computed once, when it enters
(`DragConstants`); each step evaluates all awake pieces at once (`water_forces_and_moments`).
Sources of the coefficients: `IceMotionSettings` and docs/model.md ("Ice motion").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from floebreak.dynamics.bodies import BodyGeometry
from floebreak.dynamics.settings import IceMotionSettings


@dataclass(frozen=True)
class DragConstants:
    """A piece's drag terms that do not depend on its motion: k = ½ρ_w (form_m · W + skin_m2)."""

    form_m: float  # C_d T
    skin_m2: float  # C_s A
    yaw_kg_m2: tuple[float, float]  # c for ω > 0 and for ω < 0 (the advancing edges differ)


def drag_constants(geometry: BodyGeometry, thickness_m: float, settings: IceMotionSettings) -> DragConstants:
    """The motion-independent drag terms of a piece of `geometry` and `thickness_m`."""
    draft = thickness_m * settings.draft_ratio
    rho = settings.water_density_kg_m3
    skin_yaw = settings.skin_drag_coefficient * geometry.yaw_skin_m5
    form_yaw = geometry.yaw_form_m3
    yaw = tuple(0.5 * rho * (settings.form_drag_coefficient * draft * form + skin_yaw) for form in form_yaw)
    return DragConstants(
        settings.form_drag_coefficient * draft, settings.skin_drag_coefficient * geometry.area_m2, yaw
    )


def step_drag(speed, factor, effective_mass, dt_s: float):
    """The drag's magnitude over one step, m_eff·(|u| − |u'|)/Δt with |u'| = |u|/(1 + k|u|Δt/m_eff)
    (scalars or arrays)."""
    decay = factor * speed * dt_s / effective_mass
    return effective_mass * speed * decay / ((1.0 + decay) * dt_s)


@dataclass(frozen=True)
class DragTable:
    """The drag data of a set of pieces, one row each (rings concatenated, body frame)."""

    ring_xy_m: np.ndarray  # (N, 2) all rings, one after the other
    starts: np.ndarray  # (n,) index of each piece's first vertex in ring_xy_m
    owner: np.ndarray  # (N,) the row of each vertex
    form_m: np.ndarray  # (n,)
    skin_m2: np.ndarray  # (n,)
    yaw_kg_m2: np.ndarray  # (n, 2)
    mass_kg: np.ndarray  # (n,) effective
    moment_kg_m2: np.ndarray  # (n,) effective


def drag_table(
    rings: list[np.ndarray], constants: list[DragConstants], mass_kg: list[float], moment_kg_m2: list[float]
) -> DragTable:
    """The `DragTable` of pieces given by their body-frame rings, drag constants and effective inertia."""
    sizes = np.array([len(r) for r in rings], dtype=np.int64)
    return DragTable(
        np.concatenate(rings),
        np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64),
        np.repeat(np.arange(len(rings)), sizes),
        np.array([c.form_m for c in constants]),
        np.array([c.skin_m2 for c in constants]),
        np.array([c.yaw_kg_m2 for c in constants]).reshape(-1, 2),
        np.array(mass_kg, dtype=float),
        np.array(moment_kg_m2, dtype=float),
    )


def water_forces_and_moments(
    table: DragTable,
    angle_rad: np.ndarray,
    velocity_xy_m_s: np.ndarray,
    angular_velocity_rad_s: np.ndarray,
    dt_s: float,
    water_density_kg_m3: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(F_x, F_y, M_z) of the water on each piece of `table` over a step [N, N, N·m], field frame, at the
    centroids; `velocity_xy_m_s` (n, 2). W(û) is the spread of the ring's vertices across û in the body
    frame (exact for any polygon: its shadow is one interval)."""
    vx, vy = velocity_xy_m_s[:, 0], velocity_xy_m_s[:, 1]
    speed = np.hypot(vx, vy)
    divisor = np.where(speed > 0.0, speed, 1.0)  # at rest: û = 0, and the drag is 0
    ux, uy = vx / divisor, vy / divisor
    cos_a, sin_a = np.cos(angle_rad), np.sin(angle_rad)
    dx, dy = cos_a * ux + sin_a * uy, -sin_a * ux + cos_a * uy  # û in the body frame
    across = table.ring_xy_m[:, 1] * dx[table.owner] - table.ring_xy_m[:, 0] * dy[table.owner]
    width = np.maximum.reduceat(across, table.starts) - np.minimum.reduceat(across, table.starts)
    k = 0.5 * water_density_kg_m3 * (table.form_m * width + table.skin_m2)
    magnitude = step_drag(speed, k, table.mass_kg, dt_s)
    omega = angular_velocity_rad_s
    c_yaw = np.where(omega > 0.0, table.yaw_kg_m2[:, 0], table.yaw_kg_m2[:, 1])
    moment = -np.copysign(step_drag(np.abs(omega), c_yaw, table.moment_kg_m2, dt_s), omega)
    return -magnitude * ux, -magnitude * uy, moment
