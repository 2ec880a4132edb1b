"""Cusps that flow under the hull: each cusp followed as a rigid body from the bow to the propeller plane.

Ship frame of `floebreak.propeller.hull_surface` (x aft of the stem, y to port, z depth positive down). A
cusp is a flat square plate of its area A (side a = √A) and thickness h, lying flat (buoyancy presses it
against the hull), turned by a yaw ψ; its state is the centre of its top face (x, y, z_top) and its velocity.
Forces (docs/explanation/cusp-flow.md derives each and gives every parameter's source):

- net buoyancy (ρ_w − ρ_i) g A h upwards;
- on the hull (top face within `CONTACT_TOLERANCE_M` of z_hull): the hull's reaction cancels the buoyancy's
  normal part N = (ρ_w − ρ_i) g A h n_z, and Coulomb friction μ N opposes the sliding velocity, or holds the
  cusp (sticks) where its impulse over a step can stop the sliding;
- quadratic drag ½ ρ_w C_D A_i |u − v| (u_i − v_i) per axis, with the projected areas A_x = l_y h,
  A_y = l_x h, A_z = A (l_x = l_y = a (|cos ψ| + |sin ψ|), the plate's extents);
- added mass on the vertical axis, that of the disc of equal area broadside (8/3) ρ_w r³, r = a/√π.

The flow u: the hull's mean wake V (1 − w) aft, plus each propeller's actuator-disc inflow: axial
u_x = u_a (1 + ξ/√(ξ² + R²)) inside the disc's cylinder (ξ = x − x_p), and the radial inflow continuity
gives, u_r = −(r/2) ∂u_x/∂ξ inside, −(R²/2r) ∂u_x/∂ξ outside, with ∂u_x/∂ξ = u_a R²/(ξ² + R²)^{3/2}.

Integration: semi-implicit Euler (the drag, linear in the velocity, implicit, so any step is stable), then
friction as an impulse μ N Δt against the tangential velocity, clamped at sticking (exact Coulomb friction,
no regularisation), then the top face is kept below the hull and the velocity into it removed. A cusp ends
when its aft edge reaches the propeller plane (then its cross-section decides the disc: nearest axis
wins), when its centre leaves the beam ("bilge": beside the hull it rises to the surface), when it reaches the
surface ("surfaced"), or when friction holds it at rest under the hull ("stalled": at rest before and after
a step, a fixed point of the step, so it stays there).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Final

import numpy as np

from floebreak import constants as c
from floebreak.errors import InputError
from floebreak.propeller.hull_surface import HullSurface

CONTACT_TOLERANCE_M: Final = 1e-3
REST_M_S: Final = 1e-9  # below this speed a cusp is at rest (sticking leaves only rounding)
STEP_TRAVEL_M: Final = 0.25  # a tenth of the bilge radius, the hull's tightest curve
MAX_STEP_S: Final = 10.0
DISC_ADDED_MASS: Final = 8.0 / 3.0  # m_a = (8/3) ρ r³, a disc broadside (Newman 1977, Table 4.2)

# why a followed cusp ends (`FlowResult.outcome`)
OUTCOMES: Final = ("propeller", "bilge", "surfaced", "missed", "stalled")
REACHED, BILGE, SURFACED, MISSED, STALLED = range(5)
RUNNING: Final = -1


@dataclass(frozen=True)
class Discs:
    """The propeller discs in the ship frame: plane x_p [m], lateral offsets y_k, shaft depths z_k and
    radii R_k [m], and the axial velocity u_a,k each induces at its disc [m/s]."""

    plane_m: float
    offset_y_m: np.ndarray
    shaft_depth_m: np.ndarray
    radius_m: np.ndarray
    induced_m_s: np.ndarray


@dataclass(frozen=True)
class CuspBodies:
    """Per cusp: area A [m²], thickness h [m], yaw ψ [rad], drag coefficient C_D, friction coefficient μ."""

    area_m2: np.ndarray
    thickness_m: np.ndarray
    yaw_rad: np.ndarray
    drag_coefficient: np.ndarray
    friction_coefficient: np.ndarray

    @property
    def extent_m(self) -> np.ndarray:
        """l = a (|cos ψ| + |sin ψ|): the turned square's extent along x and along y."""
        return np.sqrt(self.area_m2) * (np.abs(np.cos(self.yaw_rad)) + np.abs(np.sin(self.yaw_rad)))

    def masses_kg(self) -> np.ndarray:
        """(n, 3): the ice's mass on x and y, plus the broadside disc's added mass on z."""
        m = c.ICE_DENSITY_KG_M3 * self.area_m2 * self.thickness_m
        r = np.sqrt(self.area_m2 / math.pi)
        added = DISC_ADDED_MASS * c.SEAWATER_DENSITY_KG_M3 * r**3
        return np.stack([m, m, m + added], axis=-1)

    def drag_areas_m2(self) -> np.ndarray:
        """(n, 3): the projected areas A_x = l h, A_y = l h, A_z = A."""
        side = self.extent_m * self.thickness_m
        return np.stack([side, side, self.area_m2], axis=-1)

    def net_buoyancy_n(self) -> np.ndarray:
        """(ρ_w − ρ_i) g A h [N], upwards."""
        drho = c.SEAWATER_DENSITY_KG_M3 - c.ICE_DENSITY_KG_M3
        return drho * c.GRAVITY_M_S2 * self.area_m2 * self.thickness_m


@dataclass(frozen=True)
class FlowField:
    """The flow the cusps meet: the hull's mean wake V (1 − w) [m/s] and the discs' inflow."""

    wake_speed_m_s: float
    discs: Discs | None = None

    def velocity(self, pos: np.ndarray) -> np.ndarray:
        """(n, 3) flow velocity at the points `pos` (module docstring)."""
        u = np.zeros_like(pos)
        u[:, 0] = self.wake_speed_m_s
        if self.discs is None:
            return u
        d = self.discs
        xi = pos[:, 0] - d.plane_m
        for y_k, z_k, r_k, ua in zip(d.offset_y_m, d.shaft_depth_m, d.radius_m, d.induced_m_s, strict=True):
            dy, dz = pos[:, 1] - y_k, pos[:, 2] - z_k
            r = np.hypot(dy, dz)
            inside = r <= r_k
            u[:, 0] += np.where(inside, ua * (1.0 + xi / np.sqrt(xi * xi + r_k * r_k)), 0.0)
            gradient = ua * r_k * r_k / (xi * xi + r_k * r_k) ** 1.5
            with np.errstate(divide="ignore", invalid="ignore"):
                u_r = -np.where(inside, 0.5 * r, 0.5 * r_k * r_k / r) * gradient
                unit_y, unit_z = np.where(r > 0, dy / r, 0.0), np.where(r > 0, dz / r, 0.0)
            u[:, 1] += u_r * unit_y
            u[:, 2] += u_r * unit_z
        return u


def _forces(bodies, masses, areas, buoyancy, hull, field, pos, vel):
    """The explicit force F0, the implicit drag c_d and the hull's normal force N of one step, with the
    contact mask and normals."""
    f0 = np.zeros_like(pos)
    f0[:, 2] = -buoyancy
    z_hull = hull.depth_m(pos[:, 0], pos[:, 1])
    normal = hull.normal(pos[:, 0], pos[:, 1])
    contact = np.isfinite(z_hull) & (pos[:, 2] - z_hull <= CONTACT_TOLERANCE_M)
    n_force = np.where(contact, buoyancy * normal[:, 2], 0.0)
    f0 += n_force[:, None] * normal  # the hull's reaction: the buoyancy's normal part
    u = field.velocity(pos)
    rel = np.linalg.norm(u - vel, axis=1)
    c_d = 0.5 * c.SEAWATER_DENSITY_KG_M3 * bodies.drag_coefficient[:, None] * areas * rel[:, None]
    return f0, c_d, n_force, u, contact, normal


def _friction(vel, normal, effective_mass, impulse_n_s):
    """Coulomb friction as an impulse `impulse_n_s` = μ N Δt against the tangential velocity, with the
    per-axis effective masses m_i + Δt c_d,i; where it would reverse the sliding, the cusp sticks (tangential
    velocity zero). Returns the new velocity."""
    v_n = np.sum(vel * normal, axis=1, keepdims=True) * normal
    v_t = vel - v_n
    speed = np.linalg.norm(v_t, axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        t_hat = np.where(speed[:, None] > 0.0, v_t / speed[:, None], 0.0)
    inverse_mass = np.sum(t_hat * t_hat / effective_mass, axis=1)  # 1/M_t along the sliding direction
    stop = impulse_n_s * inverse_mass
    sliding = vel - stop[:, None] * t_hat
    return np.where((speed <= stop)[:, None], v_n, sliding)


def step(bodies: CuspBodies, hull: HullSurface, field: FlowField, pos, vel, dt: float):
    """One semi-implicit step of every cusp (module docstring): new (pos, vel, contact)."""
    derived = (bodies.masses_kg(), bodies.drag_areas_m2(), bodies.net_buoyancy_n())
    return _step(bodies, derived, hull, field, pos, vel, dt)[:3]


def _step(bodies: CuspBodies, derived, hull: HullSurface, field: FlowField, pos, vel, dt: float):
    """`step` with the bodies' (masses, drag areas, net buoyancy) given, also returning the hull's normal
    under the new positions."""
    masses, areas, buoyancy = derived
    dt = np.asarray(dt, dtype=float)
    dt_column = dt[..., None] if dt.ndim else dt  # one step for all cusps, or each its own
    f0, c_d, n_force, u, contact, normal = _forces(bodies, masses, areas, buoyancy, hull, field, pos, vel)
    effective_mass = masses + dt_column * c_d
    vel = (masses * vel + dt_column * (f0 + c_d * u)) / effective_mass
    vel = _friction(vel, normal, effective_mass, dt * bodies.friction_coefficient * n_force)
    into = np.minimum(np.sum(vel * normal, axis=1), 0.0)
    vel = vel - np.where(contact, into, 0.0)[:, None] * normal
    pos = pos + dt_column * vel
    z_hull = hull.depth_m(pos[:, 0], pos[:, 1])
    above = np.isfinite(z_hull) & (pos[:, 2] < z_hull)
    pos[:, 2] = np.where(above, z_hull, pos[:, 2])
    normal = hull.normal(pos[:, 0], pos[:, 1])
    into = np.minimum(np.sum(vel * normal, axis=1), 0.0)
    vel = vel - np.where(above, into, 0.0)[:, None] * normal
    return pos, vel, contact | above, normal


@dataclass(frozen=True)
class FlowResult:
    """Per cusp: outcome (index into `OUTCOMES`), time from the start [s], and the position (x, y, z_top)
    and velocity where it ended."""

    outcome: np.ndarray
    time_s: np.ndarray
    position_m: np.ndarray
    velocity_m_s: np.ndarray


def follow(
    bodies: CuspBodies,
    hull: HullSurface,
    field: FlowField,
    start_m: np.ndarray,
    velocity_m_s: np.ndarray,
    *,
    time_step_s: float,
    max_time_s: float,
    step_travel_m: float = STEP_TRAVEL_M,
) -> FlowResult:
    """Follow every cusp from `start_m` (n, 3) with `velocity_m_s` (n, 3) until it ends (module docstring);
    cusps still running at `max_time_s` count as stalled.

    The cusps do not interact, so each keeps its own clock and step: the step in which it moves
    `step_travel_m`, at least `time_step_s` and at most `MAX_STEP_S`; a step that carries a cusp more than
    twice that far is redone at a quarter of its length. Slow cusps so take as many steps per metre as fast
    ones."""
    if not time_step_s > 0.0:
        raise InputError("transport.time_step_s", "must be > 0", value=time_step_s, allowed="> 0 s")
    n = start_m.shape[0]
    outcome = np.full(n, RUNNING, dtype=np.int8)
    time = np.zeros(n)
    pos_out, vel_out = np.array(start_m, dtype=float), np.array(velocity_m_s, dtype=float)
    active = np.arange(n)
    pos, vel, clock, longest = pos_out.copy(), vel_out.copy(), np.zeros(n), np.full(n, MAX_STEP_S)
    plane = field.discs.plane_m if field.discs is not None else hull.propeller_plane_m
    sub = None
    while active.size:
        if sub is None:  # the running cusps' bodies, derived once per change of the running set
            sub = _subset(bodies, active)
            derived = (sub.masses_kg(), sub.drag_areas_m2(), sub.net_buoyancy_n())
            half = 0.5 * sub.extent_m
        speed = np.linalg.norm(vel, axis=1)
        with np.errstate(divide="ignore"):
            dt = np.clip(step_travel_m / speed, time_step_s, np.maximum(longest, time_step_s))
        new_pos, new_vel, contact, _ = _step(sub, derived, hull, field, pos, vel, dt)
        kept = (np.linalg.norm(new_pos - pos, axis=1) <= 2.0 * step_travel_m) | (dt <= time_step_s)
        longest = np.where(kept, np.minimum(2.0 * longest, MAX_STEP_S), 0.25 * dt)
        resting = speed <= REST_M_S
        pos, vel = np.where(kept[:, None], new_pos, pos), np.where(kept[:, None], new_vel, vel)
        clock = np.where(kept, clock + dt, clock)
        ended = np.full(active.size, RUNNING, dtype=np.int8)
        ended[contact & resting & (np.linalg.norm(vel, axis=1) <= REST_M_S)] = STALLED  # a fixed point
        ended[clock >= max_time_s] = STALLED
        ended[pos[:, 2] <= 0.0] = SURFACED
        ended[np.abs(pos[:, 1]) >= 0.5 * hull.beam_m] = BILGE  # its centre beside the hull
        beyond = pos[:, 0] + half - plane
        ended[beyond >= 0.0] = REACHED  # decided at the plane (`disc_contact`)
        ended[~kept] = RUNNING
        done = ended != RUNNING
        idx = active[done]
        # the plane crossed within the step: its time interpolated back from the step's end
        back = np.where(ended == REACHED, np.clip(beyond / np.maximum(vel[:, 0], 1e-12), 0.0, dt), 0.0)
        outcome[idx], time[idx] = ended[done], (clock - back)[done]
        pos_out[idx], vel_out[idx] = pos[done], vel[done]
        if done.any():
            keep = ~done
            active, pos, vel, clock, longest, sub = (
                active[keep],
                pos[keep],
                vel[keep],
                clock[keep],
                longest[keep],
                None,
            )
    return FlowResult(outcome, time, pos_out, vel_out)


def _subset(bodies: CuspBodies, idx: np.ndarray) -> CuspBodies:
    return CuspBodies(*(getattr(bodies, f)[idx] for f in CuspBodies.__dataclass_fields__))
