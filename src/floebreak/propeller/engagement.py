"""Blade engagement: the radial interval of a blade that cuts a cusp's cross-section (pure, numpy).

The transport (`floebreak.propeller.transport`) gives each reaching cusp's cross-section in the disc plane
as an axis-aligned rectangle [y_lo, y_hi] × [z_lo, z_hi] relative to its propeller's shaft centre
(`CuspTransport.cross_section_m`). A blade is the radial segment {t u(θ) : r_hub ≤ t ≤ R} at shaft angle
θ (u the unit vector along the blade). The part of the blade that cuts the cusp at θ is the segment's
intersection with the rectangle, an interval [t_in(θ), t_out(θ)] of radii (a convex set met by a ray).
The **engaged interval** [r_in, r_out] is that interval at the θ where it is longest: the radial extent
the milling model loads (`milling.IceBlock.inner_radius_m` / `outer_radius_m`; docs/propeller.md §2,
"Blade milling model", and §10 choice 5).

Exact maximum over θ. With the slab form of the ray–rectangle intersection,
t_in = max(r_hub, entry through the y-edges, entry through the z-edges) and
t_out = min(R, exit through the y-edges, exit through the z-edges), where the distance along the ray to an
edge line at signed offset d with normal n is d / (u·n). The length L(θ) = t_out − t_in is piecewise smooth;
its pieces change where the line that binds t_in or t_out changes: where the ray passes a corner, where an
edge line's distance crosses R or r_hub (the tip or hub circle meets an edge line), or where the ray turns
parallel to an edge (an axis-aligned direction). On one piece L is one of
- R − r_hub: constant, attained at the piece's ends;
- t_exit − r_hub: d/cos(θ − θ_n) is convex in θ, so its maximum lies at the piece's ends;
- R − t_entry: largest where the distance to the entry line is least, i.e. along that line's normal, an
  axis-aligned direction (or at the ends);
- t_exit − t_entry: through opposite edges (d₂ − d₁)/cos(θ − θ_n), convex (ends); through adjacent
  (perpendicular) edges a/sin θ − b/cos θ-type terms whose derivative keeps one sign on the piece (both
  terms move the same way while the ray sweeps the corner region), so again the ends.
Hence the maximum is attained among the directions through the 4 corners, the 4 axis directions and the
points where the hub and tip circles meet the 4 edge lines (≤ 2 each: ≤ 16): at most 24 candidates per
rectangle, evaluated exactly. Ties (lengths within `TIE_TOLERANCE` × R of the longest) go to the larger
outer radius, then the larger inner radius, so mirrored rectangles (y → −y) give the same interval. A
rectangle that does not meet the annulus r_hub ≤ r ≤ R gives NaN; one that only touches it gives a
zero-length interval. tests/propeller/test_engagement.py checks the candidates against a brute-force sweep
over θ.
"""

from __future__ import annotations

import numpy as np

from floebreak.errors import InputError

TIE_TOLERANCE = 1e-12  # relative to R: lengths this close to the longest count as equal


def _candidate_directions(y_lo, y_hi, z_lo, z_hi, hub_m, tip_m) -> np.ndarray:
    """Unit directions (n, 24, 2) of the candidates (module docstring); NaN where a circle misses a line."""
    n = y_lo.shape[0]
    corners = [(y, z) for y in (y_lo, y_hi) for z in (z_lo, z_hi)]
    axes = [(np.full(n, a), np.full(n, b)) for a, b in ((1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0))]
    circles = []
    for rho in (hub_m, tip_m):
        for c in (y_lo, y_hi):
            with np.errstate(invalid="ignore"):
                s = np.sqrt(rho**2 - c**2)
            circles += [(c, s), (c, -s)]
        for c in (z_lo, z_hi):
            with np.errstate(invalid="ignore"):
                s = np.sqrt(rho**2 - c**2)
            circles += [(s, c), (-s, c)]
    points = np.stack([np.stack(p, axis=-1) for p in corners + axes + circles], axis=1)
    norm = np.hypot(points[..., 0], points[..., 1])
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where((norm > 0.0)[..., None], points / norm[..., None], np.nan)


def _slab(lo, hi, u):
    """Ray parameters (enter, exit) of the slab lo ≤ x ≤ hi along direction component u (any sign)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        a, b = lo / u, hi / u
    inside = (lo <= 0.0) & (0.0 <= hi)
    enter = np.where(u > 0.0, a, np.where(u < 0.0, b, np.where(inside, -np.inf, np.inf)))
    leave = np.where(u > 0.0, b, np.where(u < 0.0, a, np.where(inside, np.inf, -np.inf)))
    return enter, leave


def blade_segment_in_rectangle(y_lo, y_hi, z_lo, z_hi, direction, hub_m, tip_m):
    """(t_in, t_out) of the blade {t u : hub ≤ t ≤ tip} along unit `direction` (…, 2) inside the
    rectangle; t_out < t_in where it misses. Arrays broadcast."""
    y_in, y_out = _slab(y_lo, y_hi, direction[..., 0])
    z_in, z_out = _slab(z_lo, z_hi, direction[..., 1])
    return np.maximum(np.maximum(y_in, z_in), hub_m), np.minimum(np.minimum(y_out, z_out), tip_m)


def engaged_interval(y_lo, y_hi, z_lo, z_hi, hub_radius_m, tip_radius_m) -> tuple[np.ndarray, np.ndarray]:
    """The engaged interval (r_in, r_out) [m] of each rectangle [y_lo, y_hi] × [z_lo, z_hi] (metres,
    relative to the shaft centre; arrays of one length) on a blade from `hub_radius_m` to `tip_radius_m`:
    the longest radial blade segment inside it over all shaft angles (module docstring). NaN where a
    rectangle is NaN or does not meet the annulus."""
    hub = float(hub_radius_m)
    tip = float(tip_radius_m)
    if not (np.isfinite(tip) and tip > 0.0):
        raise InputError("engagement.tip_radius_m", f"{tip!r} is not > 0", value=tip, allowed="> 0 m")
    if not (np.isfinite(hub) and 0.0 <= hub < tip):
        raise InputError(
            "engagement.hub_radius_m",
            f"{hub!r} is outside [0, {tip:g})",
            value=hub,
            allowed=f"[0, {tip:g}) m",
        )
    y_lo, y_hi, z_lo, z_hi = (np.atleast_1d(np.asarray(a, dtype=float)) for a in (y_lo, y_hi, z_lo, z_hi))
    y_lo, y_hi, z_lo, z_hi = np.broadcast_arrays(y_lo, y_hi, z_lo, z_hi)
    valid = np.isfinite(y_lo) & np.isfinite(y_hi) & np.isfinite(z_lo) & np.isfinite(z_hi)
    bad = np.flatnonzero(valid & ((y_hi < y_lo) | (z_hi < z_lo)))
    if bad.size:
        raise InputError(
            "engagement.rectangle", f"row {bad[0]}: upper bound below lower bound", allowed="lo <= hi"
        )
    directions = _candidate_directions(y_lo, y_hi, z_lo, z_hi, hub, tip)
    cols = (a[:, None] for a in (y_lo, y_hi, z_lo, z_hi))
    t_in, t_out = blade_segment_in_rectangle(*cols, directions, hub, tip)
    length = np.where(np.isfinite(directions[..., 0]) & (t_out >= t_in), t_out - t_in, -np.inf)
    longest = length.max(axis=1)
    tied = length >= (longest - TIE_TOLERANCE * tip)[:, None]
    best = _best(np.where(tied, t_out, -np.inf), np.where(tied, t_in, -np.inf))
    rows = np.arange(y_lo.shape[0])
    found = valid & np.isfinite(longest)
    r_in = np.where(found, t_in[rows, best], np.nan)
    r_out = np.where(found, t_out[rows, best], np.nan)
    return r_in, r_out


def _best(key_out: np.ndarray, key_in: np.ndarray) -> np.ndarray:
    """Per row, the column with the largest key_out, ties broken by the largest key_in."""
    top = key_out.max(axis=1, keepdims=True)
    return np.argmax(np.where(key_out == top, key_in, -np.inf), axis=1)
