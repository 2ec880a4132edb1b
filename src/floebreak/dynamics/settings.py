"""Settings of the rigid-body ice motion (docs/model.md, "Ice motion (rigid-body dynamics)").

Every coefficient carries its unit, its allowed interval (`floebreak.errors.Bounds`, checked on construction)
and its source in its docstring. The scenario table that states them is ``[ice_motion]``; an
InputError names ``ice_motion.<field>``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Annotated, ClassVar, Literal

from floebreak import constants as c
from floebreak.errors import Bounds, InputError, check_bounds

_POSITIVE = Bounds(0.0, math.inf, low_inclusive=False, high_inclusive=False)


@dataclass(frozen=True)
class IceMotionSettings:
    """Coefficients of the ice bodies, their contacts, the water forces and the awake window (SI)."""

    PREFIX: ClassVar[str] = "ice_motion"

    ice_density_kg_m3: Annotated[float, Bounds(800.0, 1000.0, unit="kg/m³")] = c.ICE_DENSITY_KG_M3
    """ρ_i [kg/m³] (from [ice]; thesis §6.3: 917); mass of a piece ρ_i·A·h"""
    water_density_kg_m3: Annotated[float, Bounds(990.0, 1100.0, unit="kg/m³")] = c.SEAWATER_DENSITY_KG_M3
    """ρ_w [kg/m³] (physics-notes §0: 1025); also sets the draft T = h·ρ_i/ρ_w of the wetted edge"""
    form_drag_coefficient: Annotated[float, Bounds(0.0, 5.0, low_inclusive=False)] = 1.0
    """C_d [-] of the pressure drag ½ρ_w C_d T W |u|u on the submerged edge (W: width projected across u).
    1.0 as in AUTO-IceNav (de Schaetzen et al. 2024, after Zhang et al. 2019, J. Offshore Mech. Arct. Eng.
    141(3) 031501); Lubbad et al. (2018, Cold Reg. Sci. Technol. 156) use 0.5. In (0, 5]: a bluff plate
    broadside is about 2"""
    skin_drag_coefficient: Annotated[float, Bounds(0.0, 0.05, low_inclusive=False)] = 5.5e-3
    """C_s [-] of the skin drag ½ρ_w C_s A |u|u on the underside: the ice–ocean drag coefficient
    5.5e-3 (McPhee 1980; Hibler 1979). In (0, 0.05]: reported values span 1e-3 to 35e-3 (Steiner 2001,
    Ann. Glaciol. 33)"""
    added_mass_coefficient: Annotated[float, Bounds(0.0, 2.0)] = 0.1
    """C_a [-] in surge and sway: effective mass (1 + C_a)·m. A floe moving in its own plane displaces
    water only at its edge: 2-D potential flow gives an ellipse of half-length a along the motion and
    half-depth b the added mass ρπb² per unit width (Newman 1977, Marine Hydrodynamics §4.13); with the
    free-surface image (b = T) this is C_a ≈ πT/L, 0.06–0.3 for the reference floes (L = 5–50 m at
    h = 0.36–1 m). In [0, 2]"""
    added_inertia_coefficient: Annotated[float, Bounds(0.0, 2.0)] = 0.1
    """C_a,ψ [-] in yaw: effective moment of inertia (1 + C_a,ψ)·I; same edge-only argument and order as
    C_a. In [0, 2]"""
    ice_ice_friction: Annotated[float, Bounds(0.0, 2.0)] = 0.35
    """μ ice–ice [-] (Huang et al. 2020, Mar. Struct. 74; used by AUTO-IceNav). In [0, 2]"""
    ice_hull_friction: Annotated[float, Bounds(0.0, 2.0)] = c.FRICTION_COEFFICIENT
    """μ ice–hull [-] of the engine's own hull contact, so used only under ``hull_contact = "engine"``: under
    "crushing" (the default) the hull does not collide with the ice in the engine, and its push, along the
    panel normals, takes no friction (the contact model's μ, ``ice.friction_coefficient``, enters only the
    crushing force's F_h and F_v). Default: the contact model's value (thesis Alg. 3: 0.15). In [0, 2]"""
    ice_ice_restitution: Annotated[float, Bounds(0.0, 1.0)] = 0.1
    """e ice–ice [-] (Yulmetov et al. 2016, Cold Reg. Sci. Technol. 121; used by AUTO-IceNav). In [0, 1]"""
    ice_hull_restitution: Annotated[float, Bounds(0.0, 1.0)] = 0.1
    """e ice–hull [-] (as ice–ice, same source) of the engine's own hull contact, so used only under
    ``hull_contact = "engine"`` (under "crushing" the hull's push does not bounce). In [0, 1]"""
    # the window: the smallest of 40/20/20 × 1, 1.5, 3 m whose cusp statistics lie within 2 % of the
    # field's whole width awake (docs/model.md, "Awake window")
    window_ahead_m: Annotated[float, _POSITIVE] = 60.0
    """awake window: distance ahead of the hull's foremost point [m], > 0"""
    window_behind_m: Annotated[float, _POSITIVE] = 30.0
    """awake window: distance behind the hull's aftmost point [m], > 0; pieces entirely behind it are
    retired (removed from the engine), so memory does not grow with the transit"""
    window_side_m: Annotated[float, _POSITIVE] = 30.0
    """awake window: distance beyond either side of the hull [m], > 0"""
    time_step_s: Annotated[float, Bounds(0.0, 1.0, low_inclusive=False, unit="s")] = 0.02
    """engine time step Δt [s], in (0, 1]; must resolve the ship's speed (`check_time_step`)"""
    smallest_floe_size_m: Annotated[float, _POSITIVE] = 1.0
    """L_min [m]: the smallest piece size the time step must resolve (1 m: thesis Eq. 5, the smallest pieces
    are unbreakable and only rotate); > 0"""
    step_travel_fraction: Annotated[float, Bounds(0.0, 1.0, low_inclusive=False)] = 0.25
    """f [-]: the hull may advance at most f·L_min per step (0.25: the static engine's 0.25 m step for a
    1 m piece); in (0, 1]"""
    solver_iterations: Annotated[int, Bounds(1, 1000)] = 20
    """contact solver iterations per step (Chipmunk's default 10; AUTO-IceNav 50), in [1, 1000]"""
    rest_speed_m_s: Annotated[float, Bounds(0.0, 0.1, unit="m/s")] = 1e-3
    """a piece whose speed and edge speed from yaw (ω times its largest radius) are both below this, and
    not rising, is set at rest [m/s] (not while the hull holds it): under quadratic drag the speed decays
    as 1/t without end (the distance still to go grows as ln t), and a piece creeping at < 1 mm/s moves
    less than 0.1 mm in a 0.1 s search interval. In [0, 0.1]; 0 never stops a piece"""
    hull_contact: Literal["crushing", "engine"] = "crushing"
    """which force the hull puts on a piece: floebreak's crushing force alone ("crushing", applied by the
    stepping loop; the hull passes through pieces in the engine, the overlap being the crushed ice), or
    also the engine's non-penetration contact ("engine"), which holds a piece at the hull whatever its mass:
    it pushes aside floes that must break (docs/model.md, Ice motion, coupling)"""
    pin_all: bool = False
    """pin every piece (no motion): the check that the coupled loop then gives the static results"""
    failure_force: Literal["crushing", "lagged_transmitted"] = "crushing"
    """the force the failure criteria see on a piece in contact: floebreak's crushing force ("crushing"), or
    that force times the share of it the piece's hull contacts passed on over the interval before
    ("lagged_transmitted", at most 1; a piece not held then, new or pinned, sees the whole force): a floe
    cannot be loaded by more than it resists (docs/model.md, "The force the hull passes on")"""

    def __post_init__(self) -> None:
        check_bounds(self, self.PREFIX)
        if self.ice_ice_restitution == 0.0 and self.ice_hull_restitution > 0.0:
            # Chipmunk multiplies the two shapes' restitutions: e_ih = e_hull·√e_ii needs e_ii > 0
            raise InputError(
                f"{self.PREFIX}.ice_ice_restitution",
                "0 with ice_hull_restitution > 0: the engine forms a pair's restitution as a product of the "
                "shapes' values, so an ice–hull restitution needs an ice–ice restitution above 0",
                value=0.0,
                allowed="(0, 1] when ice_hull_restitution > 0",
            )

    @property
    def draft_ratio(self) -> float:
        """T/h = ρ_i/ρ_w (Archimedes): the submerged share of the thickness."""
        return self.ice_density_kg_m3 / self.water_density_kg_m3

    def check_time_step(self, speed_m_s: float, time_step_s: float | None = None) -> None:
        """InputError naming ``ice_motion.time_step_s`` if the hull moves more than f·L_min in one step."""
        dt = self.time_step_s if time_step_s is None else time_step_s
        limit = self.step_travel_fraction * self.smallest_floe_size_m
        if not (dt > 0.0 and abs(speed_m_s) * dt <= limit):
            raise InputError(
                f"{self.PREFIX}.time_step_s",
                f"{dt:g} s moves the hull {abs(speed_m_s) * dt:g} m per step at {abs(speed_m_s):g} m/s, more "
                f"than step_travel_fraction·smallest_floe_size_m = {limit:g} m",
                value=dt,
                allowed=f"(0, {limit / max(abs(speed_m_s), 1e-300):g}] s",
            )
