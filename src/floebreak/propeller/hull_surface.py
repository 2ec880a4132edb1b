"""The underwater hull as a parametric surface, for following cusps from the bow to the propellers (pure).

Ship frame: x aft of the stem tip at the ice waterline, y to port, z depth positive downwards from the still
waterline (docs/explanation/cusp-flow.md, "The hull"). The surface is the depth z_hull(x, y) of the hull's
underside above a point; the water is where z ≥ z_hull. From the main dimensions:

- **midship section** (beam B, draught T, bilge radius r_b): flat bottom at z = T for |y| ≤ f = B/2 − r_b,
  a circular bilge z = T − r_b + √(r_b² − d²) for d = |y| − f in (0, r_b), and no hull beneath beyond the
  beam (the vertical side: a cusp there is beside the hull, z_hull = −∞);
- **bow** (stem angle φ_s from the horizontal): a cusp pushed down the stem reaches the flat bottom
  T / tan φ_s aft of where it was made (`bottom_start_m`);
- **stern run**: over the run length L_run ahead of the propeller plane x_p the bottom rises at the buttock
  rise angle γ, tan γ = (T − z_h) / L_run, from T to the hull above the discs z_h = z_shaft − R − c_tip, and
  stays there to the plane: z_run(x) = max(z_h, T − (x − x_p + L_run) tan γ). The run is a ramp across the
  whole section: z_hull(x, y) = min(z_section(y), z_run(x)).

The normal into the water is n ∝ (−∂z_hull/∂x, −∂z_hull/∂y, 1) (the flat bottom's is (0, 0, 1)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from floebreak.errors import InputError


@dataclass(frozen=True)
class HullSurface:
    """The parametric underwater hull (module docstring); lengths in metres, angles in degrees."""

    beam_m: float
    draught_m: float
    bilge_radius_m: float
    stem_angle_deg: float
    propeller_plane_m: float
    run_length_m: float
    hull_above_discs_m: float

    def __post_init__(self) -> None:
        if not 0.0 < self.hull_above_discs_m < self.draught_m:
            raise InputError(
                "transport.hull.run_length_m",
                f"the hull above the discs ({self.hull_above_discs_m:g} m deep) must lie between the "
                f"waterline and the flat bottom ({self.draught_m:g} m)",
                value=self.hull_above_discs_m,
                allowed=f"(0, {self.draught_m:g}) m",
            )
        if self.run_length_m >= self.propeller_plane_m - self.bottom_start_m(0.0):
            raise InputError(
                "transport.hull.run_length_m",
                f"{self.run_length_m:g} m leaves no flat bottom between the bow and the stern run",
                value=self.run_length_m,
                allowed=f"< {self.propeller_plane_m - self.bottom_start_m(0.0):g} m",
            )

    @property
    def flat_half_width_m(self) -> float:
        return 0.5 * self.beam_m - self.bilge_radius_m

    @property
    def buttock_rise_deg(self) -> float:
        """γ, the stern run's buttock rise angle (module docstring)."""
        return math.degrees(math.atan2(self.draught_m - self.hull_above_discs_m, self.run_length_m))

    def bottom_start_m(self, made_aft_m) -> np.ndarray:
        """x where a cusp made `made_aft_m` aft of the stem reaches the flat bottom: x_made + T / tan φ_s."""
        descent = self.draught_m / math.tan(math.radians(self.stem_angle_deg))
        return np.maximum(np.asarray(made_aft_m, dtype=float), 0.0) + descent

    def section_depth_m(self, y_m) -> np.ndarray:
        """z_section(y): the midship section's underside (−inf beyond the beam)."""
        d = np.abs(np.asarray(y_m, dtype=float)) - self.flat_half_width_m
        r = self.bilge_radius_m
        with np.errstate(invalid="ignore"):
            bilge = self.draught_m - r + np.sqrt(np.maximum(r * r - d * d, 0.0))
        return np.where(d <= 0.0, self.draught_m, np.where(d < r, bilge, -np.inf))

    def run_depth_m(self, x_m) -> np.ndarray:
        """z_run(x): the stern run's ramp (T ahead of the run, z_h from its end to the plane and aft)."""
        x = np.asarray(x_m, dtype=float)
        slope = (self.draught_m - self.hull_above_discs_m) / self.run_length_m
        start = self.propeller_plane_m - self.run_length_m
        return np.clip(self.draught_m - (x - start) * slope, self.hull_above_discs_m, self.draught_m)

    def depth_m(self, x_m, y_m) -> np.ndarray:
        """z_hull(x, y) = min(z_section(y), z_run(x))."""
        return np.minimum(self.section_depth_m(y_m), self.run_depth_m(x_m))

    def normal(self, x_m, y_m) -> np.ndarray:
        """(n, 3) unit normals into the water at (x, y) (zero rows where there is no hull)."""
        x, y = np.asarray(x_m, dtype=float), np.asarray(y_m, dtype=float)
        section, run = self.section_depth_m(y), self.run_depth_m(x)
        start = self.propeller_plane_m - self.run_length_m
        slope = (self.draught_m - self.hull_above_discs_m) / self.run_length_m
        on_ramp = (run < section) & (x > start) & (run > self.hull_above_discs_m)
        dzdx = np.where(on_ramp, -slope, 0.0)
        d = np.abs(y) - self.flat_half_width_m
        r = self.bilge_radius_m
        on_bilge = (run >= section) & (d > 0.0) & (d < r)
        with np.errstate(divide="ignore", invalid="ignore"):
            bilge_slope = -np.sign(y) * d / np.sqrt(np.maximum(r * r - d * d, 1e-12 * r * r))
        dzdy = np.where(on_bilge, bilge_slope, 0.0)
        n = np.stack([-dzdx, -dzdy, np.ones_like(x)], axis=-1)
        n /= np.linalg.norm(n, axis=-1, keepdims=True)
        return np.where(np.isfinite(section)[..., None], n, 0.0)
