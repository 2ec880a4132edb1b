"""Cusps that flow under the hull: each cusp followed as a rigid body from the bow to the propeller plane.

Ship frame of `floebreak.propeller.hull_surface` (x aft of the stem, y to port, z depth positive down). A
cusp is a flat square plate of its area A (side a = √A) and thickness h, lying flat (buoyancy presses it
against the hull), turned by a yaw ψ; its state is the centre of its top face (x, y, z_top) and its velocity.
Forces (docs/explanation/cusp-flow.md derives each and gives every parameter's source):

- net buoyancy (ρ_w − ρ_i) g A h upwards;
- on the hull (top face within `CONTACT_TOLERANCE_M` of z_hull): the hull's reaction cancels the buoyancy's
  normal part N = (ρ_w − ρ_i) g A h n_z, and Coulomb friction μ N opposes the sliding velocity (regularised
  below `FRICTION_SLIP_M_S`);
- quadratic drag ½ ρ_w C_D A_i |u − v| (u_i − v_i) per axis, with the projected areas A_x = l_y h,
  A_y = l_x h, A_z = A (l_x = l_y = a (|cos ψ| + |sin ψ|), the plate's extents);
- added mass on the vertical axis, that of the disc of equal area broadside (8/3) ρ_w r³, r = a/√π.

The flow u: the hull's mean wake V (1 − w) aft, plus each propeller's actuator-disc inflow: axial
u_x = u_a (1 + ξ/√(ξ² + R²)) inside the disc's cylinder (ξ = x − x_p), and the radial inflow continuity
gives, u_r = −(r/2) ∂u_x/∂ξ inside, −(R²/2r) ∂u_x/∂ξ outside, with ∂u_x/∂ξ = u_a R²/(ξ² + R²)^{3/2}.

Integration: semi-implicit Euler (the forces linear in the velocity — drag and friction — implicit, so any
step is stable), then the top face is kept below the hull and the velocity into it removed. A cusp ends
when its aft edge reaches the propeller plane (then its cross-section decides the disc: nearest axis
wins), when its centre leaves the beam ("bilge": beside the hull it rises to the surface), when it reaches the
surface ("surfaced"), or when friction holds it at rest under the hull ("stalled").
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
FRICTION_SLIP_M_S: Final = 0.01  # Coulomb friction regularised as μN v/√(v² + ε²) below ε
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
    """The explicit force F0 and the implicit damping (drag c_d, friction c_f) of one step, with the
    contact mask and normals."""
    f0 = np.zeros_like(pos)
    f0[:, 2] = -buoyancy
    z_hull = hull.depth_m(pos[:, 0], pos[:, 1])
    normal = hull.normal(pos[:, 0], pos[:, 1])
    contact = np.isfinite(z_hull) & (pos[:, 2] - z_hull <= CONTACT_TOLERANCE_M)
    n_force = np.where(contact, buoyancy * normal[:, 2], 0.0)
    f0 += n_force[:, None] * normal  # the hull's reaction: the buoyancy's normal part
    v_t = vel - np.sum(vel * normal, axis=1, keepdims=True) * normal
    slip = np.sqrt(np.sum(v_t * v_t, axis=1) + FRICTION_SLIP_M_S**2)
    c_f = bodies.friction_coefficient * n_force / slip
    u = field.velocity(pos)
    rel = np.linalg.norm(u - vel, axis=1)
    c_d = 0.5 * c.SEAWATER_DENSITY_KG_M3 * bodies.drag_coefficient[:, None] * areas * rel[:, None]
    return f0, c_d, c_f, u, contact, normal


def step(bodies: CuspBodies, hull: HullSurface, field: FlowField, pos, vel, dt: float):
    """One semi-implicit step of every cusp (module docstring): new (pos, vel, contact)."""
    derived = (bodies.masses_kg(), bodies.drag_areas_m2(), bodies.net_buoyancy_n())
    return _step(bodies, derived, hull, field, pos, vel, dt)[:3]


def _step(bodies: CuspBodies, derived, hull: HullSurface, field: FlowField, pos, vel, dt: float):
    """`step` with the bodies' (masses, drag areas, net buoyancy) given, also returning the hull's normal
    under the new positions."""
    masses, areas, buoyancy = derived
    f0, c_d, c_f, u, contact, normal = _forces(bodies, masses, areas, buoyancy, hull, field, pos, vel)
    vel = (masses * vel + dt * (f0 + c_d * u)) / (masses + dt * (c_d + c_f[:, None]))
    into = np.minimum(np.sum(vel * normal, axis=1), 0.0)
    vel = vel - np.where(contact, into, 0.0)[:, None] * normal
    pos = pos + dt * vel
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


def _held(bodies, field, pos, vel, contact, normal, areas, buoyancy) -> np.ndarray:
    """At rest on the flat part of the hull (`normal` under `pos`) where the flow's drag cannot overcome
    static friction."""
    u = field.velocity(pos)
    drag = 0.5 * c.SEAWATER_DENSITY_KG_M3 * bodies.drag_coefficient * areas[:, 0] * u[:, 0] ** 2
    flat = normal[:, 2] > 0.999
    resting = np.linalg.norm(vel, axis=1) < FRICTION_SLIP_M_S
    return contact & flat & resting & (drag <= bodies.friction_coefficient * buoyancy)


def follow(
    bodies: CuspBodies,
    hull: HullSurface,
    field: FlowField,
    start_m: np.ndarray,
    velocity_m_s: np.ndarray,
    *,
    time_step_s: float,
    max_time_s: float,
) -> FlowResult:
    """Follow every cusp from `start_m` (n, 3) with `velocity_m_s` (n, 3) until it ends (module docstring);
    cusps still running at `max_time_s` count as stalled."""
    if not time_step_s > 0.0:
        raise InputError("transport.time_step_s", "must be > 0", value=time_step_s, allowed="> 0 s")
    n = start_m.shape[0]
    outcome = np.full(n, RUNNING, dtype=np.int8)
    time = np.zeros(n)
    pos_out, vel_out = np.array(start_m, dtype=float), np.array(velocity_m_s, dtype=float)
    active = np.arange(n)
    pos, vel = pos_out.copy(), vel_out.copy()
    plane = field.discs.plane_m if field.discs is not None else hull.propeller_plane_m
    t, sub = 0.0, None
    while active.size and t < max_time_s:
        if sub is None:  # the running cusps' bodies, derived once per change of the running set
            sub = _subset(bodies, active)
            derived = (sub.masses_kg(), sub.drag_areas_m2(), sub.net_buoyancy_n())
            half = 0.5 * sub.extent_m
        pos, vel, contact, normal = _step(sub, derived, hull, field, pos, vel, time_step_s)
        t += time_step_s
        ended = np.full(active.size, RUNNING, dtype=np.int8)
        ended[_held(sub, field, pos, vel, contact, normal, *derived[1:])] = STALLED
        ended[pos[:, 2] <= 0.0] = SURFACED
        ended[np.abs(pos[:, 1]) >= 0.5 * hull.beam_m] = BILGE  # its centre beside the hull
        ended[pos[:, 0] + half >= plane] = REACHED  # decided at the plane (`disc_contact`)
        done = ended != RUNNING
        idx = active[done]
        outcome[idx], time[idx] = ended[done], t
        pos_out[idx], vel_out[idx] = pos[done], vel[done]
        if done.any():
            active, pos, vel, sub = active[~done], pos[~done], vel[~done], None
    outcome[active], time[active] = STALLED, t
    pos_out[active], vel_out[active] = pos, vel
    return FlowResult(outcome, time, pos_out, vel_out)


def _subset(bodies: CuspBodies, idx: np.ndarray) -> CuspBodies:
    return CuspBodies(*(getattr(bodies, f)[idx] for f in CuspBodies.__dataclass_fields__))
