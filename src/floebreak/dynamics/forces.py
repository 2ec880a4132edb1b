"""Water forces on the pieces, applied as external forces each step (not by the engine): pure functions.

Quadratic drag in translation, F = −k |u| u with k = ½ρ_w (C_d T W(û) + C_s A) (form drag on the submerged
edge, T = h ρ_i/ρ_w, W the width projected across the velocity; skin drag on the underside), and in yaw,
M = −c |ω| ω with c = ½ρ_w (C_d T K± + C_s J₃) (K± = ∫ max(±s, 0)³ dl along the edge, J₃ = ∫ r³ dA).
The force over a step Δt is the one that gives the exact solution of m_eff du/dt = −k |u| u over the step
with k frozen: u' = u / (1 + k |u| Δt / m_eff), so F = m_eff (u' − u)/Δt. This never reverses the velocity,
whatever Δt (an explicit −k|u|u does for k|u|Δt > m_eff: small fast pieces), and equals −k|u|u as Δt → 0.
What does not change with a piece's motion (C_d T, C_s A, c±) is computed once, when it enters
(`DragConstants`); each step evaluates all pieces in one compiled pass (`water_loads_into`).
Sources of the coefficients: `IceMotionSettings` and docs/model.md ("Ice motion").
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
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


@numba.njit(cache=True, nogil=True)
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
    velocity = np.asarray(velocity_xy_m_s, dtype=np.float64)
    state = np.zeros((len(table.starts), 6))
    state[:, 2], state[:, 3:5], state[:, 5] = angle_rad, velocity, angular_velocity_rad_s
    n = len(table.starts)
    loads = np.zeros((n, 3))
    at, zeros = np.arange(n, dtype=np.int64), np.zeros(n)
    last = np.full(n, np.inf)
    water_loads_into(loads, at, table, state, zeros, zeros > 0, last, -1.0, dt_s, water_density_kg_m3)
    return loads[:, 0], loads[:, 1], loads[:, 2]


def water_loads_into(
    out: np.ndarray,
    at: np.ndarray,
    table: DragTable,
    values: np.ndarray,
    radius_m: np.ndarray,
    held: np.ndarray,
    last_speed_m_s: np.ndarray,
    rest_speed_m_s: float,
    dt_s: float,
    water_density_kg_m3: float,
) -> tuple[np.ndarray, int, int]:
    """The water's (F_x, F_y, M_z) on each piece (row i of `table`) over a step, from its state (x, y,
    angle, vx, vy, ω) in row `at[i]` of `values`, written to row `at[i]` of `out` (the engine's bodies in
    Chipmunk's order: nothing gathered or scattered per step; the other rows of `out` are not touched);
    returns each piece's status (0 at rest, 1 to be set at rest, 2 moving) and the numbers set at rest
    and moving. A piece is set at rest when its speed u = max(|v|, |ω|·its largest radius) is below
    `rest_speed_m_s` and not above its value at the last step (`last_speed_m_s`, updated here): it creeps
    under drag. A piece pushed from rest (by the hull, `held`, or through others) gains speed slowly if
    heavy and is not stopped. One compiled pass over the rows (called every engine step: numpy's per-call
    overhead cost more than the arithmetic); arrays C-contiguous, float64 (`at` int64, `held` bool)."""
    return _water_kernel(
        table.ring_xy_m,
        table.starts,
        table.form_m,
        table.skin_m2,
        table.yaw_kg_m2,
        table.mass_kg,
        table.moment_kg_m2,
        values,
        at,
        radius_m,
        held,
        last_speed_m_s,
        float(rest_speed_m_s),
        float(dt_s),
        float(water_density_kg_m3),
        out,
    )


@numba.njit(cache=True, nogil=True)
def _water_kernel(
    ring, starts, form, skin, yaw, mass, moment, values, at, radius, held, last, rest, dt, rho, out
):
    n = len(starts)
    status = np.zeros(n, dtype=np.int8)
    stopped = moving = 0
    for i in range(n):
        b = at[i]
        out[b, 0] = out[b, 1] = out[b, 2] = 0.0
        vx, vy, w = values[b, 3], values[b, 4], values[b, 5]
        speed = math.hypot(vx, vy)
        slow, last[i] = last[i], max(speed, abs(w) * radius[i])
        if vx == 0.0 and vy == 0.0 and w == 0.0:
            continue
        if last[i] < rest and last[i] <= slow and not held[i]:
            status[i] = 1
            stopped += 1
            continue
        status[i] = 2
        moving += 1
        if speed > 0.0:  # at rest: û = 0, and the drag is 0
            ux, uy = vx / speed, vy / speed
            c, s = math.cos(values[b, 2]), math.sin(values[b, 2])
            dx, dy = c * ux + s * uy, -s * ux + c * uy  # û in the body frame
            end = starts[i + 1] if i + 1 < n else len(ring)
            low, high = np.inf, -np.inf
            for j in range(starts[i], end):
                across = ring[j, 1] * dx - ring[j, 0] * dy
                low, high = min(low, across), max(high, across)
            k = 0.5 * rho * (form[i] * (high - low) + skin[i])
            magnitude = step_drag(speed, k, mass[i], dt)
            out[b, 0], out[b, 1] = -magnitude * ux, -magnitude * uy
        if w != 0.0:
            c_yaw = yaw[i, 0] if w > 0.0 else yaw[i, 1]
            out[b, 2] = -math.copysign(step_drag(abs(w), c_yaw, moment[i], dt), w)
    return status, stopped, moving


def compile_now() -> None:
    """Compile the water kernel (or load it from numba's cache) ahead of a run."""
    one = np.ones(1)
    table = DragTable(
        np.zeros((3, 2)), np.zeros(1, np.int64), np.zeros(3, np.int64), one, one, np.ones((1, 2)), one, one
    )
    at = np.zeros(1, np.int64)
    water_loads_into(np.zeros((1, 3)), at, table, np.ones((1, 6)), one, one < 0, one * 0, 1e-3, 0.01, 1025.0)
