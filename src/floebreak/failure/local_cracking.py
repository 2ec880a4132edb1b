"""Local cracking (thesis §4.3, Alg. 6, Eq. 21, Fig. 12): a crack that starts orthogonal to the bow and
turns, through a Bezier curve, into the bending line towards the stern.

Criterion: the bending criterion F_v > P_f (thesis §4.3.1). Line (thesis §4.3.2, erratum 21):
- C_crack: 30 points from O − (ℓ/5) n̂ to O + 5ℓ n̂ (Alg. 6; `linspace`, not `arange`);
- n_Bezier0: the crack point closest to x_int, the frontmost intersection of the upper waterline with the
  floe; n_Bezier1: the crossing of the crack line with the bending arc, O + R n̂;
  n_Bezier2: the bending-arc points after n_Bezier1 towards the stern that lie within dist(n0, n1) of n1;
- C_bend: the rest of the arc towards the stern, continued until it meets the floe boundary (where the arc
  lies outside the floe the floe edge bounds the piece: "the floe edge line is used").
The separated piece is the part of the floe enclosed by this line on the stern side of the crack line.
Which floes get local cracking instead of bending is decided by the dispatch policy (`failure.dispatch`:
by default bending-class floes whose contact lies in the shoulder region).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import shapely

from floebreak.failure.base import (
    FailureContext,
    FailureInput,
    Fate,
    NewPiece,
    Outcome,
    failed,
    intact,
    pass_on,
    split_parts,
)
from floebreak.failure.bending import BendingSettings, bending_check, bending_gate
from floebreak.failure.registry import register_mode

CRACK_POINTS = 30  # thesis Alg. 6 (intended linspace with 30 points)
BEZIER_POINTS = 30


@functools.lru_cache(maxsize=64)
def _bernstein_basis(degree: int, n_points: int) -> np.ndarray:
    """B_(i,degree)(t) = C(degree, i) tⁱ (1 − t)^(degree − i) at n_points t in [0, 1] (rows), read-only."""
    t = np.linspace(0.0, 1.0, n_points)
    # integer powers by repeated products: `**` may round differently with the CPU's vector width
    rising = np.cumprod(np.vstack([np.ones(n_points), np.tile(t, (degree, 1))]), axis=0)
    falling = np.cumprod(np.vstack([np.ones(n_points), np.tile(1.0 - t, (degree, 1))]), axis=0)[::-1]
    binomial = np.array([math.comb(degree, i) for i in range(degree + 1)], dtype=float)
    basis = (binomial[:, None] * rising * falling).T.copy()
    basis.setflags(write=False)
    return basis


def bezier_curve(nodes: np.ndarray, n_points: int = BEZIER_POINTS) -> np.ndarray:
    """Points of the Bezier curve with control points `nodes` (Bernstein form), from first to last node."""
    nodes = np.asarray(nodes, dtype=float)
    basis = _bernstein_basis(len(nodes) - 1, n_points)
    points = np.zeros((n_points, nodes.shape[1]))
    for i, node in enumerate(nodes):  # Σ_i B_i · node_i in a fixed order, not `@` (BLAS kernels vary per CPU)
        points += basis[:, i, None] * node[None, :]
    return points


@dataclass(frozen=True)
class LocalCrackLine:
    """The three parts of the local cracking line (bow frame) and the closed cutter region."""

    crack_part: np.ndarray
    bezier_part: np.ndarray
    bend_part: np.ndarray
    cutter: shapely.Polygon

    @property
    def line(self) -> np.ndarray:
        return np.concatenate([self.crack_part, self.bezier_part[1:], self.bend_part])


def stern_tangent(normal_xy: np.ndarray) -> np.ndarray:
    """The unit tangent of the bow at a panel with outward normal n̂ that points towards the stern (−x)."""
    t = np.array([-normal_xy[1], normal_xy[0]])
    if t[0] > 0 or (t[0] == 0 and t[1] < 0):
        t = -t
    return t


def local_crack_line(
    origin_xy_m: np.ndarray,
    normal_xy: np.ndarray,
    frontmost_contact_xy_m: np.ndarray,
    breaking_radius_m: float,
    characteristic_length_m: float,
    wedge_angle_rad: float,
) -> LocalCrackLine:
    """Construct the local cracking line and its cutter polygon (thesis Eq. 21, Fig. 12)."""
    u = np.asarray(normal_xy, dtype=float) / np.hypot(*normal_xy)
    t = stern_tangent(u)
    radius = breaking_radius_m
    ell = characteristic_length_m
    crack = origin_xy_m + np.linspace(-ell / 5.0, 5.0 * ell, CRACK_POINTS)[:, None] * u
    i_last = int(np.argmin(np.hypot(*(crack - frontmost_contact_xy_m).T)))
    n0 = crack[i_last]
    n1 = origin_xy_m + radius * u
    # bending arc from the crack line (angle 0) towards the stern (angle π) in steps of the wedge angle
    arc_angles = np.arange(wedge_angle_rad, np.pi + 1e-12, wedge_angle_rad)
    arc = origin_xy_m + radius * (np.cos(arc_angles)[:, None] * u + np.sin(arc_angles)[:, None] * t)
    dist_m = float(np.hypot(*(n0 - n1)))
    within = np.hypot(*(arc - n1).T) <= dist_m
    n_used = int(np.argmin(within)) if not within.all() else len(arc)  # first arc point beyond dist_m
    n2 = arc[:n_used]
    nodes = np.vstack([n0, n1, n2]) if n_used else np.vstack([n0, n1, arc[0]])
    bezier = bezier_curve(nodes)
    bend = arc[n_used:] if n_used else arc[1:]
    crack_part = crack[: i_last + 1]
    ring = np.vstack([crack_part, bezier[1:], bend, crack_part[:1]])
    cutter = shapely.make_valid(shapely.polygons(ring))
    return LocalCrackLine(crack_part, bezier, bend, cutter)


def frontmost_contact_point(floe, waterline, zone=None) -> np.ndarray | None:
    """x_int of Eq. 21: the frontmost intersection point of the upper waterline with the floe outline; given
    the `zone` (`ContactZone.overlap_upper`) of a floe in contact at several places, only the points on that
    zone count: a floe touching both shoulders must not start one shoulder's crack from a point on the other
    side of the hull (that made a symmetric floe crack at one shoulder only, the first in zone order)."""
    points = shapely.get_coordinates(shapely.intersection(waterline, shapely.boundary(floe)))
    if zone is not None and len(points):
        points = points[shapely.dwithin(shapely.points(points), zone, ON_ZONE_M)]
    if len(points) == 0:
        return None
    return points[int(np.argmax(points[:, 0]))]


ON_ZONE_M = 1e-6  # an intersection point lies on its zone's boundary up to rounding


@dataclass(frozen=True)
class LocalCracking:
    name: ClassVar[str] = "local_cracking"
    settings: BendingSettings = BendingSettings()

    def evaluate(self, inp: FailureInput, ctx: FailureContext) -> Outcome:
        check = bending_check(inp, ctx, self.settings)
        if (held := bending_gate(self.name, check)) is not None:
            return held
        zone = inp.zone
        several = len(inp.contact.zones) > 1
        x_int = frontmost_contact_point(
            inp.polygon, ctx.bow_geometry.waterline, zone.overlap_upper if several else None
        )
        if x_int is None:
            x_int = zone.centre_xy_m
        line = local_crack_line(
            zone.centre_xy_m,
            zone.centre_normal,
            x_int,
            check.breaking_radius_m,
            check.characteristic_length_m,
            check.fan.wedge_angle_rad,
        )
        near, far = split_parts(
            shapely.intersection(inp.polygon, line.cutter),
            shapely.difference(inp.polygon, line.cutter),
            thickness_m=inp.thickness_m,
        )
        if not near:  # the local cracking line misses the floe
            return intact(self.name, check.margin)
        if not far:  # no line crosses the floe: no local cracking here (the policy's next mode is tried)
            return pass_on(self.name, check.margin)
        pieces = (NewPiece(p, Fate.FLOE, inp.crack_count + 1) for p in [*near, *far])
        return failed(self.name, pieces, check.margin)


# no settings of its own: it shares bending's ([failure.bending], and bending's thesis values)
register_mode(LocalCracking, create=lambda settings: LocalCracking(settings["bending"]))
