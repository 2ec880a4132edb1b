"""The "flow" transport: which propeller each cusp reaches, found by following it under the hull.

Per cusp (docs/explanation/cusp-flow.md):
1. **Region**: as the kinematic transport (`transport.cusp_regions`); shoulder cusps rise beside the hull
   unless `shoulder_cusps_submerge`.
2. **Start**: the stem pushes the cusp down and aft along its buttock (stem angle φ_s) at the ship's speed
   (the ice at rest in the earth frame, times the slip factor): it reaches the hull's underside
   T / tan φ_s aft of where it was made, at its lateral position from breaking plus a seeded tumble: a
   yaw ψ ~ U(0, π/2) and a lateral shift ~ U(−a/2, a/2) (it turns about an edge of side a = √A while
   being pushed under), on the midship section there (flat bottom or bilge).
3. **Per-cusp parameters**, sampled with the `numpy.random.Generator`: C_D ~ U(`drag_coefficient_range`),
   μ ~ U(`friction_range`) (`FlowParameters`).
4. **Flow**: `cusp_flow.follow` in the hull's wake V (1 − w) with the discs' actuator-disc inflow at the
   computed thrust (u_a of the operating point).
5. **Contact** at the propeller plane: the cross-section [y − l/2, y + l/2] × [z_top, z_top + h] meets a
   disc when its nearest point to the axis lies within R; the nearest axis wins (ties: the lower index).
6. **Arrival time**: made at bow_x / V, down the stem in (descent length) / (s V), then the flow's time.
"""

from __future__ import annotations

import math

import numpy as np

from floebreak.errors import InputError
from floebreak.propeller import cusp_flow as cf
from floebreak.propeller.hull_surface import HullSurface
from floebreak.propeller.transport import (
    NO_PROPELLER,
    PATHS,
    CuspTransport,
    FlowParameters,
    HullUnderwater,
    PropellerArrangement,
    TransportParameters,
    _checked_columns,
    cusp_regions,
)

OUTCOME_PATH = {
    cf.REACHED: PATHS.index("propeller"),
    cf.BILGE: PATHS.index("bilge"),
    cf.SURFACED: PATHS.index("surfaced"),
    cf.MISSED: PATHS.index("missed"),
    cf.STALLED: PATHS.index("stalled"),
}


def hull_surface(
    hull: HullUnderwater, arrangement: PropellerArrangement, stem_angle_deg: float
) -> HullSurface:
    """The parametric surface of `hull`, its run rising to the hull above the shallowest disc."""
    above = min(p.shaft_depth_m - p.radius_m for p in arrangement.propellers) - arrangement.tip_clearance_m
    return HullSurface(
        hull.beam_m,
        hull.draught_m,
        hull.bilge_radius_m,
        stem_angle_deg,
        hull.propeller_plane_aft_of_stem_m,
        hull.run_length_m,
        above,
    )


def _sample(rng: np.random.Generator, area: np.ndarray, flow: FlowParameters):
    """Per cusp: yaw, lateral tumble shift, C_D, μ (module docstring, steps 2–3), in this fixed order."""
    n = area.size
    yaw = rng.uniform(0.0, 0.5 * math.pi, n)
    shift = rng.uniform(-0.5, 0.5, n) * np.sqrt(area)
    drag = rng.uniform(*flow.drag_coefficient_range, n)
    friction = rng.uniform(*flow.friction_range, n)
    return yaw, shift, drag, friction


def _discs(arrangement: PropellerArrangement, plane_m: float, induced_m_s: float) -> cf.Discs:
    props = arrangement.propellers
    return cf.Discs(
        plane_m,
        np.array([p.offset_y_m for p in props]),
        np.array([p.shaft_depth_m for p in props]),
        np.array([p.radius_m for p in props]),
        np.full(len(props), induced_m_s),
    )


def disc_contact(discs: cf.Discs, y, z_top, half_width, thickness):
    """Step 5: per cusp the reached disc (−1: none), entry radius fraction and angle [deg] and the
    cross-section relative to that disc's shaft centre (y_lo, y_hi, z_lo, z_hi; NaN without a disc)."""
    n = y.size
    best, index = np.full(n, np.inf), np.full(n, NO_PROPELLER, dtype=np.int64)
    radius, angle = np.full(n, np.nan), np.full(n, np.nan)
    section = tuple(np.full(n, np.nan) for _ in range(4))
    for k, (y_k, z_k, r_k) in enumerate(
        zip(discs.offset_y_m, discs.shaft_depth_m, discs.radius_m, strict=True)
    ):
        bounds = (y - half_width - y_k, y + half_width - y_k, z_top - z_k, z_top + thickness - z_k)
        dy, dz = np.clip(0.0, bounds[0], bounds[1]), np.clip(0.0, bounds[2], bounds[3])
        dist = np.hypot(dy, dz)
        wins = (dist < r_k) & (dist < best)
        best[wins], index[wins] = dist[wins], k
        radius[wins] = dist[wins] / r_k
        angle[wins] = np.degrees(np.arctan2(dy[wins], -dz[wins]))
        for out, value in zip(section, bounds, strict=True):
            out[wins] = value[wins]
    return index, radius, angle, section


def flow_transport_cusps(
    bow_x_m,
    centroid_x_m,
    centroid_y_m,
    area_m2,
    thickness_m,
    *,
    speed_m_s: float,
    induced_velocity_m_s: float,
    wake_fraction: float,
    rng: np.random.Generator,
    hull: HullUnderwater = HullUnderwater(),  # noqa: B008 - frozen dataclasses, immutable defaults
    arrangement: PropellerArrangement = PropellerArrangement(),  # noqa: B008
    params: TransportParameters = TransportParameters(),  # noqa: B008
    flow: FlowParameters = FlowParameters(),  # noqa: B008
) -> CuspTransport:
    """Which propeller each cusp reaches, when, and where it enters the disc (module docstring, steps 1–6).

    Inputs per cusp as `transport.transport_cusps`; `induced_velocity_m_s` is u_a of the operating point
    (`operating.controlled_point`), `wake_fraction` its w; `rng` draws the per-cusp tumble and parameters.
    """
    if not isinstance(rng, np.random.Generator):
        raise InputError("transport.rng", "the flow transport needs a numpy.random.Generator")
    if not speed_m_s > 0.0:
        raise InputError("ship.speed_m_s", "the flow transport needs a speed > 0", value=speed_m_s)
    cols = _checked_columns(
        dict(bow_x_m=bow_x_m, centroid_x_m=centroid_x_m, centroid_y_m=centroid_y_m, area_m2=area_m2)
        | {"thickness_m": thickness_m}
    )
    surface = hull_surface(hull, arrangement, flow.stem_angle_deg)
    region = cusp_regions(
        cols["bow_x_m"], cols["centroid_x_m"], hull.bow_length_m, params.shoulder_region_start
    )
    yaw, shift, drag, friction = _sample(rng, cols["area_m2"], flow)
    path = np.full(region.size, PATHS.index("missed"), dtype=np.int8)
    followed = np.ones(region.size, dtype=bool)
    if not params.shoulder_cusps_submerge:
        followed = region != "shoulder"
        path[~followed] = PATHS.index("shoulder")
    made_aft = cols["bow_x_m"] - cols["centroid_x_m"]
    x0 = surface.bottom_start_m(made_aft)
    y0 = cols["centroid_y_m"] + shift
    z0 = surface.section_depth_m(y0)
    z0 = np.where(np.isfinite(z0), z0, hull.draught_m - hull.bilge_radius_m)
    ice_speed = params.slip_factor * speed_m_s
    bodies = cf.CuspBodies(cols["area_m2"], cols["thickness_m"], yaw, drag, friction)
    discs = _discs(arrangement, hull.propeller_plane_aft_of_stem_m, induced_velocity_m_s)
    field = cf.FlowField(speed_m_s * (1.0 - wake_fraction), discs)
    idx = np.flatnonzero(followed)
    start = np.stack([x0, y0, z0], axis=-1)[idx]
    velocity = np.zeros_like(start)
    velocity[:, 0] = ice_speed
    max_time = 10.0 * hull.propeller_plane_aft_of_stem_m / max(field.wake_speed_m_s, 0.1)
    result = cf.follow(
        cf._subset(bodies, idx),
        surface,
        field,
        start,
        velocity,
        time_step_s=flow.time_step_s,
        max_time_s=max_time,
    )
    n = region.size
    index, radius, angle, section, outcome = _at_plane(n, idx, result, discs, bodies, cols["thickness_m"])
    path[idx] = [OUTCOME_PATH[int(o)] for o in outcome]
    descent_s = (x0 - np.maximum(made_aft, 0.0)) / ice_speed
    arrival = np.full(n, np.nan)
    arrival[idx] = cols["bow_x_m"][idx] / speed_m_s + descent_s[idx] + result.time_s
    arrival[index < 0] = np.nan
    return CuspTransport(index, arrival, radius, angle, region, path, len(arrangement.propellers), section)


def _at_plane(n, idx, result, discs, bodies, thickness):
    """Step 5 for the followed cusps `idx` that reached the plane: per cusp of `n` the disc, entry point and
    cross-section (`disc_contact`), and the followed cusps' outcomes with the plane's misses."""
    index, radius, angle = np.full(n, NO_PROPELLER, dtype=np.int64), np.full(n, np.nan), np.full(n, np.nan)
    section = tuple(np.full(n, np.nan) for _ in range(4))
    at_plane = result.outcome == cf.REACHED
    sub = idx[at_plane]
    y, z = result.position_m[at_plane, 1], result.position_m[at_plane, 2]
    k, r, a, s = disc_contact(discs, y, z, 0.5 * bodies.extent_m[sub], thickness[sub])
    index[sub], radius[sub], angle[sub] = k, r, a
    for out, value in zip(section, s, strict=True):
        out[sub] = value
    outcome = result.outcome.copy()
    outcome[at_plane] = np.where(k >= 0, cf.REACHED, cf.MISSED)
    return index, radius, angle, section, outcome


def flow_draws(columns, n_draws: int, rng: np.random.Generator, **kw) -> list[CuspTransport]:
    """`n_draws` independent draws of the flow transport of one cusp set (`columns`: the five per-cusp
    inputs of `flow_transport_cusps`; `kw`: its keywords but `rng`): the cusps repeated `n_draws` times in
    one call, so that each copy draws its own tumble, C_D and μ from `rng`, then split per draw."""
    cols = [np.asarray(c, dtype=float) for c in columns]
    n = cols[0].size
    moved = flow_transport_cusps(*(np.tile(c, n_draws) for c in cols), rng=rng, **kw)
    return [_draw(moved, slice(k * n, (k + 1) * n)) for k in range(n_draws)]


def _draw(moved: CuspTransport, rows: slice) -> CuspTransport:
    section = None if moved.cross_section_m is None else tuple(a[rows] for a in moved.cross_section_m)
    arrays = ("propeller_index", "arrival_time_s", "entry_radius_fraction", "entry_angle_deg", "region")
    return CuspTransport(
        *(getattr(moved, name)[rows] for name in arrays), moved.path[rows], moved.n_propellers, section
    )


def _run_inputs(columns, exposures, run, settings, spec, rated_torque_n_m, wake_fraction):
    """One run's rows, cusp inputs, operating point and the transport's keywords (but `rng`)."""
    from floebreak import constants as c
    from floebreak.propeller.operating import controlled_point
    from floebreak.ship.agulhas_ii import AGULHAS_II

    idx = np.flatnonzero(columns["run_id"] == run)
    basis = exposures[run].basis if run in exposures else None
    speed = basis.speed_m_s if basis else c.SHIP_SPEED_IN_ICE_M_S
    n_prop = basis.n_propellers if basis else AGULHAS_II.propeller_count
    point = controlled_point(spec, speed, rated_torque_n_m, wake_fraction)
    cols = [columns[k][idx] for k in ("bow_x_m", "centroid_x_m", "centroid_y_m", "area_m2", "thickness_m")]
    kw = {
        "speed_m_s": speed,
        "induced_velocity_m_s": point.point.induced_velocity_m_s,
        "wake_fraction": point.wake_fraction,
        "hull": settings.hull,
        "arrangement": settings.arrangement(n_prop, spec.radius_m),
        "params": settings.params,
        "flow": settings.flow,
    }
    return idx, cols, kw, point


def _check_inputs(columns, runs) -> None:
    needed = ("bow_x_m", "centroid_x_m", "centroid_y_m", "area_m2", "thickness_m")
    rows = np.isin(columns["run_id"], list(runs))
    missing = [k for k in needed if k not in columns or not np.all(np.isfinite(columns[k][rows]))]
    if missing:
        raise InputError(
            "cusps",
            f"the transport needs column(s) {', '.join(missing)} (cusps.parquet of a current run has them)",
            allowed="cusps with these columns, or transport 'all' / a fraction reaching",
        )


def flow_of_runs(
    columns, exposures, runs, settings, spec, rated_torque_n_m: float, *, wake_fraction=None, seed=0
):
    """The flow transport of the cusps of each of `runs` (as `load_models.transport_of_runs`), each run at
    its speed's controlled operating point (`operating.controlled_point`) with its own Generator seeded by
    (seed, the run's rank in sorted order): run → (indices into `columns`, CuspTransport), and run → the
    operating point's dict."""
    _check_inputs(columns, runs)
    out, points = {}, {}
    for rank, run in enumerate(sorted(runs)):
        idx, cols, kw, point = _run_inputs(
            columns, exposures, run, settings, spec, rated_torque_n_m, wake_fraction
        )
        transport = flow_transport_cusps(*cols, rng=np.random.default_rng([seed, rank]), **kw)
        out[run], points[run] = (idx, transport), point.as_dict()
    return out, points


def flow_draws_of_runs(
    columns,
    exposures,
    runs,
    settings,
    spec,
    rated_torque_n_m: float,
    n_draws: int,
    *,
    wake_fraction=None,
    seed=0,
):
    """`n_draws` further draws of each run's flow transport (`flow_draws`, seeded by (seed, the run's rank,
    1), apart from `flow_of_runs`' draw): run → [(indices into `columns`, CuspTransport)] per draw."""
    _check_inputs(columns, runs)
    out = {}
    for rank, run in enumerate(sorted(runs)):
        idx, cols, kw, _ = _run_inputs(
            columns, exposures, run, settings, spec, rated_torque_n_m, wake_fraction
        )
        draws = flow_draws(cols, n_draws, np.random.default_rng([seed, rank, 1]), **kw) if n_draws else []
        out[run] = [(idx, t) for t in draws]
    return out
